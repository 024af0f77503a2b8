// Synthetic ground-truth leaves: the outline formulas against hand-computed points, exact
// areas against closed forms and an independent integration, markers by the protocol.
#include "leafdig/model/synth/synthetic_leaf.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <numbers>

#include "leafdig/model/errors.hpp"
#include "leafdig/model/leaf/leaf_model.hpp"
#include "leafdig/model/metrics/metrics.hpp"
#include "leafdig/names/name_table.hpp"

namespace leafdig::model {
namespace {

constexpr double kPi = std::numbers::pi;

// A plain shape: no tip/base deformation, no bend.
SyntheticLeafSpec plain(LeafShape shape, double length, double width) {
  SyntheticLeafSpec s;
  s.outline.shape = shape;
  s.outline.lengthMm = length;
  s.outline.widthMm = width;
  s.bend = {0.0, 0.0, 0.0, 0.0, 80.0};
  return s;
}

double shoelace(const std::vector<Eigen::Vector2d>& p) {
  double a = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const auto& u = p[i];
    const auto& v = p[(i + 1) % p.size()];
    a += u.x() * v.y() - v.x() * u.y();
  }
  return 0.5 * a;
}

double meshSurface(const Mesh& m) {
  double a = 0.0;
  for (const auto& t : m.triangles)
    a += 0.5 * (m.positions[t[1]] - m.positions[t[0]]).cross(m.positions[t[2]] - m.positions[t[0]]).norm();
  return a;
}

TEST(SyntheticOutline, ShapesMatchHandComputedPoints) {
  // Elliptic: x = W/2 sin φ, y = L/2 (1 - cos φ).
  const SyntheticLeaf ellipse(plain(LeafShape::Elliptic, 300, 200));
  EXPECT_NEAR(ellipse.outlinePoint(+1, kPi / 2).x(), 100.0, 1e-12);
  EXPECT_NEAR(ellipse.outlinePoint(+1, kPi / 2).y(), 150.0, 1e-12);
  EXPECT_NEAR(ellipse.outlinePoint(+1, kPi / 3).x(), 100.0 * std::sqrt(3.0) / 2, 1e-12);
  EXPECT_NEAR(ellipse.outlinePoint(+1, kPi / 3).y(), 75.0, 1e-12);
  EXPECT_NEAR(ellipse.outlinePoint(-1, kPi / 3).x(), -100.0 * std::sqrt(3.0) / 2, 1e-12);
  // Oblong: p = (sin φ + sin 3φ / 9) 9/8: full width at the middle, 1.5x the ellipse's
  // slope at the base; default width L/3.
  const SyntheticLeaf oblong(plain(LeafShape::Oblong, 300, 100));
  EXPECT_NEAR(oblong.outlinePoint(+1, kPi / 2).x(), 50.0, 1e-12);
  EXPECT_NEAR(oblong.outlinePoint(+1, kPi / 6).x(), 50.0 * (0.5 + 1.0 / 9.0) * 9.0 / 8.0, 1e-12);
  SyntheticLeafSpec defaults = plain(LeafShape::Oblong, 300, 0);
  defaults.outline.widthMm.reset();
  EXPECT_NEAR(SyntheticLeaf(defaults).widthMm(), 100.0, 1e-12);
  // Ovate S = 0.25: the widest point (φ = π/2) at 0.375 L; obovate at 0.625 L.
  EXPECT_NEAR(SyntheticLeaf(plain(LeafShape::Ovate, 400, 200)).outlinePoint(+1, kPi / 2).y(), 150.0, 1e-12);
  EXPECT_NEAR(SyntheticLeaf(plain(LeafShape::Obovate, 400, 200)).outlinePoint(+1, kPi / 2).y(), 250.0, 1e-12);
  // Tobacco: S = 0.1, tip narrowing 0.6 over 0.25 L, base narrowing 0.5 over 0.2 L.
  SyntheticLeafSpec t = defaultSyntheticSpec(LeafShape::Tobacco);
  t.outline.lengthMm = 500;
  const SyntheticLeaf tobacco(t);
  const double phi = kPi / 4, L = 500, W = 250;
  const double y = 0.5 * L * (1 - std::cos(phi)) - 0.1 * 0.5 * L * std::sin(phi) * std::sin(phi);
  const double tipD = (L - y) / (0.25 * L), baseD = y / (0.2 * L);
  const double x = 0.5 * W * std::sin(phi) * (1 - 0.6 * std::exp(-tipD * tipD)) * (1 - 0.5 * std::exp(-baseD * baseD));
  EXPECT_NEAR(tobacco.outlinePoint(+1, phi).x(), x, 1e-9);
  EXPECT_NEAR(tobacco.outlinePoint(+1, phi).y(), y, 1e-9);
  // A sine-sum width term: 1 + 0.1 sin(2φ) at φ = π/4 widens by 10 %.
  SyntheticLeafSpec wavy = plain(LeafShape::Elliptic, 300, 200);
  wavy.outline.widthTerms = {{0.1, 2.0, 0.0}};
  EXPECT_NEAR(SyntheticLeaf(wavy).outlinePoint(+1, kPi / 4).x(), 100.0 * std::sin(kPi / 4) * 1.1, 1e-12);
  // Asymmetry narrows the left half only.
  wavy.outline.widthTerms.clear();
  wavy.outline.asymmetry = 0.1;
  EXPECT_NEAR(SyntheticLeaf(wavy).outlinePoint(-1, kPi / 2).x(), -90.0, 1e-12);
  EXPECT_NEAR(SyntheticLeaf(wavy).outlinePoint(+1, kPi / 2).x(), 100.0, 1e-12);
}

TEST(SyntheticOutline, SerrationsMatchTheirFormulas) {
  // n = 10 teeth per side: θ = 10 φ. At a crest (θ = π/2) and between (θ = π/4), against
  // round |sin θ|, sharp 1 - |cos θ|, straight |sin θ| + 1 - |cos θ|, acuminate
  // |sin θ| + (1 - |cos θ|)^2, in units of D = 4 mm, pushed out horizontally.
  const double r = std::sqrt(0.5);
  const struct {
    Serration kind;
    double crest, quarter;
  } cases[] = {{Serration::Round, 1.0, r},
               {Serration::Sharp, 1.0, 1.0 - r},
               {Serration::Straight, 2.0, 1.0},
               {Serration::Acuminate, 2.0, r + (1.0 - r) * (1.0 - r)}};
  for (const auto& c : cases) {
    SyntheticLeafSpec s = plain(LeafShape::Elliptic, 300, 200);
    s.outline.serration = c.kind;
    s.outline.toothDepthMm = 4.0;
    s.outline.teethPerSide = 10;
    const SyntheticLeaf leaf(s);
    for (double theta : {kPi / 2, kPi / 4, 0.0, kPi}) {
      const double phi = (theta + 4 * kPi) / 10;  // the fifth tooth
      const double want = theta == kPi / 2 ? c.crest : theta == kPi / 4 ? c.quarter : 0.0;
      EXPECT_NEAR(leaf.outlinePoint(+1, phi).x(), 100.0 * std::sin(phi) + 4.0 * want, 1e-9) << toString(c.kind);
      EXPECT_NEAR(leaf.outlinePoint(-1, phi).x(), -100.0 * std::sin(phi) - 4.0 * want, 1e-9) << toString(c.kind);
      EXPECT_NEAR(leaf.outlinePoint(+1, phi).y(), 150.0 * (1 - std::cos(phi)), 1e-9);
    }
    // Normal direction: the tooth leaves the margin at right angles (outward).
    s.outline.toothDirection = ToothDirection::Normal;
    const SyntheticLeaf normal(s);
    const double phi = (kPi / 2 + 2 * kPi) / 10;
    const Eigen::Vector2d base(100.0 * std::sin(phi), 150.0 * (1 - std::cos(phi)));
    const Eigen::Vector2d tangent(100.0 * std::cos(phi), 150.0 * std::sin(phi));
    const Eigen::Vector2d offset = normal.outlinePoint(+1, phi) - base;
    EXPECT_NEAR(offset.norm(), 4.0 * c.crest, 1e-6);
    EXPECT_NEAR(offset.dot(tangent), 0.0, 1e-6);
    EXPECT_GT(offset.x(), 0.0);
  }
}

TEST(SyntheticArea, FlatEllipseIsPiAB) {
  const SyntheticLeaf leaf(plain(LeafShape::Elliptic, 300, 200));
  EXPECT_NEAR(leaf.flatArea() / (kPi * 100 * 150), 1.0, 1e-10);
  double estimate = 1.0;
  EXPECT_NEAR(leaf.area(&estimate) / (kPi * 100 * 150), 1.0, 1e-10);
  EXPECT_LT(estimate, 1e-9);
}

TEST(SyntheticArea, DroopAloneKeepsTheArea) {
  // Bending along the midrib into a cylinder is an isometry.
  SyntheticLeafSpec s = plain(LeafShape::Ovate, 400, 200);
  s.bend.droopDeg = 120;
  const SyntheticLeaf leaf(s);
  EXPECT_NEAR(leaf.area() / leaf.flatArea(), 1.0, 1e-10);
  // ... but moves the tip: a 120° arc of length 400 ends 400 sin(120°)/(2π/3) forward.
  const Eigen::Vector3d tip = leaf.surfacePoint({0.0, 400.0});
  const double k = (2 * kPi / 3) / 400;
  EXPECT_NEAR(tip.y(), std::sin(2 * kPi / 3) / k, 1e-9);
  EXPECT_NEAR(tip.z(), (std::cos(2 * kPi / 3) - 1) / k, 1e-9);
}

TEST(SyntheticArea, SerratedFlatAreaMatchesADensePolygon) {
  for (Serration kind : {Serration::Round, Serration::Sharp, Serration::Straight, Serration::Acuminate}) {
    SyntheticLeafSpec s = defaultSyntheticSpec(LeafShape::Tobacco);
    s.outline.serration = kind;
    s.outline.toothDepthMm = 6.0;
    s.outline.teethPerSide = 23;
    s.outline.toothDirection = ToothDirection::Normal;
    const SyntheticLeaf leaf(s);
    // The polygon through 400 000 outline points converges as h²: two resolutions and
    // Richardson's extrapolation give an independent value.
    const double a1 = shoelace(leaf.outline(100'000));
    const double a2 = shoelace(leaf.outline(200'000));
    const double extrapolated = (4 * a2 - a1) / 3;
    EXPECT_NEAR(leaf.flatArea() / extrapolated, 1.0, 1e-8) << toString(kind);
  }
}

TEST(SyntheticArea, BentAreaMatchesAnIndependentIntegration) {
  // Droop, cup, twist and a wavy margin: the exact Green integral against the fine truth
  // mesh's triangle sum extrapolated from two resolutions.
  SyntheticLeafSpec s = defaultSyntheticSpec(LeafShape::Tobacco);
  s.bend = {35.0, 25.0, 15.0, 4.0, 60.0};
  const SyntheticLeaf leaf(s);
  double estimate = 1.0;
  const double exact = leaf.area(&estimate);
  EXPECT_LT(estimate, 1e-6);
  const double a1 = meshSurface(leaf.truthMesh(400, 40).organs[0].mesh);
  const double a2 = meshSurface(leaf.truthMesh(800, 80).organs[0].mesh);
  const double extrapolated = (4 * a2 - a1) / 3;
  EXPECT_NEAR(exact / extrapolated, 1.0, 2e-5);
  EXPECT_GT(exact / leaf.flatArea(), 1.005);  // cupping and waves stretch the outline
}

TEST(SyntheticSurface, NormalsAreTheMapsDerivatives) {
  SyntheticLeafSpec s = defaultSyntheticSpec(LeafShape::Tobacco);
  s.bend = {35.0, 25.0, 15.0, 4.0, 60.0};
  const SyntheticLeaf leaf(s);
  const LeafMesh mesh = leaf.truthMesh(40, 6);
  const Mesh& m = mesh.organs[0].mesh;
  for (const auto& t : m.triangles) {
    const Eigen::Vector3d face =
        (m.positions[t[1]] - m.positions[t[0]]).cross(m.positions[t[2]] - m.positions[t[0]]).normalized();
    EXPECT_GT(face.dot(m.normals[t[0]]), 0.5);
  }
  // Finite differences of the map against the normal at a few flat points.
  for (const Eigen::Vector2d& p : {Eigen::Vector2d(30, 100), Eigen::Vector2d(-80, 260), Eigen::Vector2d(10, 450)}) {
    const double h = 1e-4;
    const Eigen::Vector3d dx =
        (leaf.surfacePoint(p + Eigen::Vector2d(h, 0)) - leaf.surfacePoint(p - Eigen::Vector2d(h, 0))) / (2 * h);
    const Eigen::Vector3d dy =
        (leaf.surfacePoint(p + Eigen::Vector2d(0, h)) - leaf.surfacePoint(p - Eigen::Vector2d(0, h))) / (2 * h);
    EXPECT_GT(dx.cross(dy).z(), 0.0);  // adaxial side up
  }
}

TEST(SyntheticMarkers, FollowTheProtocol) {
  SyntheticLeafSpec s = defaultSyntheticSpec(LeafShape::Tobacco);
  s.rows = 9;
  const SyntheticLeaf leaf(s);
  const MarkerSet exact = leaf.markers(0.0, 1);
  ASSERT_EQ(exact.rows.size(), 9u);
  // The last row at the leaf base: its midrib marker is the origin of the leaf frame.
  EXPECT_LT(exact.rows.back().pointsMm[kMidribColumn].norm(), 0.006);
  EXPECT_LT((exact.tipMm - leaf.surfacePoint({0.0, 500.0})).norm(), 0.006);
  // Rows from tip to base: midrib markers get closer to the base row by row.
  for (std::size_t i = 1; i < exact.rows.size(); ++i)
    EXPECT_LT(exact.rows[i].pointsMm[kMidribColumn].norm(), exact.rows[i - 1].pointsMm[kMidribColumn].norm());
  // Right half on +x, left on -x; veins end on the margin.
  const std::vector<Eigen::Vector2d> outline = leaf.outline(20'000);
  for (const TruthVein& v : leaf.veins()) {
    EXPECT_EQ(v.flatStart.x(), 0.0);
    EXPECT_EQ(v.flatEnd.x() > 0, v.side > 0);
    double nearest = 1e9;
    for (const auto& p : outline) nearest = std::min(nearest, (p - v.flatEnd).norm());
    EXPECT_LT(nearest, 0.05) << "row " << v.row;
    const auto& row = exact.rows[static_cast<std::size_t>(v.row - 1)];
    const Eigen::Vector3d margin = row.pointsMm[v.side > 0 ? 0 : 6];
    EXPECT_LT((margin - v.points.back()).norm(), 0.009);  // rounded to 0.01 mm
  }
  EXPECT_NEAR(*exact.leaf.measuredAreaMm2, leaf.area(), 0.5);
  // The leaf builds into a model whose blade area is close to the truth.
  const LeafModel model = buildLeafModel(exact);
  const double modelArea = convergedBladeArea(model.blade, Eigen::Vector3d::UnitZ()).areaMm2;
  EXPECT_NEAR(modelArea / leaf.area(), 1.0, 0.03);
}

TEST(SyntheticMarkers, NoiseIsGaussianAndSeeded) {
  const SyntheticLeaf leaf(defaultSyntheticSpec(LeafShape::Elliptic));
  const MarkerSet exact = leaf.markers(0.0, 5);
  const MarkerSet a = leaf.markers(0.5, 5);
  const MarkerSet b = leaf.markers(0.5, 5);
  const MarkerSet c = leaf.markers(0.5, 6);
  double sum = 0.0, sumSq = 0.0;
  int n = 0;
  bool differs = false;
  for (std::size_t i = 0; i < exact.rows.size(); ++i)
    for (int j = 0; j < kMarkersPerRow; ++j) {
      EXPECT_EQ(a.rows[i].pointsMm[j], b.rows[i].pointsMm[j]);
      differs |= a.rows[i].pointsMm[j] != c.rows[i].pointsMm[j];
      const Eigen::Vector3d d = a.rows[i].pointsMm[j] - exact.rows[i].pointsMm[j];
      for (int k = 0; k < 3; ++k) {
        sum += d[k];
        sumSq += d[k] * d[k];
        ++n;
      }
    }
  EXPECT_TRUE(differs);
  EXPECT_NEAR(sum / n, 0.0, 0.15);
  EXPECT_NEAR(std::sqrt(sumSq / n), 0.5, 0.1);
}

TEST(SyntheticMarkers, EveryShapeAndSerrationMakesAValidLeaf) {
  for (LeafShape shape :
       {LeafShape::Oblong, LeafShape::Elliptic, LeafShape::Ovate, LeafShape::Obovate, LeafShape::Tobacco})
    for (Serration kind :
         {Serration::None, Serration::Round, Serration::Sharp, Serration::Straight, Serration::Acuminate}) {
      SyntheticLeafSpec s = defaultSyntheticSpec(shape);
      s.outline.serration = kind;
      s.outline.toothDepthMm = kind == Serration::None ? 0.0 : 3.0;
      s.outline.teethPerSide = kind == Serration::None ? 0 : 17;
      for (int rows : {6, 25}) {
        s.rows = rows;
        const SyntheticLeaf leaf(s);
        EXPECT_NO_THROW({
          const LeafModel model = buildLeafModel(leaf.markers(0.3, 2));
          EXPECT_EQ(model.markers.rows.size(), static_cast<std::size_t>(rows));
        }) << toString(shape)
           << " " << toString(kind) << " " << rows;
      }
    }
}

TEST(SyntheticSpec, RefusesWhatMakesNoLeaf) {
  const auto message = [](const SyntheticLeafSpec& s) {
    try {
      const SyntheticLeaf leaf(s);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  SyntheticLeafSpec s = defaultSyntheticSpec(LeafShape::Elliptic);
  s.outline.serration = Serration::Round;
  s.outline.teethPerSide = 10;
  s.outline.toothDepthMm = 100;
  EXPECT_NE(message(s).find("tooth depth"), std::string::npos) << message(s);
  s = defaultSyntheticSpec(LeafShape::Elliptic);
  s.rows = 1;
  EXPECT_NE(message(s).find("rows"), std::string::npos);
  s = defaultSyntheticSpec(LeafShape::Elliptic);
  s.outline.lengthMm = -3;
  EXPECT_NE(message(s).find("length"), std::string::npos);
  s = defaultSyntheticSpec(LeafShape::Ovate);
  s.outline.symmetry = 0.6;
  EXPECT_NE(message(s).find("symmetry"), std::string::npos);
  EXPECT_THROW((void)leafShapeFromString("round"), leafdig::UnknownName);
  EXPECT_THROW((void)serrationFromString("wavy"), leafdig::UnknownName);
  EXPECT_THROW((void)SyntheticLeaf(defaultSyntheticSpec(LeafShape::Ovate)).markers(-1.0, 1), InputError);
}

TEST(SyntheticTruth, FileHoldsTheExactAreaAndTheVeins) {
  const SyntheticLeaf leaf(defaultSyntheticSpec(LeafShape::Obovate));
  const nlohmann::json doc = nlohmann::json::parse(truthToJson(leaf, 0.2, 9));
  EXPECT_EQ(doc["format"], "leafdig.truth/1");
  EXPECT_DOUBLE_EQ(doc["area_mm2"].get<double>(), leaf.area());
  EXPECT_EQ(doc["veins"].size(), 2u * static_cast<std::size_t>(leaf.spec().rows));
  EXPECT_EQ(doc["markers_exact"]["rows"].size(), static_cast<std::size_t>(leaf.spec().rows));
  EXPECT_EQ(doc["spec"]["shape"], "obovate");
  const std::string svg = figureSvg({figurePanel(leaf, "obovate & co")}, 1);
  EXPECT_NE(svg.find("<polygon"), std::string::npos);
  EXPECT_NE(svg.find("obovate &amp; co"), std::string::npos);
}

}  // namespace
}  // namespace leafdig::model
