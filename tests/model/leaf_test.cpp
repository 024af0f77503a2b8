#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "leafdig/model/errors.hpp"
#include "leafdig/model/leaf/leaf_model.hpp"
#include "leafdig/model/mesh/mesh.hpp"
#include "leafdig/model/metrics/metrics.hpp"
#include "test_support.hpp"

namespace leafdig::model {
namespace {

using test::flatTriangleLeaf;
using test::sample;

TEST(ThicknessRule, standardModeInterpolatesFromVeinOriginToMargin) {
  MarkerSet m = flatTriangleLeaf(2, 10, 20);
  m.rows[1].veinOriginThicknessMm = 1.5;
  const LeafThickness t = applyThicknessRule(m);
  ASSERT_EQ(t.mode, ThicknessMode::Standard);
  const double d = 0.3;
  const double r2 = 1.5;
  const std::array<double, 7> expected{d, (2 * d + r2) / 3, (d + 2 * r2) / 3, r2, (d + 2 * r2) / 3, (2 * d + r2) / 3,
                                       d};
  for (int j = 0; j < 7; ++j) EXPECT_DOUBLE_EQ(t.rows[1].lateralMm[j], expected[j]);
  EXPECT_DOUBLE_EQ(t.rows[1].midribMm, 2.0);
  EXPECT_DOUBLE_EQ(t.tipMm, d);
}

TEST(ThicknessRule, smallModeUsesTheMidribForTheVeinOrigin) {
  MarkerSet m = flatTriangleLeaf(3, 10, 20);
  for (auto& row : m.rows) row.veinOriginThicknessMm.reset();
  const LeafThickness t = applyThicknessRule(m);
  ASSERT_EQ(t.mode, ThicknessMode::Small);
  EXPECT_DOUBLE_EQ(t.rows[0].lateralMm[3], 2.0);
  EXPECT_DOUBLE_EQ(t.rows[0].lateralMm[2], (0.3 + 2 * 2.0) / 3);
}

TEST(ThicknessRule, fullModeTakesEveryMeasuredValue) {
  MarkerSet m = flatTriangleLeaf(2, 10, 20);
  m.edgeThicknessMm.reset();
  for (auto& row : m.rows) {
    for (int j = 0; j < 7; ++j) row.measuredThicknessMm[j] = 0.1 * (j + 1);
  }
  const LeafThickness t = applyThicknessRule(m);
  ASSERT_EQ(t.mode, ThicknessMode::Full);
  for (int j = 0; j < 7; ++j) EXPECT_DOUBLE_EQ(t.rows[1].lateralMm[j], 0.1 * (j + 1));
  EXPECT_DOUBLE_EQ(t.tipMm, 0.5 * (0.1 + 0.7));  // no leaf-wide d: the first row's margins
}

TEST(ThicknessRule, perRowEdgeThicknessReplacesTheLeafValue) {
  MarkerSet m = flatTriangleLeaf(2, 10, 20);
  m.rows[0].edgeThicknessMm = 0.2;
  const LeafThickness t = applyThicknessRule(m);
  EXPECT_DOUBLE_EQ(t.rows[0].lateralMm[0], 0.2);
  EXPECT_DOUBLE_EQ(t.rows[1].lateralMm[0], 0.3);
}

TEST(ThicknessRule, namesTheRowWhenAThicknessIsMissingOrNotPositive) {
  MarkerSet m = flatTriangleLeaf(3, 10, 20);
  m.rows[1].veinOriginThicknessMm.reset();
  try {
    static_cast<void>(applyThicknessRule(m));
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("row 2"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("vein_origin_thickness"), std::string::npos);
  }
  m = flatTriangleLeaf(3, 10, 20);
  m.rows[2].midribThicknessMm = -1.0;
  EXPECT_THROW(static_cast<void>(applyThicknessRule(m)), InputError);
}

TEST(LeafModel, assemblesMidribTwoHalfLateralsPerRowAndContour) {
  const LeafModel leaf = buildLeafModel(sample("lower-leaf-n10.markers.json"));
  ASSERT_EQ(leaf.veins.size(), 2u * 10 + 2);
  EXPECT_EQ(leaf.veins.front().name, "midrib");
  EXPECT_EQ(leaf.veins[1].name, "lateral-1-right");
  EXPECT_EQ(leaf.veins[2].name, "lateral-1-left");
  EXPECT_EQ(leaf.veins.back().name, "contour");
  EXPECT_EQ(leaf.veins.front().curve.dataBalls().size(), 11u);
  EXPECT_EQ(leaf.veins.back().curve.dataBalls().size(), 21u);
  // The contour passes through the tip with radius d/2.
  const Ball& tip = leaf.veins.back().curve.dataBalls()[10];
  EXPECT_EQ(tip.center, leaf.markers.tipMm);
  EXPECT_DOUBLE_EQ(tip.radius, *leaf.markers.edgeThicknessMm / 2);
  // The right half-lateral runs P_i4 -> P_i1 with the midrib point first.
  EXPECT_EQ(leaf.veins[1].curve.dataBalls().front().center, leaf.markers.rows[0].pointsMm[3]);
  EXPECT_EQ(leaf.veins[1].curve.dataBalls().back().center, leaf.markers.rows[0].pointsMm[0]);
}

TEST(Blade, interpolatingBladePassesThroughEveryMarker) {
  const MarkerSet m = sample("upper-curved-leaf-n14.markers.json");
  const LeafModel leaf = buildLeafModel(m);
  const auto& us = leaf.blade.rowParameters;
  const auto& vs = leaf.blade.columnParameters;
  const MarkerGrid grid = markerGrid(m);
  for (std::size_t k = 0; k < grid.size(); ++k) {
    for (int l = 0; l < 7; ++l) {
      EXPECT_LT((leaf.blade.evaluate(us[k], vs[l]) - grid[k][l]).norm(), 1e-9) << "k=" << k << " l=" << l;
    }
  }
}

TEST(Blade, otherKindsUseTheMarkersAsControlPoints) {
  const MarkerSet m = sample("lower-leaf-n10.markers.json");
  for (BladeKind kind : {BladeKind::Approx, BladeKind::Bezier, BladeKind::Nurbs}) {
    const LeafModel leaf = buildLeafModel(m, {kind, nullptr});
    // Clamped: corners are interpolated; the tip row collapses to the tip.
    EXPECT_LT((leaf.blade.evaluate(0, 0.37) - m.tipMm).norm(), 1e-9) << toString(kind);
    EXPECT_LT((leaf.blade.evaluate(1, 0) - m.rows.back().pointsMm[0]).norm(), 1e-9);
    EXPECT_LT((leaf.blade.evaluate(1, 1) - m.rows.back().pointsMm[6]).norm(), 1e-9);
  }
  const LeafModel bezier = buildLeafModel(m, {BladeKind::Bezier, nullptr});
  EXPECT_EQ(bezier.blade.degreeU, 10);
  EXPECT_EQ(bezier.blade.degreeV, 6);
}

TEST(Blade, nurbsWithUnitWeightsEqualsApproxAndWeightsPullTheSurface) {
  const MarkerSet m = sample("lower-leaf-n10.markers.json");
  const LeafModel approx = buildLeafModel(m, {BladeKind::Approx, nullptr});
  const LeafModel nurbs = buildLeafModel(m, {BladeKind::Nurbs, nullptr});
  for (double u : {0.1, 0.45, 0.8}) {
    for (double v : {0.2, 0.5, 0.9}) {
      EXPECT_LT((approx.blade.evaluate(u, v) - nurbs.blade.evaluate(u, v)).norm(), 1e-9);
    }
  }
  std::vector<std::vector<double>> weights(11, std::vector<double>(7, 1.0));
  weights[5][3] = 10.0;
  const LeafModel pulled = buildLeafModel(m, {BladeKind::Nurbs, &weights});
  const Eigen::Vector3d target = m.rows[4].pointsMm[3];
  const double u = 0.5;
  const double v = 0.5;
  EXPECT_LT((pulled.blade.evaluate(u, v) - target).norm(), (approx.blade.evaluate(u, v) - target).norm());
}

TEST(Metrics, flatMarkerGridGivesTheExactPlanarArea) {
  const int n = 6;
  const double a = 12.0;
  const double h = 25.0;
  const LeafModel leaf = buildLeafModel(flatTriangleLeaf(n, a, h));
  const double exact = 3 * a * h * n * n;
  for (int perRow : {1, 3, 5}) {
    const Mesh blade = meshBlade(leaf.blade, perRow, 6 * perRow);
    EXPECT_NEAR(meshArea(blade), exact, 1e-9 * exact) << "per row " << perRow;
  }
  const BladeAreaEstimate est = convergedBladeArea(leaf.blade, {0, 0, 1});
  EXPECT_NEAR(est.areaMm2, exact, 1e-9 * exact);
  EXPECT_NEAR(est.projectedAreaMm2, exact, 1e-9 * exact);  // flat, lit from its normal
  const BladeAreaEstimate edgeOn = convergedBladeArea(leaf.blade, {1, 0, 0});
  EXPECT_NEAR(edgeOn.projectedAreaMm2, 0.0, 1e-9 * exact);
}

// Markers on a cylinder of radius R over `arc` radians, `length` along its axis.
BladeSurface cylinderBlade(double radius, double arc, double length) {
  const int rows = 9;
  MarkerGrid grid;
  for (int k = 0; k < rows; ++k) {
    std::array<Eigen::Vector3d, 7> row;
    for (int l = 0; l < 7; ++l) {
      const double phi = -arc / 2 + arc * l / 6;
      row[l] = {radius * std::sin(phi), -length * k / (rows - 1), radius * std::cos(phi)};
    }
    grid.push_back(row);
  }
  return buildBlade(grid, BladeKind::Interp);
}

TEST(Metrics, cylinderPatchAreaConvergesToTheAnalyticValue) {
  const double radius = 80.0;
  const double length = 200.0;
  // Finer meshes of one surface approach the analytic area monotonically ...
  const double arc = std::numbers::pi / 3;
  const BladeSurface blade = cylinderBlade(radius, arc, length);
  const double exact = radius * arc * length;
  double previousError = 1e9;
  for (int across : {6, 12, 24, 48}) {
    const double error = std::abs(meshArea(meshBlade(blade, 1, across)) - exact) / exact;
    EXPECT_LT(error, previousError) << "across " << across;
    previousError = error;
  }
  // ... and denser markers (the same 7 columns over a smaller arc) converge to it at the
  // cubic spline's O(h^2) rate or better.
  double previousSurfaceError = 1e9;
  for (double a : {arc, arc / 2, arc / 4}) {
    const BladeAreaEstimate est = convergedBladeArea(cylinderBlade(radius, a, length), {0, 0, 1});
    ASSERT_TRUE(est.converged);
    const double analytic = radius * a * length;
    const double error = std::abs(est.areaMm2 - analytic) / analytic;
    EXPECT_LT(error, 5e-4) << "arc " << a;
    EXPECT_LT(error, previousSurfaceError / 3.5) << "arc " << a;
    previousSurfaceError = error;
  }
}

TEST(Metrics, areaConstraintFlagsADifferenceAboveTheThreshold) {
  const AreaConstraint close = compareArea(1030.0, 1000.0);
  EXPECT_NEAR(close.differencePercent, 3.0, 1e-12);
  EXPECT_FALSE(close.exceeded);
  const AreaConstraint far = compareArea(900.0, 1000.0, 5.0);
  EXPECT_NEAR(far.differencePercent, -10.0, 1e-12);
  EXPECT_TRUE(far.exceeded);
}

TEST(Metrics, markerGridHeronAreaIsExactOnAFlatGridOfTriangles) {
  const MarkerSet m = flatTriangleLeaf(4, 10, 20);
  EXPECT_NEAR(markerGridHeronArea(markerGrid(m)), 3 * 10 * 20 * 16, 1e-6);
}

TEST(Mesh, paperPresetReproducesTheSeedsTable1Counts) {
  struct Row {
    const char* file;
    std::size_t veinVertices, veinQuads, bladeVertices, bladeQuads;
  };
  const Row table1[] = {{"lower-leaf-n10.markers.json", 3610, 3500, 1581, 1500},
                        {"upper-small-leaf-n17.markers.json", 6130, 5950, 2666, 2550},
                        {"upper-curved-leaf-n14.markers.json", 5050, 4900, 2201, 2100}};
  for (const Row& row : table1) {
    const LeafMesh mesh = meshLeaf(buildLeafModel(sample(row.file)), MeshResolution::preset("paper"));
    const MeshCounts veins = countVeins(mesh);
    const MeshCounts blade = countBlade(mesh);
    EXPECT_EQ(veins.vertices, row.veinVertices) << row.file;
    EXPECT_EQ(veins.quads, row.veinQuads) << row.file;
    EXPECT_EQ(veins.triangles, 2 * row.veinQuads) << row.file;
    EXPECT_EQ(blade.vertices, row.bladeVertices) << row.file;
    EXPECT_EQ(blade.quads, row.bladeQuads) << row.file;
  }
}

TEST(Mesh, everyVertexHasAUnitNormalAndBladeFacesTheAdaxialSide) {
  for (const char* file : test::kSampleFiles) {
    const LeafModel leaf = buildLeafModel(sample(file));
    const LeafMesh mesh = meshLeaf(leaf, MeshResolution::preset("export"));
    for (const Organ& o : mesh.organs) {
      ASSERT_EQ(o.mesh.normals.size(), o.mesh.positions.size()) << o.name;
      for (const auto& n : o.mesh.normals) ASSERT_NEAR(n.norm(), 1.0, 1e-9) << o.name;
    }
    // In the leaf frame +Z is the adaxial side by definition; the blade must agree.
    const LeafModel inLeafFrame = transformed(leaf, leafFrameFromDigitizer(leaf));
    const Mesh blade = meshBlade(inLeafFrame.blade, 3, 18);
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (const auto& n : blade.normals) sum += n;
    EXPECT_GT(sum.normalized().z(), 0.5) << file;
  }
}

// Vein tubes are closed and wound counter-clockwise seen from outside (the face normal from
// the winding agrees with the vertex normals): a renderer may cull their back faces, and
// exported files show the outside to viewers that use the winding.
TEST(Mesh, veinTrianglesAreWoundToFaceOutwards) {
  for (const char* file : test::kSampleFiles)
    for (const char* preset : {"preview", "export"}) {
      const LeafMesh mesh = meshLeaf(buildLeafModel(sample(file)), MeshResolution::preset(preset));
      for (const Organ& o : mesh.organs) {
        if (o.kind != OrganKind::Vein) continue;
        std::size_t inward = 0, measured = 0;
        for (const auto& t : o.mesh.triangles) {
          const auto& a = o.mesh.positions[t[0]];
          const Eigen::Vector3d face = (o.mesh.positions[t[1]] - a).cross(o.mesh.positions[t[2]] - a);
          if (face.norm() < 1e-12) continue;  // a degenerate sliver at a cap's pole
          ++measured;
          const Eigen::Vector3d n = o.mesh.normals[t[0]] + o.mesh.normals[t[1]] + o.mesh.normals[t[2]];
          inward += face.dot(n) <= 0;
        }
        EXPECT_GT(measured, 0u) << file << " " << o.name;
        EXPECT_EQ(inward, 0u) << file << " " << preset << " " << o.name << ": " << inward << " of " << measured
                              << " triangles face inwards";
      }
    }
}

TEST(LeafFrame, putsTheLastMidribMarkerAtTheOriginAndTheTipOnPlusY) {
  const LeafModel leaf = buildLeafModel(sample("upper-curved-leaf-n14.markers.json"));
  const Eigen::Isometry3d toLeaf = leafFrameFromDigitizer(leaf);
  EXPECT_LT((toLeaf * leaf.markers.rows.back().pointsMm[3]).norm(), 1e-9);
  const Eigen::Vector3d tip = toLeaf * leaf.markers.tipMm;
  EXPECT_NEAR(tip.x(), 0.0, 1e-9);
  EXPECT_NEAR(tip.z(), 0.0, 1e-9);
  EXPECT_GT(tip.y(), 0.0);
  EXPECT_NEAR(toLeaf.linear().determinant(), 1.0, 1e-12);  // a rotation, not a reflection
  // Markers on the right (j = 1) are at +X, seen from the adaxial side with the tip up.
  EXPECT_GT((toLeaf * leaf.markers.rows[3].pointsMm[0]).x(), 0.0);
  // The transformed model keeps every data ball on its curve.
  const LeafModel moved = transformed(leaf, toLeaf);
  for (const Vein& v : moved.veins) {
    for (std::size_t k = 0; k < v.curve.dataBalls().size(); ++k) {
      EXPECT_LT((v.curve.center(v.curve.dataParameters()[k]) - v.curve.dataBalls()[k].center).norm(), 1e-9);
    }
  }
}

TEST(Metrics, sampleLeafAreasConvergeWithinAThousandth) {
  for (const char* file : test::kSampleFiles) {
    const LeafModel leaf = buildLeafModel(sample(file));
    const LeafMetrics metrics = computeLeafMetrics(leaf, {0, 0, 1});
    EXPECT_TRUE(metrics.blade.converged) << file;
    EXPECT_LT(metrics.blade.relativeChange, 1e-3);
    EXPECT_LE(metrics.blade.projectedAreaMm2, metrics.blade.areaMm2 * (1 + 1e-12));
    // The markers-only Heron sum is a comparison figure close to the blade's area.
    EXPECT_NEAR(metrics.markerGridHeronAreaMm2, metrics.blade.areaMm2, 0.05 * metrics.blade.areaMm2);
  }
}

}  // namespace
}  // namespace leafdig::model
