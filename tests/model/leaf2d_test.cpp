// 2-D leaves (seed 001): outlines, scans, curl, Laplacian deformation, area constraint.
#include "leafdig/model/leaf2d/leaf2d.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>

#include "leafdig/model/errors.hpp"
#include "leafdig/model/files.hpp"
#include "leafdig/model/leaf2d/leaf_scan.hpp"
#include "leafdig/model/metrics/metrics.hpp"
#include "leafdig/model/synth/synthetic_leaf.hpp"
#include "leafdig/names/name_table.hpp"
#include "test_support.hpp"

namespace m = leafdig::model;
namespace fs = std::filesystem;

namespace {

std::vector<Eigen::Vector2d> ellipse(double a, double b, int n, Eigen::Vector2d centre = {0, 0}) {
  std::vector<Eigen::Vector2d> out;
  for (int i = 0; i < n; ++i) {
    const double t = 2 * M_PI * i / n;
    out.push_back(centre + Eigen::Vector2d(a * std::cos(t), b * std::sin(t)));
  }
  return out;
}

// The polygon inscribed in an ellipse has area (n/2) a b sin(2 pi / n).
double inscribedArea(double a, double b, int n) {
  return n / 2.0 * a * b * std::sin(2 * M_PI / n);
}

// What f throws as an InputError, or "no error".
template <class F>
std::string inputErrorOf(F&& f) {
  try {
    f();
  } catch (const m::InputError& e) {
    return std::string(e.what());
  }
  return std::string("no error");
}

TEST(Outline, ReadsJsonAndCsvAndNamesWhatIsWrong) {
  const m::Outline2d j = m::parseOutlineJson(
      R"({"format": "leafdig.outline/1", "units": "mm", "id": "L1", "measured_area_mm2": 100,
          "points": [[0,0],[10,0],[10,10],[0,10],[0,9],[0,8],[0,7],[0,6],[0,0]], "base": [5, 0]})",
      "a.json");
  EXPECT_EQ(j.pointsMm.size(), 8u);  // the closing repeat is dropped
  EXPECT_DOUBLE_EQ(m::polygonArea(j.pointsMm), 100.0);
  ASSERT_TRUE(j.baseMm);
  EXPECT_EQ(*j.measuredAreaMm2, 100.0);
  const m::Outline2d c =
      m::parseOutlineCsv("# a square\nx_mm,y_mm\n0,0\n10,0\n10,10\n0,10\n0,9\n0,8\n0,7\n0,6\n", "a.csv");
  EXPECT_EQ(c.pointsMm.size(), 8u);

  EXPECT_NE(inputErrorOf([] {
              (void)m::parseOutlineJson(R"({"format": "leafdig.outline/1", "units": "px", "points": []})", "p.json");
            }).find("convert the points to millimetres"),
            std::string::npos);
  EXPECT_NE(
      inputErrorOf([] { (void)m::parseOutlineCsv("x_px,y_px\n0,0\n", "p.csv"); }).find("does not say millimetres"),
      std::string::npos);
  EXPECT_NE(inputErrorOf([] { (void)m::parseOutlineCsv("0,0\n1,0\n1,1\n", "few.csv"); }).find("at least 8"),
            std::string::npos);
  EXPECT_NE(inputErrorOf([] { (void)m::parseOutlineCsv("0,0\n1,zero\n", "bad.csv"); }).find("bad.csv:2: column 2"),
            std::string::npos);
  EXPECT_NE(inputErrorOf([] {
              (void)m::parseOutlineJson(R"({"format": "leafdig.outline/1", "units": "mm", "base": [50, 50],
                 "points": [[0,0],[10,0],[10,10],[0,10],[0,9],[0,8],[0,7],[0,6]]})",
                                        "b.json");
            }).find("the base (50, 50) is"),
            std::string::npos);
}

TEST(Outline, BaseAndTipAreTheFarthestPairWithTheTipAtTheNarrowEnd) {
  // An egg: wide at x = -40 (base), pointed towards x = +60 (tip).
  m::Outline2d o;
  for (int i = 0; i < 400; ++i) {
    const double t = 2 * M_PI * i / 400;
    const double x = std::cos(t);
    o.pointsMm.emplace_back(x > 0 ? 60 * x : 40 * x, 30 * std::sin(t) * (x > 0 ? 1 - 0.5 * x : 1.0));
  }
  const auto [base, tip] = m::findBaseAndTip(o);
  EXPECT_NEAR(base.x(), -40, 0.5);
  EXPECT_NEAR(tip.x(), 60, 0.5);
}

TEST(Curl, TheMarginHeightsAreTheSeedsFivePoints) {
  const std::array<double, 5> parabola{0, 0.75, 1, 0.75, 0};
  const std::array<double, 5> sine{0, 1, 0, 1, 0};
  for (int i = 0; i < 5; ++i) {
    EXPECT_NEAR(m::curlHeight(m::CurlKind::Parabola, i / 4.0), parabola[static_cast<std::size_t>(i)], 1e-12);
    EXPECT_NEAR(m::curlHeight(m::CurlKind::Sine, i / 4.0), sine[static_cast<std::size_t>(i)], 1e-12);
  }
  EXPECT_EQ(m::curlHeight(m::CurlKind::None, 0.3), 0.0);
  EXPECT_EQ(m::curlKindFromString("sine"), m::CurlKind::Sine);
  EXPECT_THROW((void)m::curlKindFromString("helix"), leafdig::UnknownName);
}

TEST(Leaf2d, AnEllipseCurlsByTheChosenProfileAndKeepsItsMeasuredArea) {
  const double a = 60;
  const double b = 25;
  m::Outline2d o;
  o.pointsMm = ellipse(a, b, 720);
  const double exact = inscribedArea(a, b, 720);
  for (m::CurlKind kind : {m::CurlKind::Parabola, m::CurlKind::Sine, m::CurlKind::None}) {
    m::Leaf2dOptions opt;
    opt.curl = kind;
    opt.amplitudeMm = 8;
    const m::Leaf2dModel leaf = m::buildLeaf2d(o, opt);
    EXPECT_NEAR(leaf.lengthMm, 2 * a, 1e-9);
    EXPECT_NEAR(leaf.widthMm, 2 * b, 0.2);  // the widest of 28 sections
    EXPECT_NEAR(leaf.outlineAreaMm2, exact, 1e-9 * exact);
    EXPECT_NEAR(leaf.flatModelAreaMm2, exact, 0.005 * exact) << "flat bicubic leaf vs its outline";
    // The area constraint: the curled leaf's surface area is the measured (outline) area.
    EXPECT_NEAR(leaf.modelAreaMm2, exact, 1e-3 * exact);
    EXPECT_NEAR(m::meshArea(leaf.mesh), leaf.measuredAreaMm2, 1e-8 * exact);
    EXPECT_LE(leaf.projectedAreaMm2, leaf.modelAreaMm2 + 1e-9);
    EXPECT_LE(leaf.silhouetteAreaMm2, leaf.modelAreaMm2 * 1.001);
    // Curling takes the margin in: the in-plane scale is below 1 exactly when it curls.
    if (kind == m::CurlKind::None) {
      EXPECT_NEAR(leaf.inPlaneScale, std::sqrt(exact / leaf.flatModelAreaMm2), 1e-6);
    } else {
      EXPECT_LT(leaf.inPlaneScale, std::sqrt(exact / leaf.flatModelAreaMm2));
    }
    // The margin follows the profile: z = A h(t) at every margin vertex, base and tip at 0.
    ASSERT_EQ(leaf.marginVertices.size(), leaf.marginT.size());
    ASSERT_GT(leaf.marginVertices.size(), 100u);
    for (std::size_t k = 0; k < leaf.marginVertices.size(); ++k) {
      EXPECT_NEAR(leaf.mesh.positions[leaf.marginVertices[k]].z(), 8.0 * m::curlHeight(kind, leaf.marginT[k]), 1e-9);
    }
    // The leaf frame: base at the origin, tip on +Y.
    EXPECT_NEAR(leaf.mesh.positions.back().norm(), 0.0, 1e-9);
    EXPECT_NEAR(leaf.mesh.positions.front().y(), 2 * a * leaf.inPlaneScale, 1e-6);
    // The interior follows smoothly: the least-squares energy over every vertex is not a
    // maximum principle (it may overshoot the margin a little), but stays close to it.
    for (const auto& p : leaf.mesh.positions) {
      EXPECT_GE(p.z(), -0.05 * 8.0);
      EXPECT_LE(p.z(), 1.05 * 8.0);
    }
  }
}

bool insidePolygon(const std::vector<Eigen::Vector2d>& poly, const Eigen::Vector2d& p) {
  bool in = false;
  for (std::size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++) {
    if ((poly[i].y() > p.y()) != (poly[j].y() > p.y()) &&
        p.x() < poly[j].x() + (p.y() - poly[j].y()) / (poly[i].y() - poly[j].y()) * (poly[i].x() - poly[j].x())) {
      in = !in;
    }
  }
  return in;
}

// Whether some triangle of the mesh, seen from +Z, covers p.
bool covers(const m::Mesh& mesh, const Eigen::Vector2d& p) {
  for (const auto& t : mesh.triangles) {
    const Eigen::Vector2d a = mesh.positions[t[0]].head<2>();
    const Eigen::Vector2d b = mesh.positions[t[1]].head<2>();
    const Eigen::Vector2d c = mesh.positions[t[2]].head<2>();
    auto side = [&](const Eigen::Vector2d& u, const Eigen::Vector2d& v) {
      return (v - u).x() * (p - u).y() - (v - u).y() * (p - u).x();
    };
    if (side(a, b) >= 0 && side(b, c) >= 0 && side(c, a) >= 0) return true;
  }
  return false;
}

TEST(Leaf2d, AHeartShapedLeafFollowsItsSinus) {
  // A cordate leaf: sections across the midrib would span the basal sinus; the flat leaf is
  // trimmed to the outline instead, so the lobes are leaf and the sinus is not.
  m::Outline2d o;
  for (int i = 0; i < 400; ++i) {
    const double t = 2 * M_PI * i / 400;
    o.pointsMm.emplace_back(48 * std::pow(std::sin(t), 3),
                            3 * (13 * std::cos(t) - 5 * std::cos(2 * t) - 2 * std::cos(3 * t) - std::cos(4 * t)));
  }
  o.baseMm = Eigen::Vector2d(0, 15);  // the sinus's apex; the tip is the heart's point, (0, -51)
  m::Leaf2dOptions flatOpt;
  flatOpt.curl = m::CurlKind::None;
  const m::Leaf2dModel flat = m::buildLeaf2d(o, flatOpt);
  EXPECT_TRUE(flat.trimmedToOutline);
  EXPECT_TRUE(flat.warnings.empty()) << flat.warnings[0].message;
  EXPECT_NEAR(flat.flatModelAreaMm2, flat.outlineAreaMm2, 0.003 * flat.outlineAreaMm2);
  EXPECT_NEAR(flat.inPlaneScale, 1.0, 0.002);  // nothing filled, nothing to draw in
  EXPECT_NE(m::leaf2dToJson(flat).find("\"flat_leaf\":\"trimmed-to-outline\""), std::string::npos);
  // Outline coordinates -> leaf frame: origin at the base, +Y to the tip (down the page), +X
  // the leaf's right (-x of the page).
  auto frame = [&](const Eigen::Vector2d& p) -> Eigen::Vector2d {
    return Eigen::Vector2d(-p.x(), 15.0 - p.y()) * flat.inPlaneScale;
  };
  EXPECT_NEAR(flat.mesh.positions.back().norm(), 0.0, 1e-9);                                 // the base
  EXPECT_NEAR((flat.mesh.positions.front().head<2>() - frame({0, -51})).norm(), 0.0, 1e-6);  // the tip
  // The sinus is not leaf; both lobes and the blade are.
  for (const Eigen::Vector2d& sinus : {Eigen::Vector2d(0, 20), Eigen::Vector2d(0, 30), Eigen::Vector2d(2, 26)}) {
    ASSERT_FALSE(insidePolygon(o.pointsMm, sinus));
    EXPECT_FALSE(covers(flat.mesh, frame(sinus))) << sinus.transpose();
  }
  for (const Eigen::Vector2d& leaf :
       {Eigen::Vector2d(24, 25), Eigen::Vector2d(-24, 25), Eigen::Vector2d(0, 10), Eigen::Vector2d(0, -40)}) {
    ASSERT_TRUE(insidePolygon(o.pointsMm, leaf));
    EXPECT_TRUE(covers(flat.mesh, frame(leaf))) << leaf.transpose();
  }
  // Every margin vertex lies on the outline, the right margin at +X; no triangle is degenerate.
  std::vector<Eigen::Vector2d> framed;
  for (const auto& p : o.pointsMm) framed.push_back(frame(p));
  for (std::uint32_t v : flat.marginVertices) {
    double d = 1e9;
    for (std::size_t i = 0; i < framed.size(); ++i) {
      const Eigen::Vector2d a = framed[i];
      const Eigen::Vector2d ab = framed[(i + 1) % framed.size()] - a;
      const double t = std::clamp((flat.mesh.positions[v].head<2>() - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
      d = std::min(d, (a + t * ab - flat.mesh.positions[v].head<2>()).norm());
    }
    EXPECT_LT(d, 1e-6) << "margin vertex " << v;
  }
  EXPECT_GT(flat.mesh.positions[flat.marginVertices[flat.marginVertices.size() / 4]].x(), 0.0);
  EXPECT_LT(flat.mesh.positions[flat.marginVertices[3 * flat.marginVertices.size() / 4]].x(), 0.0);
  for (const auto& t : flat.mesh.triangles) {
    const Eigen::Vector3d n = (flat.mesh.positions[t[1]] - flat.mesh.positions[t[0]])
                                  .cross(flat.mesh.positions[t[2]] - flat.mesh.positions[t[0]]);
    EXPECT_GT(n.z(), 1e-6);  // faces up, none of zero area
  }
  // Curled: the margin, sinus edges included, follows the profile from the base, and the
  // measured area holds.
  for (m::CurlKind kind : {m::CurlKind::Parabola, m::CurlKind::Sine}) {
    m::Leaf2dOptions opt;
    opt.curl = kind;
    opt.amplitudeMm = 6;
    const m::Leaf2dModel leaf = m::buildLeaf2d(o, opt);
    EXPECT_TRUE(leaf.trimmedToOutline);
    ASSERT_EQ(leaf.marginVertices.size(), leaf.marginT.size());
    for (std::size_t k = 0; k < leaf.marginVertices.size(); ++k) {
      EXPECT_NEAR(leaf.mesh.positions[leaf.marginVertices[k]].z(), 6.0 * m::curlHeight(kind, leaf.marginT[k]), 1e-9);
    }
    EXPECT_NEAR(leaf.modelAreaMm2, leaf.outlineAreaMm2, 1e-6 * leaf.outlineAreaMm2);
    EXPECT_GT(leaf.inPlaneScale, 0.95);
  }
  // An ellipse has nothing to fill: no warning.
  m::Outline2d e;
  e.pointsMm = ellipse(50, 30, 400);
  EXPECT_TRUE(m::buildLeaf2d(e).warnings.empty());
  // ... unless its curl is far too tall for it: the area still holds, the leaf is drawn in.
  m::Leaf2dOptions tall;
  tall.amplitudeMm = 60;
  const m::Leaf2dModel drawnIn = m::buildLeaf2d(e, tall);
  EXPECT_LT(drawnIn.inPlaneScale, 0.9);
  EXPECT_NEAR(drawnIn.modelAreaMm2, drawnIn.outlineAreaMm2, 1e-6 * drawnIn.outlineAreaMm2);
  ASSERT_EQ(drawnIn.warnings.size(), 1u);
  EXPECT_EQ(drawnIn.warnings[0].name, "curl-draws-leaf-in");
}

TEST(Leaf2d, AutoPicksTheCurlThatCatchesMostLight) {
  m::Outline2d o;
  o.pointsMm = ellipse(50, 30, 400);
  m::Leaf2dOptions opt;
  opt.curl = m::CurlKind::Auto;
  opt.light = {0.3, 0.2, 1.0};
  const m::Leaf2dModel leaf = m::buildLeaf2d(o, opt);
  ASSERT_EQ(leaf.candidates.size(), 2u);
  const auto& best = leaf.candidates[0].projectedAreaMm2 >= leaf.candidates[1].projectedAreaMm2 ? leaf.candidates[0]
                                                                                                : leaf.candidates[1];
  EXPECT_EQ(leaf.curl, best.kind);
  EXPECT_DOUBLE_EQ(leaf.projectedAreaMm2, best.projectedAreaMm2);
  for (const auto& c : leaf.candidates) EXPECT_NEAR(c.areaMm2, leaf.measuredAreaMm2, 1e-6 * leaf.measuredAreaMm2);
  EXPECT_NE(m::leaf2dToJson(leaf).find("\"candidates\""), std::string::npos);
}

TEST(LeafScan, AScannedEllipseOfKnownAreaAt300Dpi) {
  const fs::path dir = m::test::freshDir("ellipse");
  const double a = 45;
  const double b = 28;
  const int n = 4096;
  m::renderScan({ellipse(a, b, n, {105, 148})}, {}, {210, 297}, 300, dir / "ellipse.png");
  const m::LeafScan scan = m::scanLeaf(dir / "ellipse.png", {300, 3});
  const double truth = inscribedArea(a, b, n);
  EXPECT_NEAR(scan.areaMm2, truth, 0.002 * truth);
  EXPECT_NEAR(scan.filledAreaMm2, truth, 0.002 * truth);
  EXPECT_EQ(scan.holes, 0);
  EXPECT_FALSE(scan.petioleFound);
  EXPECT_FALSE(scan.touchesBorder);
  EXPECT_EQ(scan.otherObjects, 0);
  EXPECT_NEAR(m::polygonArea(scan.outline.pointsMm), truth, 0.01 * truth);  // through the boundary pixels' centres
  const auto [base, tip] = m::findBaseAndTip(scan.outline);
  EXPECT_NEAR((tip - base).norm(), 2 * a, 0.3);
  EXPECT_NEAR(std::abs(tip.y() - 148), 0.0, 2.0);  // the ends are flat: pixels tie within ~1 mm
  fs::remove_all(dir);
}

TEST(LeafScan, HolesAreNotTissueAndThePetioleIsFoundAndSetApart) {
  const fs::path dir = m::test::freshDir("petiole");
  const double a = 40;
  const double b = 25;
  const Eigen::Vector2d c(100, 120);
  // A 2 mm wide, 30 mm long petiole from the ellipse's left end; a 6 mm round hole.
  const std::vector<Eigen::Vector2d> petiole{
      {c.x() - a - 30, c.y() - 1}, {c.x() - a + 2, c.y() - 1}, {c.x() - a + 2, c.y() + 1}, {c.x() - a - 30, c.y() + 1}};
  const auto hole = ellipse(3, 3, 256, {c.x() + 10, c.y() + 5});
  m::renderScan({ellipse(a, b, 2048, c), petiole}, {hole}, {210, 297}, 300, dir / "leaf.png");
  const m::LeafScan scan = m::scanLeaf(dir / "leaf.png", {300, 3});
  const double blade = inscribedArea(a, b, 2048);
  ASSERT_TRUE(scan.petioleFound);
  EXPECT_NEAR(scan.petioleAreaMm2, 60.0, 6.0);  // 2 x 30 mm outside the blade
  EXPECT_EQ(scan.holes, 1);
  EXPECT_NEAR(scan.holesAreaMm2, M_PI * 9, 0.05 * M_PI * 9);
  EXPECT_NEAR(scan.filledAreaMm2, blade, 0.004 * blade);
  EXPECT_NEAR(scan.areaMm2, blade - M_PI * 9, 0.004 * blade);
  ASSERT_TRUE(scan.outline.baseMm);
  EXPECT_NEAR((*scan.outline.baseMm - Eigen::Vector2d(c.x() - a, c.y())).norm(), 0.0, 1.0);
  // ... and the 2-D leaf built from it stands on that base with the blade's measured area.
  const m::Leaf2dModel leaf = m::buildLeaf2d(scan.outline);
  EXPECT_NEAR(leaf.lengthMm, 2 * a, 1.0);
  EXPECT_NEAR(leaf.modelAreaMm2, scan.filledAreaMm2, 1e-6 * blade);
  fs::remove_all(dir);
}

TEST(LeafScan, NamesWhatIsWrongWithTheImage) {
  const fs::path dir = m::test::freshDir("bad");
  m::renderScan({}, {}, {50, 50}, 100, dir / "blank.png");
  EXPECT_NE(inputErrorOf([&] {
              (void)m::scanLeaf(dir / "blank.png", {100, 3});
            }).find("nearly uniform"),
            std::string::npos);
  EXPECT_NE(inputErrorOf([&] { (void)m::scanLeaf(dir / "blank.png", {0, 3}); }).find("give --dpi"), std::string::npos);
  m::writeFileAtomically(dir / "not.png", "this is not an image");
  EXPECT_NE(inputErrorOf([&] {
              (void)m::scanLeaf(dir / "not.png", {300, 3});
            }).find("cannot decode"),
            std::string::npos);
  EXPECT_NE(inputErrorOf([&] {
              (void)m::scanLeaf(dir / "missing.png", {300, 3});
            }).find("no such image"),
            std::string::npos);
  // Only dust: nothing as large as a leaf.
  m::renderScan({ellipse(1, 1, 64, {25, 25})}, {}, {50, 50}, 300, dir / "dust.png");
  EXPECT_NE(inputErrorOf([&] {
              (void)m::scanLeaf(dir / "dust.png", {300, 3});
            }).find("no leaf found"),
            std::string::npos);
  fs::remove_all(dir);
}

}  // namespace

namespace {

// A scan of a toothed leaf shows its teeth (issue 26): the outline of a synthetic leaf with
// straight teeth D deep (the profile runs from 0 to 2 D about a mean of D) reaches about D
// outside and D inside a smooth margin at a marker spacing of several teeth; an entire
// margin shows next to nothing. Through a real scan too (rendered at 300 DPI, segmented).
TEST(MarginFromScan, AToothedOutlineShowsItsTeethAndAnEntireOneNone) {
  m::SyntheticLeafSpec spec = m::defaultSyntheticSpec(m::LeafShape::Elliptic);
  spec.outline.lengthMm = 200;
  const double depth = 2.0;
  const auto outlineOf = [&](m::Serration serration) {
    m::SyntheticLeafSpec s = spec;
    s.outline.serration = serration;
    s.outline.teethPerSide = 30;
    s.outline.toothDepthMm = depth;
    m::Outline2d o;
    o.pointsMm = m::SyntheticLeaf(s).outline(6000);
    return o;
  };
  const m::MarginSample toothed = m::marginFromOutline(outlineOf(m::Serration::Straight), 25.0);
  EXPECT_NEAR(toothed.outsideMm, depth, 0.5 * depth) << toothed.insideMm;
  EXPECT_NEAR(toothed.insideMm, depth, 0.5 * depth) << toothed.outsideMm;
  const m::MarginSample entire = m::marginFromOutline(outlineOf(m::Serration::None), 25.0);
  EXPECT_LT(entire.outsideMm + entire.insideMm, 0.25 * depth);
  // The profile at several spacings, increasing; marginAt interpolates between them.
  const m::MarginFromScan profile = m::marginProfile(outlineOf(m::Serration::Straight));
  ASSERT_GE(profile.size(), 5u);
  for (std::size_t k = 1; k < profile.size(); ++k) EXPECT_GT(profile[k].spacingMm, profile[k - 1].spacingMm);
  const m::MarginSample mid = m::marginAt(profile, 0.5 * (profile[2].spacingMm + profile[3].spacingMm));
  EXPECT_NEAR(mid.outsideMm, 0.5 * (profile[2].outsideMm + profile[3].outsideMm), 1e-9);
  // Scanned: the same teeth, within a pixel's worth.
  const fs::path dir = m::test::freshDir("toothed-scan");
  std::vector<Eigen::Vector2d> page;
  for (const auto& p : outlineOf(m::Serration::Straight).pointsMm) page.push_back(p + Eigen::Vector2d(105, 40));
  m::renderScan({page}, {}, {210, 297}, 300, dir / "toothed.png");
  const m::LeafScan scan = m::scanLeaf(dir / "toothed.png", {300, 0});
  const m::MarginSample scanned = m::marginFromOutline(scan.outline, 25.0);
  EXPECT_NEAR(scanned.outsideMm, toothed.outsideMm, 0.3);
  EXPECT_NEAR(scanned.insideMm, toothed.insideMm, 0.3);
  fs::remove_all(dir);
}

}  // namespace
