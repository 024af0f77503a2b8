// Whole plants: placement, phyllotaxis, organ library draws, growth, plan checks, metrics,
// and the CARIBU and MTG exports read back by the strict readers of docs/plants.md "Formats".
#include "leafdig/model/plant/plant.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>

#include "../support/strict_formats.hpp"
#include "leafdig/model/errors.hpp"
#include "leafdig/model/io/plant_export.hpp"
#include "leafdig/model/metrics/metrics.hpp"
#include "leafdig/model/plant/plant_frame.hpp"
#include "test_support.hpp"

#define TINYGLTF_NO_STB_IMAGE
#define TINYGLTF_NO_STB_IMAGE_WRITE
#define TINYGLTF_NO_EXTERNAL_IMAGE
#include <tiny_gltf.h>  // the implementation is compiled into leafdig_model

namespace leafdig::model {
namespace {

namespace fs = std::filesystem;
constexpr double kPi = 3.14159265358979323846;

constexpr const char* kStraightStem = R"({"height": 900, "base_diameter": 24, "top_diameter": 8})";

std::string planText(const std::string& leaves, const std::string& extra = "",
                     const std::string& stem = kStraightStem) {
  return R"({"format": "leafdig.plant/1", "units": "mm", "id": "P-07", "seed": 42, "stem": )" + stem +
         R"(, "phyllotaxis": {"divergence_deg": 137.5078, "jitter_deg": 0}, "leaves": [)" + leaves + "]" + extra + "}";
}

std::string markersLeaf(int rank, double height, const std::string& more = "") {
  return R"({"rank": )" + std::to_string(rank) + R"(, "markers": "lower-leaf-n10.markers.json", "insertion_height": )" +
         std::to_string(height) + more + "}";
}

PlantPlan plan(const std::string& text) {
  return parsePlantPlan(text, "plan.json", fs::path(LEAFDIG_SOURCE_DIR) / "data" / "samples");
}

// A flat leaf (z = 0) as a library leaf of the given type.
LibraryLeaf flatLibraryLeaf(const std::string& type, int position) {
  MarkerSet m = test::flatTriangleLeaf(6, 8.0, 20.0);
  m.leaf.type = type;
  m.leaf.position = position;
  m.leaf.id = type + "-" + std::to_string(position);
  return {"test " + m.leaf.id, m};
}

double angleBetween(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::acos(std::clamp(a.normalized().dot(b.normalized()), -1.0, 1.0)) * 180.0 / kPi;
}

TEST(Plant, LeavesFollowTheGoldenAngleSitOnTheStemAndLeanAtTheirInclination) {
  std::string leaves;
  for (int k = 1; k <= 6; ++k)
    leaves += (k > 1 ? "," : "") + markersLeaf(k, 100.0 * k, ", \"inclination_deg\": " + std::to_string(20 + 10 * k));
  const Plant p = PlantBuilder(plan(planText(leaves)), {}).build();
  ASSERT_EQ(p.leaves.size(), 6u);
  for (const PlacedLeaf& l : p.leaves) {
    EXPECT_NEAR(l.azimuthDeg, std::fmod(l.rank * 137.5078, 360.0), 1e-9) << l.rank;
    // The base sits on the stem's surface at the insertion height, on the azimuth's side.
    const double radius = (24.0 + (8.0 - 24.0) * l.insertionHeightMm / 900.0) / 2.0;
    EXPECT_NEAR(l.base.z(), 100.0 * l.rank, 1e-9);
    EXPECT_NEAR(std::hypot(l.base.x(), l.base.y()), radius, 1e-9);
    EXPECT_NEAR(std::atan2(l.base.y(), l.base.x()) * 180 / kPi, l.azimuthDeg > 180 ? l.azimuthDeg - 360 : l.azimuthDeg,
                1e-9);
    // The base-to-tip chord makes the inclination with the stem axis, in the azimuth's plane.
    EXPECT_NEAR(angleBetween(l.tip - l.base, Eigen::Vector3d::UnitZ()), 20 + 10 * l.rank, 1e-6);
    const Eigen::Vector3d horizontal(l.tip.x() - l.base.x(), l.tip.y() - l.base.y(), 0);
    EXPECT_NEAR(angleBetween(horizontal, Eigen::Vector3d(l.base.x(), l.base.y(), 0)), 0.0, 1e-5);
    // A plant digitized in place measures the angles its plan placed the leaf at.
    const LeafPose measured = leafPose(l.base, l.tip);
    EXPECT_NEAR(measured.azimuthDeg, l.azimuthDeg, 1e-9);
    EXPECT_NEAR(measured.inclinationDeg, 20 + 10 * l.rank, 1e-6);
    // The model's P_N4 is the base, its tip the tip.
    EXPECT_LT((l.model.markers.rows.back().pointsMm[kMidribColumn] - l.base).norm(), 1e-9);
    EXPECT_LT((l.model.markers.tipMm - l.tip).norm(), 1e-9);
  }
}

TEST(Plant, ADigitizedStemCarriesItsLeavesOnItsSurfaceAtTheirLocalInclination) {
  // Two digitized points make the same straight taper as height and diameters.
  std::string leaves;
  for (int k = 1; k <= 4; ++k) leaves += (k > 1 ? "," : "") + markersLeaf(k, 150.0 * k);
  const std::string straight = planText(leaves);
  const std::string twoPoints = planText(leaves, "", R"({"points": [[10, 20, 5, 24], [10, 20, 905, 8]]})");
  const Plant a = PlantBuilder(plan(straight), {}).build();
  const Plant b = PlantBuilder(plan(twoPoints), {}).build();
  ASSERT_EQ(a.leaves.size(), b.leaves.size());
  for (std::size_t i = 0; i < a.leaves.size(); ++i) EXPECT_LT((a.leaves[i].tip - b.leaves[i].tip).norm(), 1e-6);

  // A stem digitized along a leaning arc: every base on the surface, every chord at its
  // inclination from the local axis.
  std::string arc = R"({"points": [)";
  for (int i = 0; i <= 6; ++i) {
    const double t = i / 6.0;
    arc += (i ? "," : "") + std::string("[") + std::to_string(200 * (1 - std::cos(t))) + ", 0, " +
           std::to_string(800 * std::sin(t)) + ", " + std::to_string(24 - 14 * t) + "]";
  }
  arc += "]}";
  std::string inclined;
  for (int k = 1; k <= 4; ++k) inclined += (k > 1 ? "," : "") + markersLeaf(k, 150.0 * k, R"(, "inclination_deg": 60)");
  const std::string curved = planText(inclined, "", arc);
  const Plant c = PlantBuilder(plan(curved), {}).build();
  for (const PlacedLeaf& l : c.leaves) {
    const StemPoint at = stemPointAt(c, l.insertionHeightMm / c.stemHeightMm);
    EXPECT_NEAR((l.base - at.center).norm(), at.radius, 1e-6);
    EXPECT_NEAR((l.base - at.center).dot(at.tangent), 0.0, 1e-6);
    EXPECT_NEAR(angleBetween(l.tip - l.base, at.tangent), 60.0, 1e-6);
    EXPECT_GT(at.tangent.x(), 0.01) << "the stem leans, so does its axis";
  }
  const std::string mtg =
      encodeMtg(c, computePlantMetrics(c, meshPlant(c, MeshResolution::preset("preview")), Eigen::Vector3d::UnitZ()));
  EXPECT_NO_THROW((void)leafdig::test::readMtgStrictly(mtg));
  EXPECT_THROW((void)plan(planText(leaves, "", R"({"points": [[0, 0, 0, 10]]})")), InputError);
  EXPECT_THROW((void)plan(planText(leaves, "", R"({"points": [[0, 0, 0, 10], [0, 0, 900, 0]]})")), InputError);
}

TEST(Plant, AFlatLeafLaidHorizontalShowsItsAdaxialSideUpAndRollTurnsIt) {
  const std::vector<LibraryLeaf> library{flatLibraryLeaf("lower", 1)};
  const std::string leaves =
      R"({"rank": 1, "library": {"type": "lower"}, "insertion_height": 100, "inclination_deg": 90},
         {"rank": 2, "library": {"type": "lower"}, "insertion_height": 200, "inclination_deg": 90, "roll_deg": 90})";
  const Plant p = PlantBuilder(plan(planText(leaves, R"(, "library": {"db": "x.sqlite"})")), library).build();
  const LeafMesh mesh = meshPlant(p, MeshResolution::preset("preview"));
  for (const Organ& o : mesh.organs) {
    if (o.kind != OrganKind::Blade) continue;
    for (const auto& t : o.mesh.triangles) {
      const Eigen::Vector3d n =
          (o.mesh.positions[t[1]] - o.mesh.positions[t[0]]).cross(o.mesh.positions[t[2]] - o.mesh.positions[t[0]]);
      if (o.leafRank == 1) {
        EXPECT_GT(n.normalized().z(), 0.999) << "adaxial side up";
      }
      if (o.leafRank == 2) {
        EXPECT_NEAR(n.normalized().z(), 0.0, 1e-9) << "rolled on its side";
      }
    }
  }
}

TEST(Plant, TheSamePlanAndSeedGiveTheSameBytesAndAnotherSeedOtherDraws) {
  const std::vector<LibraryLeaf> library{flatLibraryLeaf("lower", 1), flatLibraryLeaf("lower", 2),
                                         flatLibraryLeaf("upper", 7)};
  std::string leaves;
  for (int k = 1; k <= 8; ++k)
    leaves += std::string(k > 1 ? "," : "") + R"({"rank": )" + std::to_string(k) +
              R"(, "library": {"type": "lower"}, "insertion_height": )" + std::to_string(90 * k) + "}";
  const std::string extra =
      R"(, "library": {"db": "x.sqlite", "ranges": {"scale": [0.8, 1.2], "bend_deg": [0, 20],
         "azimuth_jitter_deg": [-10, 10], "inclination_deg": [40, 60]}})";
  std::string text = planText(leaves, extra);
  const auto encodeAll = [&](const std::string& t) {
    const Plant p = PlantBuilder(plan(t), library).build();
    const LeafMesh mesh = meshPlant(p, MeshResolution::preset("preview"));
    const PlantMetrics metrics = computePlantMetrics(p, mesh, Eigen::Vector3d::UnitZ());
    return encodePlantJson(p, metrics) + encodeCan(mesh, CanUnit::Metre).text + encodeMtg(p, metrics);
  };
  EXPECT_EQ(encodeAll(text), encodeAll(text));
  std::string other = text;
  other.replace(other.find("\"seed\": 42"), 10, "\"seed\": 43");
  EXPECT_NE(encodeAll(text), encodeAll(other));

  // Draws lie in their ranges, come from the requested type, and vary.
  const Plant p = PlantBuilder(plan(text), library).build();
  std::set<double> scales;
  std::set<std::string> sources;
  for (const PlacedLeaf& l : p.leaves) {
    EXPECT_GE(l.scale, 0.8);
    EXPECT_LE(l.scale, 1.2);
    EXPECT_GE(l.bendDeg, 0.0);
    EXPECT_LE(l.bendDeg, 20.0);
    EXPECT_GE(l.inclinationDeg, 40.0);
    EXPECT_LE(l.inclinationDeg, 60.0);
    double jitter = std::remainder(l.azimuthDeg - l.rank * 137.5078, 360.0);
    EXPECT_LE(std::abs(jitter), 10.0 + 1e-9);
    EXPECT_NE(l.source, "test upper-7");
    scales.insert(l.scale);
    sources.insert(l.source);
  }
  EXPECT_EQ(scales.size(), p.leaves.size()) << "every leaf draws its own scale";
  EXPECT_EQ(sources.size(), 2u) << "both lower leaves are drawn over eight ranks";

  // A leaf added at a new rank does not change the draws of the others.
  std::string more = planText(leaves + R"(, {"rank": 9, "library": {}, "insertion_height": 850})", extra);
  const Plant q = PlantBuilder(plan(more), library).build();
  for (std::size_t i = 0; i < p.leaves.size(); ++i) EXPECT_EQ(q.leaves[i].scale, p.leaves[i].scale);
}

TEST(Plant, LeavesGrowOnLogisticCurvesWidthLessThanLengthAndAppearOnePlastochronApart) {
  std::string leaves;
  for (int k = 1; k <= 5; ++k) leaves += (k > 1 ? "," : "") + markersLeaf(k, 150.0 * k);
  const std::string growth = R"(, "growth": {"time_unit": "days", "plastochron": 4, "leaf": {"rate": 0.3,
      "midpoint": 12}, "width_at_emergence": 0.4, "stem": {"rate": 0.12, "midpoint": 30}})";
  const PlantBuilder builder(plan(planText(leaves, growth)), {});
  const Plant final = builder.build();
  double lastStem = 0;
  std::vector<double> lastLength(6, 0.0), lastWidth(6, 0.0);
  for (double t = 0; t <= 120; t += 5) {
    const Plant p = builder.build(t);
    EXPECT_EQ(p.leaves.size(), std::min<std::size_t>(5, static_cast<std::size_t>(std::floor(t / 4)) + 1)) << t;
    EXPECT_GT(p.stemHeightMm, lastStem);
    lastStem = p.stemHeightMm;
    for (const PlacedLeaf& l : p.leaves) {
      const auto r = static_cast<std::size_t>(l.rank);
      EXPECT_GT(l.lengthFactor, lastLength[r]) << "monotone, rank " << l.rank << " t " << t;
      EXPECT_GT(l.widthFactor, l.lengthFactor) << "width starts larger, relatively";
      if (lastLength[r] > 0) {
        EXPECT_LT(l.widthFactor - lastWidth[r], l.lengthFactor - lastLength[r]);
      }
      lastLength[r] = l.lengthFactor;
      lastWidth[r] = l.widthFactor;
      const PlacedLeaf& f = final.leaves[r - 1];
      EXPECT_NEAR(l.lengthMm, f.lengthMm * l.lengthFactor, 0.01 * f.lengthMm) << "length follows its factor";
      EXPECT_NEAR(l.insertionHeightMm, f.insertionHeightMm * p.stemHeightMm / final.stemHeightMm, 1e-9);
    }
  }
  // The asymptote: late states approach the final plant.
  const Plant late = builder.build(400);
  EXPECT_NEAR(late.stemHeightMm, final.stemHeightMm, 1e-6 * final.stemHeightMm);
  for (std::size_t i = 0; i < late.leaves.size(); ++i)
    EXPECT_NEAR(late.leaves[i].lengthMm, final.leaves[i].lengthMm, 1e-6 * final.leaves[i].lengthMm);
  EXPECT_NEAR(logistic(0.3, 12, 12), 0.5, 1e-15);
  EXPECT_THROW((void)PlantBuilder(plan(planText(leaves)), {}).build(3.0), InputError) << "no growth in the plan";
}

TEST(Plant, EveryBadPlanIsRefusedNamingTheKey) {
  const std::string one = markersLeaf(1, 100);
  const std::vector<std::pair<std::string, std::string>> cases{
      {R"({"units": "mm", "id": "P", "stem": {"height": 9, "base_diameter": 1, "top_diameter": 1}, "leaves": [1]})",
       "format"},
      {R"({"format": "leafdig.markers/1"})", "format"},
      {R"({"format": "leafdig.plant/1", "units": "mm", "stem": {"height": 900, "base_diameter": 24,
          "top_diameter": 8}, "leaves": [)" +
           one + "]}",
       "id"},
      {R"({"format": "leafdig.plant/1", "units": "furlong", "id": "P"})", "units"},
      {R"({"format": "leafdig.plant/1", "units": "mm", "id": "P", "stem": {"base_diameter": 24, "top_diameter": 8},
          "leaves": [)" +
           one + "]}",
       "stem.height"},
      {planText(""), "leaves"},
      {planText(one + "," + markersLeaf(1, 200)), "rank 1 is given twice"},
      {planText(markersLeaf(1, 950)), "insertion_height"},
      {planText(R"({"rank": 1, "markers": "a.json"})"), "insertion_height"},
      {planText(R"({"rank": 1, "insertion_height": 10})"), "exactly one of"},
      {planText(R"({"rank": 1, "library": {"type": "lower"}, "insertion_height": 10})"), "library.db"},
      {planText(one, R"(, "library": {"db": "x", "ranges": {"scale": [1.2, 0.8]}})"), "library.ranges.scale"},
      {planText(one, R"(, "growth": {"plastochron": 4, "leaf": {"rate": 0.3}, "stem": {"rate": 1, "midpoint": 1}})"),
       "growth.leaf.midpoint"},
      {planText(one, R"(, "growth": {"plastochron": 4, "leaf": {"rate": 0.3, "midpoint": 3}, "width_at_emergence": 1.5,
          "stem": {"rate": 1, "midpoint": 1}})"),
       "width_at_emergence"},
      {planText(markersLeaf(1, 100, R"(, "inclination_deg": 200)")), "inclination_deg"},
      {"{not json", "plan.json"},
  };
  for (const auto& [text, expected] : cases) {
    try {
      (void)plan(text);
      ADD_FAILURE() << "accepted: " << text;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
    }
  }
  // Found only when the plant is assembled: no approved leaf of the requested type, a bad file.
  const std::string wantsUpper =
      planText(R"({"rank": 1, "library": {"type": "upper"}, "insertion_height": 10})", R"(, "library": {"db": "x"})");
  try {
    (void)PlantBuilder(plan(wantsUpper), {flatLibraryLeaf("lower", 1)});
    ADD_FAILURE() << "an empty draw was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("\"upper\""), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("sessions approve"), std::string::npos) << e.what();
  }
  const std::string missing = planText(R"({"rank": 1, "markers": "nowhere.json", "insertion_height": 10})");
  EXPECT_THROW((void)PlantBuilder(plan(missing), {}), InputError);
}

TEST(Plant, AFlatLeafSeenAlongItsNormalHasSilhouetteEqualToAreaAndEdgeOnNone) {
  const LeafModel leaf = buildLeafModel(test::flatTriangleLeaf(8, 10.0, 25.0));
  const Mesh blade = meshBlade(leaf.blade, 4, 24);
  const double area = meshArea(blade);
  EXPECT_NEAR(silhouetteArea({&blade}, Eigen::Vector3d::UnitZ()) / area, 1.0, 0.005);
  EXPECT_NEAR(silhouetteArea({&blade}, -Eigen::Vector3d::UnitZ()) / area, 1.0, 0.005);
  EXPECT_EQ(silhouetteArea({&blade}, Eigen::Vector3d::UnitX()), 0.0);
  // At 60° from the normal a flat leaf shows half its area.
  const Eigen::Vector3d slanted(std::sin(kPi / 3), 0, std::cos(kPi / 3));
  EXPECT_NEAR(silhouetteArea({&blade}, slanted) / area, 0.5, 0.005);
  // Two copies on top of each other count once.
  EXPECT_NEAR(silhouetteArea({&blade, &blade}, Eigen::Vector3d::UnitZ()) / area, 1.0, 0.005);
}

TEST(Plant, ALeafsSilhouetteAt1024PixelsIsWithinAFifthOfAPercentOf4096) {
  for (const char* name : test::kSampleFiles) {
    const LeafModel leaf = buildLeafModel(test::sample(name));
    const Mesh blade = meshBlade(leaf.blade, 10, 60);
    for (const Eigen::Vector3d& d : {Eigen::Vector3d(0, 0, 1), Eigen::Vector3d(0.3, -0.5, 0.8)}) {
      const double fine = silhouetteArea({&blade}, d, 4096);
      EXPECT_NEAR(silhouetteArea({&blade}, d, 1024) / fine, 1.0, 0.002) << name;
      EXPECT_LE(fine, projectedArea(blade, d) * (1 + 1e-3)) << "a silhouette never exceeds the projected area";
    }
  }
}

TEST(Plant, ThePlantsSilhouetteCountsOverlapsOnce) {
  std::string leaves;
  for (int k = 1; k <= 6; ++k) leaves += (k > 1 ? "," : "") + markersLeaf(k, 80.0 * k);
  const Plant p = PlantBuilder(plan(planText(leaves)), {}).build();
  const LeafMesh mesh = meshPlant(p, MeshResolution::preset("preview"));
  const PlantMetrics m = computePlantMetrics(p, mesh, Eigen::Vector3d::UnitZ());
  double sum = 0, largest = 0;
  for (const LeafLight& l : m.leaves) {
    EXPECT_GT(l.star, 0.0);
    EXPECT_LE(l.star, 1.0 + 1e-3);
    sum += l.silhouetteMm2;
    largest = std::max(largest, l.silhouetteMm2);
  }
  EXPECT_LT(m.silhouetteMm2, sum) << "six leaves on one stem overlap seen from above";
  EXPECT_GT(m.silhouetteMm2, largest);
  EXPECT_NEAR(m.star, m.silhouetteMm2 / m.areaMm2, 1e-12);
}

TEST(PlantExport, CaribuFilesPassTheStrictReaderWithUpperSidesFirstAndTheStemOpaque) {
  const std::vector<LibraryLeaf> library{flatLibraryLeaf("lower", 1)};
  const std::string leaves =
      R"({"rank": 1, "library": {}, "insertion_height": 100, "inclination_deg": 90},
         {"rank": 2, "markers": "upper-small-leaf-n17.markers.json", "insertion_height": 300})";
  const Plant p = PlantBuilder(plan(planText(leaves, R"(, "library": {"db": "x"})")), library).build();
  const LeafMesh mesh = meshPlant(p, MeshResolution::preset("export"));
  for (const CanUnit unit : {CanUnit::Metre, CanUnit::Centimetre}) {
    const CanFile can = encodeCan(mesh, unit);
    const leafdig::test::CaribuOpt opt = leafdig::test::readOptStrictly(encodeCaribuOpt());
    const std::vector<leafdig::test::CanTriangle> triangles = leafdig::test::readCanStrictly(can.text, opt);
    EXPECT_EQ(triangles.size(), can.triangles);
    std::size_t all = 0;
    for (const Organ& o : mesh.organs) all += o.mesh.triangles.size();
    EXPECT_EQ(can.triangles + can.dropped, all);
    EXPECT_EQ(can.dropped, 0u) << "the mesher makes no triangle that vanishes at micrometre precision";
    const double toMm = unit == CanUnit::Metre ? 1000.0 : 10.0;
    std::set<int> leavesSeen;
    for (const auto& t : triangles) {
      EXPECT_EQ(t.plant, 1);
      leavesSeen.insert(t.leaf);
      // The flat leaf laid horizontal: its blade (element after its veins) faces up.
      if (t.leaf == 1 && t.element == 2 * 6 + 3) {
        EXPECT_GT(t.normal()[2], 0.0) << t.label;
      }
      (void)toMm;
    }
    EXPECT_EQ(leavesSeen, (std::set<int>{0, 1, 2})) << "stem 000 (opaque), leaves by rank";
  }
}

TEST(PlantExport, EncodingManyFormatsOnSeveralThreadsGivesEachFormatsBytesInTheOrderAsked) {
  std::string leaves;
  for (int k = 1; k <= 3; ++k) leaves += (k > 1 ? "," : "") + markersLeaf(k, 150.0 * k);
  const Plant p = PlantBuilder(plan(planText(leaves)), {}).build();
  const LeafMesh mesh = meshPlant(p, MeshResolution::preset("preview"));
  const PlantMetrics metrics = computePlantMetrics(p, mesh, Eigen::Vector3d::UnitZ());
  const PlantExportOptions options{CanUnit::Metre, "test"};
  const std::vector<fs::path> paths{"a.json", "b.glb", "c.can", "d.mtg", "e.obj", "f.csv", "g.stl", "h.ply"};
  for (const unsigned threads : {1U, 2U, 5U}) {
    const std::vector<EncodedFile> files = encodePlantFiles(paths, p, mesh, metrics, options, threads);
    std::vector<EncodedFile> expected;
    for (const auto& path : paths)
      for (auto& f : encodePlant(path, p, mesh, metrics, options)) expected.push_back(std::move(f));
    ASSERT_EQ(files.size(), 9u) << "eight formats and the CARIBU .opt beside the .can";
    ASSERT_EQ(files.size(), expected.size());
    for (std::size_t i = 0; i < files.size(); ++i) {
      EXPECT_EQ(files[i].path, expected[i].path) << threads << " threads";
      EXPECT_TRUE(files[i].bytes == expected[i].bytes) << files[i].path << ", " << threads << " threads";
    }
  }
  // One bad path among good ones: its error, in the order asked, whatever finished first.
  EXPECT_THROW((void)encodePlantFiles({"a.glb", "b.txt", "c.obj", "d.doc"}, p, mesh, metrics, options, 2), InputError);
  try {
    (void)encodePlantFiles({"a.glb", "b.txt", "c.obj", "d.doc"}, p, mesh, metrics, options, 2);
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("b.txt"), std::string::npos) << e.what();
  }
}

TEST(PlantExport, TheMtgPassesTheStrictReaderWithEveryFeatureOnEveryLeaf) {
  std::string leaves;
  for (int k = 1; k <= 4; ++k) leaves += (k > 1 ? "," : "") + markersLeaf(k, 150.0 * k);
  const Plant p = PlantBuilder(plan(planText(leaves)), {}).build();
  const LeafMesh mesh = meshPlant(p, MeshResolution::preset("preview"));
  const PlantMetrics metrics = computePlantMetrics(p, mesh, Eigen::Vector3d::UnitZ());
  const leafdig::test::MtgFile mtg = leafdig::test::readMtgStrictly(encodeMtg(p, metrics));
  EXPECT_EQ(mtg.nbScales(), 3) << "$, plant, internode + leaf";
  std::size_t leafCount = 0, internodes = 0;
  for (const auto& e : mtg.entities) {
    if (e.symbol == 'I') ++internodes;
    if (e.symbol != 'L') continue;
    ++leafCount;
    EXPECT_EQ(e.relation, '+');
    EXPECT_EQ(mtg.entities[static_cast<std::size_t>(e.parent)].symbol, 'I');
    EXPECT_EQ(e.features.size(), mtg.features.size()) << "every declared feature on leaf " << e.index;
    const PlacedLeaf& l = p.leaves[static_cast<std::size_t>(std::stoi(e.features.at("rank")) - 1)];
    EXPECT_NEAR(std::stod(e.features.at("azimuth")), l.azimuthDeg, 5e-4);
    EXPECT_NEAR(std::stod(e.features.at("tip_z")), l.tip.z(), 5e-4);
    EXPECT_NEAR(std::stod(e.features.at("length")), l.lengthMm, 5e-4);
  }
  EXPECT_EQ(leafCount, 4u);
  EXPECT_EQ(internodes, 5u) << "one below each leaf, one up to the apex";
  // The reader is strict: a space, an exponent, an extra tab are each refused.
  const std::string good = encodeMtg(p, metrics);
  std::string spaced = good;
  spaced.replace(spaced.find("\t+L1"), 1, " ");
  EXPECT_THROW(leafdig::test::readMtgStrictly(spaced), std::runtime_error);
  std::string exponent = good;
  exponent.replace(exponent.find("150.000"), 7, "1.5e+02");
  EXPECT_THROW(leafdig::test::readMtgStrictly(exponent), std::runtime_error);
  std::string shifted = good;
  shifted.replace(shifted.find("\t+L1\t"), 5, "\t+L1\t\t");
  EXPECT_THROW(leafdig::test::readMtgStrictly(shifted), std::runtime_error);
}

// The animated glTF, decoded by tinygltf: at every key the leaf's node transform applied to
// its full-grown blade lands on the blade of that growth state, within 0.1 mm (the blade's
// chord-length parameters are not invariant under the anisotropic growth scale, so the exact
// state's surface differs from the scaled full-grown one by that much on a 600 mm leaf).
TEST(PlantExport, TheGrowthAnimationReproducesEachStatesBlade) {
  std::string leaves;
  for (int k = 1; k <= 3; ++k) leaves += (k > 1 ? "," : "") + markersLeaf(k, 200.0 * k);
  const std::string growth = R"(, "growth": {"plastochron": 4, "leaf": {"rate": 0.3, "midpoint": 12},
      "stem": {"rate": 0.12, "midpoint": 30}})";
  const PlantBuilder builder(plan(planText(leaves, growth)), {});
  const Plant final = builder.build();
  std::vector<Plant> states;
  for (double t = 0; t <= 40; t += 10) states.push_back(builder.build(t));
  MeshOptions res;
  res.resolution = MeshResolution::preset("preview");
  const std::string glb = encodeGrowthGlb(final, states, res, "test");

  tinygltf::Model model;
  tinygltf::TinyGLTF loader;
  std::string err, warn;
  ASSERT_TRUE(loader.LoadBinaryFromMemory(&model, &err, &warn, reinterpret_cast<const unsigned char*>(glb.data()),
                                          static_cast<unsigned>(glb.size())))
      << err;
  ASSERT_EQ(model.animations.size(), 1u);
  const auto floats = [&model](int accessor) {
    const auto& a = model.accessors[static_cast<std::size_t>(accessor)];
    const auto& v = model.bufferViews[static_cast<std::size_t>(a.bufferView)];
    const auto* p = reinterpret_cast<const float*>(model.buffers[0].data.data() + v.byteOffset + a.byteOffset);
    const std::size_t n = a.count * (a.type == TINYGLTF_TYPE_VEC3 ? 3 : a.type == TINYGLTF_TYPE_VEC4 ? 4 : 1);
    return std::vector<float>(p, p + n);
  };
  const auto nodeNamed = [&model](const std::string& name) {
    for (std::size_t i = 0; i < model.nodes.size(); ++i)
      if (model.nodes[i].name == name) return static_cast<int>(i);
    return -1;
  };
  const auto channel = [&](int node, const std::string& path) {
    for (const auto& c : model.animations[0].channels)
      if (c.target_node == node && c.target_path == path)
        return floats(model.animations[0].samplers[static_cast<std::size_t>(c.sampler)].output);
    return std::vector<float>{};
  };
  const int place = nodeNamed("plant/leaf-2");
  const int grow = nodeNamed("plant/leaf-2/growth");
  const int blade = nodeNamed("plant/leaf-2/blade");
  ASSERT_GE(place, 0);
  ASSERT_GE(grow, 0);
  ASSERT_GE(blade, 0);
  const auto translation = channel(place, "translation");
  const auto scale = channel(grow, "scale");
  ASSERT_EQ(translation.size(), 3 * states.size());
  ASSERT_EQ(scale.size(), 3 * states.size());
  const auto rotation = channel(place, "rotation");
  ASSERT_EQ(rotation.size(), 4 * states.size());
  const auto& prim =
      model.meshes[static_cast<std::size_t>(model.nodes[static_cast<std::size_t>(blade)].mesh)].primitives[0];
  const auto full = floats(prim.attributes.at("POSITION"));
  for (std::size_t i = 0; i < states.size(); ++i) {
    const PlacedLeaf* leaf = nullptr;
    for (const PlacedLeaf& l : states[i].leaves)
      if (l.rank == 2) leaf = &l;
    if (leaf == nullptr) {
      EXPECT_LT(scale[3 * i], 1e-5) << "not yet appeared: shrunk to nothing";
      continue;
    }
    const Eigen::Quaterniond q(rotation[4 * i + 3], rotation[4 * i], rotation[4 * i + 1], rotation[4 * i + 2]);
    const Mesh expected =
        meshBlade(leaf->model.blade, res.resolution.bladeSegmentsPerRow, res.resolution.bladeSegmentsAcross);
    ASSERT_EQ(full.size(), 3 * expected.positions.size());
    for (std::size_t v = 0; v < expected.positions.size(); v += 97) {
      const Eigen::Vector3d local(full[3 * v] * scale[3 * i], full[3 * v + 1] * scale[3 * i + 1],
                                  full[3 * v + 2] * scale[3 * i + 2]);
      const Eigen::Vector3d world =
          q * local + Eigen::Vector3d(translation[3 * i], translation[3 * i + 1], translation[3 * i + 2]);
      const Eigen::Vector3d want = toGltfAxes(expected.positions[v]) * 1e-3;
      // A visual: within 0.5 mm of the state rebuilt from its markers (0.4 mm at worst on the
      // samples: the blade's chord-length parameters do not follow an anisotropic scale).
      EXPECT_LT((world - want).norm(), 5e-4) << "state " << i << " vertex " << v;
    }
  }
}

TEST(Mesh, TheBladeMeshesOfTheSamplesHaveNoDegenerateTriangles) {
  for (const char* name : test::kSampleFiles) {
    const LeafModel digitizer = buildLeafModel(test::sample(name));
    // In the leaf frame (every leaf of a plant is first put there) the tip row's repeated
    // points differ by rounding: the mesher must still see those triangles as degenerate.
    for (const LeafModel& leaf : {digitizer, transformed(digitizer, leafFrameFromDigitizer(digitizer))})
      for (const char* preset : {"paper", "preview", "export"}) {
        const MeshResolution r = MeshResolution::preset(preset);
        const Mesh blade = meshBlade(leaf.blade, r.bladeSegmentsPerRow, r.bladeSegmentsAcross);
        for (const auto& t : blade.triangles) {
          const Eigen::Vector3d a = blade.positions[t[0]], b = blade.positions[t[1]], c = blade.positions[t[2]];
          const double longest = std::max({(b - a).norm(), (c - b).norm(), (a - c).norm()});
          const double area = 0.5 * (b - a).cross(c - a).norm();
          // Height over the longest edge at least 0.1 µm: nothing that rounds away in an export.
          EXPECT_GT(2 * area / longest, 1e-4) << name << " " << preset;
        }
      }
  }
}

}  // namespace
}  // namespace leafdig::model
