// Seed and error-bounded meshing (docs/meshing.md), and the mesh distance they are measured with.
#include "leafdig/model/mesh/mesh_method.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <map>
#include <numbers>
#include <random>

#include "leafdig/model/leaf/leaf_model.hpp"
#include "leafdig/model/mesh/mesh_compare.hpp"
#include "leafdig/model/metrics/metrics.hpp"
#include "leafdig/model/study/mesh_study.hpp"
#include "leafdig/names/name_table.hpp"
#include "test_support.hpp"

namespace leafdig::model {
namespace {

constexpr double kPi = std::numbers::pi;

// ---- the compare tool on cases with known answers ------------------------------------

TriangleSoup gridPlane(int n, double size, double z) {
  TriangleSoup s;
  for (int i = 0; i <= n; ++i) {
    for (int j = 0; j <= n; ++j) s.positions.emplace_back(size * i / n, size * j / n, z);
  }
  const auto w = static_cast<std::uint32_t>(n + 1);
  for (std::uint32_t i = 0; i < static_cast<std::uint32_t>(n); ++i) {
    for (std::uint32_t j = 0; j < static_cast<std::uint32_t>(n); ++j) {
      const std::uint32_t a = i * w + j;
      s.triangles.push_back({a, a + w, a + w + 1});
      s.triangles.push_back({a, a + w + 1, a + 1});
    }
  }
  return s;
}

TEST(MeshCompare, APlaneAgainstTheSamePlaneShiftedIsTheShiftEverywhere) {
  const TriangleSoup a = gridPlane(20, 100.0, 0.0);
  const TriangleSoup b = gridPlane(7, 100.0, 0.25);  // other triangles, same square
  const MeshDistance d = compareMeshes(a, b, {20'000, 1.0, 7, 2});
  EXPECT_NEAR(d.hausdorff, 0.25, 1e-9);
  EXPECT_NEAR(d.mean, 0.25, 1e-9);
  EXPECT_NEAR(d.rms, 0.25, 1e-9);
  EXPECT_EQ(d.trianglesA, 800U);
  EXPECT_EQ(d.trianglesB, 98U);
}

TEST(MeshCompare, APlaneAgainstALargerPlaneSeesTheOverhangOnlyOneWay) {
  const TriangleSoup a = gridPlane(10, 100.0, 0.0);
  TriangleSoup b = gridPlane(10, 100.0, 0.0);
  for (auto& p : b.positions) p.x() *= 1.1;  // 10 mm longer in x
  const MeshDistance d = compareMeshes(a, b, {50'000, 1.0, 3, 2});
  EXPECT_NEAR(d.aToB.max, 0.0, 1e-9);   // every point of a lies on b
  EXPECT_NEAR(d.bToA.max, 10.0, 1e-9);  // b's far corner vertices are 10 mm from a
  EXPECT_NEAR(d.hausdorff, 10.0, 1e-9);
}

// An icosahedron subdivided and pushed onto the sphere of radius R: the sphere's points
// farthest from it are over the face centres, at R - (distance of the face's plane).
TriangleSoup sphere(double radius, int subdivisions, bool onSphere) {
  const double g = (1.0 + std::sqrt(5.0)) / 2.0;
  TriangleSoup s;
  for (const auto& p : std::vector<Eigen::Vector3d>{{-1, g, 0},
                                                    {1, g, 0},
                                                    {-1, -g, 0},
                                                    {1, -g, 0},
                                                    {0, -1, g},
                                                    {0, 1, g},
                                                    {0, -1, -g},
                                                    {0, 1, -g},
                                                    {g, 0, -1},
                                                    {g, 0, 1},
                                                    {-g, 0, -1},
                                                    {-g, 0, 1}})
    s.positions.push_back(p.normalized() * radius);
  s.triangles = {{0, 11, 5},  {0, 5, 1},  {0, 1, 7},  {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                 {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
                 {3, 8, 9},   {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  for (int level = 0; level < subdivisions; ++level) {
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> mid;
    auto middle = [&](std::uint32_t a, std::uint32_t b) {
      auto key = std::minmax(a, b);
      auto [it, inserted] = mid.try_emplace({key.first, key.second}, static_cast<std::uint32_t>(s.positions.size()));
      if (inserted) {
        Eigen::Vector3d m = (s.positions[a] + s.positions[b]) / 2.0;
        s.positions.push_back(onSphere ? Eigen::Vector3d(m.normalized() * radius) : m);
      }
      return it->second;
    };
    std::vector<std::array<std::uint32_t, 3>> next;
    for (const auto& t : s.triangles) {
      const std::uint32_t ab = middle(t[0], t[1]);
      const std::uint32_t bc = middle(t[1], t[2]);
      const std::uint32_t ca = middle(t[2], t[0]);
      next.push_back({t[0], ab, ca});
      next.push_back({ab, t[1], bc});
      next.push_back({ca, bc, t[2]});
      next.push_back({ab, bc, ca});
    }
    s.triangles = std::move(next);
  }
  return s;
}

TEST(MeshCompare, ASphereAgainstItsInscribedIcosahedronIsTheGapAtTheFaceCentres) {
  const double radius = 50.0;
  const TriangleSoup icosahedron = sphere(radius, 0, true);
  const TriangleSoup fine = sphere(radius, 6, true);  // 81 920 triangles, 0.03 mm from the sphere
  // Inradius of the regular icosahedron with circumradius R: R * 0.7946544723.
  const double expected = radius * (1.0 - 0.7946544723);
  const MeshDistance d = compareMeshes(icosahedron, fine, {400'000, 2.0, 11, 2});
  // Both ways the farthest points are over the face centres (the corners touch the sphere).
  EXPECT_NEAR(d.aToB.max, expected, 0.05);
  EXPECT_NEAR(d.bToA.max, expected, 0.05);
  EXPECT_NEAR(d.hausdorff, expected, 0.05);
}

TEST(MeshCompare, TheSameSeedGivesTheSameAnswerWithAnyNumberOfThreads) {
  const TriangleSoup a = sphere(10.0, 2, true);
  const TriangleSoup b = sphere(10.0, 3, false);
  const MeshDistance one = compareMeshes(a, b, {30'000, 1.0, 5, 1});
  const MeshDistance two = compareMeshes(a, b, {30'000, 1.0, 5, 2});
  EXPECT_DOUBLE_EQ(one.hausdorff, two.hausdorff);
  EXPECT_NEAR(one.mean, two.mean, 1e-12);
}

TEST(MeshCompare, AMeshWithoutAreaIsRefusedWithAMessage) {
  TriangleSoup flat;
  flat.positions = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}};
  flat.triangles = {{0, 1, 2}};
  try {
    (void)compareMeshes(flat, gridPlane(2, 1.0, 0.0));
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("no triangle of positive area"), std::string::npos);
  }
}

// ---- the seed's merge rule on hand-made polylines ------------------------------------

TEST(SeedRule, AStraightLineKeepsOnlyItsEnds) {
  std::vector<Eigen::Vector3d> line;
  for (int k = 0; k <= 10; ++k) line.emplace_back(k, 0, 0);
  EXPECT_EQ(mergeByAngle(line, 175.0), (std::vector<std::size_t>{0, 10}));
}

TEST(SeedRule, ACornerSharperThanAlphaIsKeptAndTheMergedSegmentIsTestedWithTheNext) {
  // 0-1-2 straight, a 90 degree corner at 2, then 2-3-4 straight.
  const std::vector<Eigen::Vector3d> l{{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {2, 1, 0}, {2, 2, 0}};
  EXPECT_EQ(mergeByAngle(l, 170.0), (std::vector<std::size_t>{0, 2, 4}));
  // A gentle arc of 10 degree turns: at alpha 175 every point stays (angle 170 < 175)...
  std::vector<Eigen::Vector3d> arc;
  for (int k = 0; k <= 6; ++k) arc.emplace_back(std::cos(k * 10.0 * kPi / 180.0), std::sin(k * 10.0 * kPi / 180.0), 0);
  EXPECT_EQ(mergeByAngle(arc, 175.0).size(), 7U);
  // ...at alpha 160 the angle at point 1 (170) merges it; then the merged chord 0-2 meets
  // 2-3 at 165 > 160, merged; chord 0-3 meets 3-4 at 160: kept (not greater).
  EXPECT_EQ(mergeByAngle(arc, 160.0), (std::vector<std::size_t>{0, 3, 6}));
}

TEST(SeedRule, DivisionByLengthCutsEveryMAlongTheCurve) {
  std::vector<double> ts;
  std::vector<Eigen::Vector3d> points;
  for (int k = 0; k <= 100; ++k) {
    ts.push_back(k / 100.0);
    points.emplace_back(10.0 * k / 100.0, 0, 0);  // 10 mm long
  }
  const auto cuts = divideByLength(ts, points, 3.0);
  ASSERT_EQ(cuts.size(), 5U);  // 0, 3, 6, 9, 10 mm
  EXPECT_NEAR(cuts[1], 0.3, 1e-12);
  EXPECT_NEAR(cuts[3], 0.9, 1e-12);
  EXPECT_DOUBLE_EQ(cuts.back(), 1.0);
  // A last piece under a quarter of M joins the one before it: 0, 3, 6, 10.
  EXPECT_EQ(divideByLength(ts, points, 3.3).size(), 4U);
}

// ---- leaves ---------------------------------------------------------------------------

LeafModel sampleLeaf(const std::string& name) {
  const LeafModel m = buildLeafModel(test::sample(name));
  return transformed(m, leafFrameFromDigitizer(m));
}

std::size_t triangles(const LeafMesh& m) {
  std::size_t n = 0;
  for (const Organ& o : m.organs) n += o.mesh.triangles.size();
  return n;
}

// Markers of a sample leaf moved by seeded noise (a different leaf each seed).
LeafModel noisyLeaf(const std::string& name, std::uint64_t seed, double sigma) {
  MarkerSet m = test::sample(name);
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0.0, sigma);
  for (MarkerRow& row : m.rows) {
    for (auto& p : row.pointsMm) p += Eigen::Vector3d(noise(rng), noise(rng), noise(rng));
  }
  const LeafModel leaf = buildLeafModel(m);
  return transformed(leaf, leafFrameFromDigitizer(leaf));
}

TEST(AdaptiveMesh, MeasuredHausdorffIsWithinTheAskedErrorOnSeededRandomLeaves) {
  int leaf = 0;
  for (const char* name : test::kSampleFiles) {
    for (double e : {0.1, 0.3}) {
      const MeshSubject subject(noisyLeaf(name, 1000 + static_cast<std::uint64_t>(leaf++), 0.25));
      ASSERT_LT(subject.referenceErrorMm(), e / 3.0);
      MeshOptions o;
      o.method = MeshMethod::Adaptive;
      o.maxErrorMm = e;
      const LeafMesh mesh = subject.mesh(o);
      const MeshDistance d = subject.measure(mesh, 60'000);
      EXPECT_LE(d.hausdorff, e) << name << " at E = " << e;
      // Not needlessly fine either: the farthest point uses at least a third of the budget.
      EXPECT_GT(d.hausdorff, e / 3.0) << name << " at E = " << e;
    }
  }
}

TEST(AdaptiveMesh, AtTheSameErrorItNeedsFarFewerTrianglesThanUniform) {
  const LeafModel leaf = sampleLeaf("upper-small-leaf-n17.markers.json");
  MeshOptions o;
  o.method = MeshMethod::Adaptive;
  o.maxErrorMm = 0.1;
  // The export resolution is itself about 0.1 mm from the exact surface (measured by the
  // study); the adaptive mesh needs well under half its triangles.
  EXPECT_LT(triangles(meshLeaf(leaf, o)),
            0.4 * static_cast<double>(triangles(meshLeaf(leaf, MeshResolution::preset("export")))));
  // A larger error, fewer triangles.
  MeshOptions coarse = o;
  coarse.maxErrorMm = 0.5;
  EXPECT_LT(triangles(meshLeaf(leaf, coarse)), triangles(meshLeaf(leaf, o)));
}

// Positions welded (the tip repeats), edges counted: a boundary edge has one triangle. Our
// meshers make no edge shared by more than two triangles (checked unless `othersMesh`: a
// peer's output, whose folds are counted in `folds`).
std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> boundaryEdges(const Mesh& mesh, bool othersMesh = false,
                                                                       int* folds = nullptr) {
  std::map<std::tuple<double, double, double>, std::uint32_t> weld;
  std::vector<std::uint32_t> id(mesh.positions.size());
  for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
    const auto& p = mesh.positions[v];
    id[v] = weld.try_emplace({p.x(), p.y(), p.z()}, static_cast<std::uint32_t>(v)).first->second;
  }
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> uses;
  for (const auto& t : mesh.triangles) {
    for (int k = 0; k < 3; ++k) {
      const auto e = std::minmax(id[t[k]], id[t[(k + 1) % 3]]);
      ++uses[{e.first, e.second}];
    }
  }
  std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> out;
  for (const auto& [e, n] : uses) {
    if (!othersMesh) {
      EXPECT_LE(n, 2) << "an edge shared by more than two triangles";
    }
    if (n > 2 && folds) ++*folds;
    if (n == 1) out.emplace_back(mesh.positions[e.first], mesh.positions[e.second]);
  }
  return out;
}

TEST(AdaptiveMesh, TheBladeHasNoCracksNoSliversAndNoFlippedTriangles) {
  for (const char* name : test::kSampleFiles) {
    const LeafModel leaf = sampleLeaf(name);
    const BladeSurface& blade = leaf.blade;
    const std::pair<Mesh, double> meshes[] = {{meshBladeAdaptive(blade, 0.1), 0.01},
                                              {meshBladeSeed(blade, {2.0, 170.0, 8}), 0.04}};
    for (const auto& [mesh, areaTolerance] : meshes) {
      // The margin and base row, densely: every boundary edge's ends lie on them.
      std::vector<Eigen::Vector3d> outline;
      const double u0 = blade.rowParameters.front();
      const double u1 = blade.rowParameters.back();
      const double v0 = blade.columnParameters.front();
      const double v1 = blade.columnParameters.back();
      for (int k = 0; k <= 4000; ++k) {
        const double f = k / 4000.0;
        outline.push_back(blade.evaluate(u0 + f * (u1 - u0), v0));
        outline.push_back(blade.evaluate(u0 + f * (u1 - u0), v1));
        outline.push_back(blade.evaluate(u1, v0 + f * (v1 - v0)));
      }
      auto nearOutline = [&](const Eigen::Vector3d& p) {  // distance to the outline's segments
        double best = 1e300;
        for (std::size_t k = 0; k + 3 < outline.size(); ++k) {
          const Eigen::Vector3d& a = outline[k];
          const Eigen::Vector3d d = outline[k + 3] - a;  // the next sample of the same line
          const double t = d.squaredNorm() > 0 ? std::clamp((p - a).dot(d) / d.squaredNorm(), 0.0, 1.0) : 0.0;
          best = std::min(best, (p - (a + t * d)).norm());
        }
        return best;
      };
      const auto edges = boundaryEdges(mesh);
      ASSERT_FALSE(edges.empty());
      for (const auto& [a, b] : edges) {
        EXPECT_LT(nearOutline(a), 1e-3) << name << ": a boundary vertex inside the blade (a crack)";
        EXPECT_LT(nearOutline(b), 1e-3) << name << ": a boundary vertex inside the blade (a crack)";
      }
      // Orientation: against the uniform blade's normals (which face the adaxial side).
      const Mesh uniform = meshBlade(blade, 3, 18);
      for (const auto& t : mesh.triangles) {
        const Eigen::Vector3d& a = mesh.positions[t[0]];
        const Eigen::Vector3d n = (mesh.positions[t[1]] - a).cross(mesh.positions[t[2]] - a);
        const double longest = std::max({(mesh.positions[t[1]] - a).norm(), (mesh.positions[t[2]] - a).norm(),
                                         (mesh.positions[t[2]] - mesh.positions[t[1]]).norm()});
        ASSERT_GT(n.norm(), 1e-9 * longest * longest) << name << ": a degenerate triangle";
        const Eigen::Vector3d centre = (a + mesh.positions[t[1]] + mesh.positions[t[2]]) / 3.0;
        std::size_t nearest = 0;
        for (std::size_t v = 1; v < uniform.positions.size(); ++v)
          if ((uniform.positions[v] - centre).squaredNorm() < (uniform.positions[nearest] - centre).squaredNorm())
            nearest = v;
        EXPECT_GT(n.normalized().dot(uniform.normals[nearest]), 0.0) << name << ": a flipped triangle";
      }
      // Same area as the exact blade, to the error's order: within 1 % for the adaptive mesh;
      // the seed's blade has no interior points (its flat triangles span the curved blade:
      // 1.6-3.0 % short on the samples), within 4 %.
      const double exact = surfaceArea(soupOf(meshBlade(blade, 30, 240)));
      EXPECT_NEAR(surfaceArea(soupOf(mesh)), exact, areaTolerance * exact) << name;
    }
  }
}

TEST(AdaptiveMesh, VeinRingsFollowTheRadiusAndTheMidribGetsMoreThanALateral) {
  const LeafModel leaf = sampleLeaf("upper-small-leaf-n17.markers.json");
  std::vector<Warning> warnings;
  const Mesh midrib = meshVeinAdaptive(leaf.veins.front(), 0.1, CapStyle::Sphere, warnings);
  const Mesh lateral = meshVeinAdaptive(leaf.veins[1], 0.1, CapStyle::Sphere, warnings);
  EXPECT_GT(midrib.triangles.size(), lateral.triangles.size());
  // The tube stays within E of the vein's balls: every vertex is within E of the envelope,
  // i.e. its distance to the nearest ball centre is the radius there, to E.
  for (const Mesh* m : {&midrib, &lateral}) {
    const Vein& vein = m == &midrib ? leaf.veins.front() : leaf.veins[1];
    for (const auto& p : m->positions) {
      double best = 1e300;
      for (int k = 0; k <= 2000; ++k) {
        const double t = k / 2000.0;
        best = std::min(best, std::abs((p - vein.curve.center(t)).norm() - vein.curve.radius(t)));
      }
      EXPECT_LT(best, 0.1);
    }
  }
  EXPECT_THROW((void)meshVeinAdaptive(leaf.veins.front(), 0.0, CapStyle::None, warnings), InputError);
}

TEST(SeedMesh, TheAxisOrganExperimentOfThePatentInShape) {
  // A gently curved vein: uniform rings every 2 mm, then the seed's merge at 175/170/160.
  std::vector<Ball> balls;
  for (int k = 0; k <= 6; ++k) {
    const double a = k * 0.08;
    balls.push_back({Eigen::Vector3d(100.0 * std::sin(a), 100.0 * (1.0 - std::cos(a)), 0.0), 1.5});
  }
  const Vein vein{"axis", BallBSplineCurve::interpolate(balls)};
  std::vector<Warning> warnings;
  std::size_t previous = meshVeinSeed(vein, {2.0, 180.0, 8}, CapStyle::None, warnings).triangles.size();
  for (double alpha : {175.0, 170.0, 160.0}) {
    const std::size_t n = meshVeinSeed(vein, {2.0, alpha, 8}, CapStyle::None, warnings).triangles.size();
    EXPECT_LT(n, previous) << "alpha " << alpha;
    previous = n;
  }
  EXPECT_GE(previous, 16U);  // at least one segment (two strips of 8)
}

TEST(SeedMesh, BadParametersAreRefusedWithTheOptionToChange) {
  const LeafModel leaf = sampleLeaf("lower-leaf-n10.markers.json");
  std::vector<Warning> w;
  try {
    (void)meshVeinSeed(leaf.veins.front(), {2.0, 170.0, 2}, CapStyle::None, w);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("--ring"), std::string::npos);
  }
  EXPECT_THROW((void)meshBladeSeed(leaf.blade, {0.0, 170.0, 8}), InputError);
  EXPECT_THROW((void)meshMethodFromString("fine"), leafdig::UnknownName);
}

TEST(MeshStudy, MeshoptimizerKeepsTheBorderAndReachesTheErrorOnALeaf) {
  const LeafModel leaf = sampleLeaf("lower-leaf-n10.markers.json");
  const MeshSubject subject(leaf);
  const LeafMesh simplified = simplifyWithMeshoptimizer(subject.reference(), 0.02);
  EXPECT_LT(triangles(simplified), triangles(subject.reference()) / 4);
  EXPECT_EQ(simplified.organs.size(), subject.reference().organs.size());
  // The blade's margin is locked: its boundary vertices are all still there. (meshoptimizer
  // may fold an edge between four triangles inside the blade: a peer's output, counted and
  // reported, not ours to repair.)
  const auto before = boundaryEdges(subject.reference().organs.back().mesh);
  int folds = 0;
  const auto after = boundaryEdges(simplified.organs.back().mesh, true, &folds);
  EXPECT_EQ(before.size(), after.size());
  std::printf("meshoptimizer: %d edge(s) shared by more than two triangles\n", folds);
  EXPECT_LT(subject.measure(simplified, 50'000).hausdorff, 0.2);
}

}  // namespace
}  // namespace leafdig::model

namespace leafdig::model {
namespace {

TEST(BladeEvaluate, ThePointEvaluatorAgreesWithTheGridSamplerForEveryBladeKind) {
  const MarkerSet markers = test::sample("upper-curved-leaf-n14.markers.json");
  std::vector<std::vector<double>> weights(markers.rows.size() + 1, std::vector<double>(7, 1.0));
  weights[3][2] = 2.5;
  weights[7][5] = 0.4;
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (BladeKind kind : {BladeKind::Interp, BladeKind::Approx, BladeKind::Bezier, BladeKind::Nurbs}) {
    const BladeSurface blade = buildBlade(markerGrid(markers), kind, kind == BladeKind::Nurbs ? &weights : nullptr);
    for (int k = 0; k < 200; ++k) {
      const double u = k == 0 ? blade.knotsU.back() : unit(rng);
      const double v = k == 0 ? blade.knotsV.back() : unit(rng);
      const Eigen::Vector3d grid = sampleSurface(blade, {u}, {v})[0][0];
      EXPECT_LT((blade.evaluate(u, v) - grid).norm(), 1e-9) << toString(kind) << " at " << u << ", " << v;
    }
  }
}

}  // namespace
}  // namespace leafdig::model
