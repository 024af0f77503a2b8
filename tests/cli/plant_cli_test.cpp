// `leafdig plant build|grow` driven as a modeller would: a plan file, every export format,
// each opened by an independent reader (Khronos glTF validator, assimp, the strict MTG and
// CARIBU readers of docs/plants.md "Formats"), reproducibility, bad plans, growth series, the organ library.
#include <cmath>
#include <csignal>
#include <cstring>
#include <map>
#include <random>
#include <set>
#include <thread>
#include <tuple>

#include "../support/strict_formats.hpp"
#include "cli_support.hpp"

namespace {

class PlantCli : public Cli {
 protected:
  // The sample plan with its leaf paths made absolute, written into the test's folder.
  fs::path samplePlan() {
    std::string text = slurp(std::string(LEAFDIG_SOURCE_DIR) + "/data/plants/tobacco-p07.plant.json");
    const std::string samples = std::string(LEAFDIG_SOURCE_DIR) + "/data/samples/";
    for (std::size_t at; (at = text.find("../samples/")) != std::string::npos;) text.replace(at, 11, samples);
    return write("plan.json", text);
  }
  fs::path write(const std::string& name, const std::string& text) {
    const fs::path p = dir_ / name;
    std::ofstream(p) << text;
    return p;
  }
  // A synthetic plant of known truth as a plant-markers file in the test's folder.
  fs::path synthPlant(int seed, int nodes) {
    const fs::path markers = dir_ / ("plant-" + std::to_string(seed) + ".plant-markers.json");
    const fs::path truth = dir_ / ("plant-" + std::to_string(seed) + ".truth.json");
    const Result r = leafdig("synth plant --markers " + quote(markers) + " --truth " + quote(truth) + " --nodes " +
                             std::to_string(nodes) + " --seed " + std::to_string(seed) + " --date 2026-06-12");
    EXPECT_EQ(r.exitCode, 0) << r.err;
    return markers;
  }
};

TEST_F(PlantCli, EveryExportOfTheSamplePlantOpensInAnIndependentReader) {
  const fs::path plan = samplePlan();
  std::string outputs;
  for (const char* ext : {"glb", "obj", "ply", "stl", "can", "mtg", "csv", "json"})
    outputs += " -o " + quote(dir_ / (std::string("p07.") + ext));
  const Result r = leafdig("plant build " + quote(plan) + outputs + " --resolution preview --json");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const json report = json::parse(r.out);
  const json& state = report["states"][0];
  ASSERT_EQ(state["leaves"].size(), 6u);
  const long triangles = state["triangles"].get<long>();
  for (const char* timing : {"build", "mesh", "metrics", "encode", "write"})
    EXPECT_GE(report["timings_ms"][timing].get<double>(), 0.0) << timing;
  EXPECT_GT(state["metrics"]["star"].get<double>(), 0.3);
  EXPECT_LT(state["metrics"]["star"].get<double>(), 1.0);

  // glTF: the Khronos validator, and a named node per organ.
  const std::string validator = std::string(LEAFDIG_SOURCE_DIR) + "/tests/tools/validate-gltf.mjs";
  const Result check = run("node " + quote(validator) + " " + quote(dir_ / "p07.glb"));
  ASSERT_EQ(check.exitCode, 0) << check.out << check.err;
  EXPECT_EQ(json::parse(check.out)["numErrors"], 0) << check.out;
  const std::string glb = slurp(dir_ / "p07.glb");
  for (const char* node : {"\"plant/stem\"", "\"plant/leaf-1/blade\"", "\"plant/leaf-6/midrib\"", "\"P-07\""})
    EXPECT_NE(glb.find(node), std::string::npos) << node;

  // OBJ, PLY, STL: assimp, with the triangle count the command reported.
  ASSERT_EQ(run("command -v assimp").exitCode, 0) << "assimp is not installed: run scripts/setup.sh";
  const auto count = [&](const char* ext, const std::string& key) {
    const std::string out = run("assimp info " + quote(dir_ / (std::string("p07.") + ext)) + " -r").out;
    const std::size_t at = out.find("\n" + key + ":");
    return at == std::string::npos ? -1L : std::stol(out.substr(at + key.size() + 2));
  };
  EXPECT_EQ(count("obj", "Faces"), triangles);
  EXPECT_EQ(count("ply", "Faces"), triangles);
  EXPECT_EQ(count("stl", "Faces"), triangles);
  const std::string ply = slurp(dir_ / "p07.ply");
  EXPECT_NE(ply.find("property int leaf_rank"), std::string::npos);
  EXPECT_NE(ply.find("comment organ_id 0 plant/stem"), std::string::npos);
  EXPECT_NE(slurp(dir_ / "p07.obj").find("o plant/leaf-3/blade"), std::string::npos);

  // CARIBU: the strict reader, every triangle kept, stem opaque, leaves by rank.
  const auto opt = leafdig::test::readOptStrictly(slurp(dir_ / "p07.opt"));
  const auto can = leafdig::test::readCanStrictly(slurp(dir_ / "p07.can"), opt);
  EXPECT_EQ(static_cast<long>(can.size()), triangles);
  std::set<int> leaves;
  for (const auto& t : can) leaves.insert(t.leaf);
  EXPECT_EQ(leaves, (std::set<int>{0, 1, 2, 3, 4, 5, 6}));

  // MTG: the strict reader; the plan's leaves with every feature.
  const auto mtg = leafdig::test::readMtgStrictly(slurp(dir_ / "p07.mtg"));
  int leafEntities = 0;
  for (const auto& e : mtg.entities)
    if (e.symbol == 'L') {
      ++leafEntities;
      EXPECT_EQ(e.features.size(), mtg.features.size());
    }
  EXPECT_EQ(leafEntities, 6);

  // CSV: a header, the stem, six leaves; the JSON document: placements and models.
  const std::string csv = slurp(dir_ / "p07.csv");
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 8);
  const json doc = json::parse(slurp(dir_ / "p07.json"));
  EXPECT_EQ(doc["format"], "leafdig.plant-model/1");
  ASSERT_EQ(doc["leaves"].size(), 6u);
  EXPECT_EQ(doc["leaves"][0]["placement"].size(), 4u);
  EXPECT_EQ(doc["leaves"][0]["model"]["format"], "leafdig.model/1");
  EXPECT_NEAR(doc["leaves"][3]["bend_deg"].get<double>(), 10.0, 1e-12);
}

// Helios XML and VegeSTAR (issue 51): each read by a strict reader of its reader's rules (Helios's
// loadXML: each triangle from its transform of the unit triangle; PlantGL's and PyRATP's VGX),
// every triangle there with its organ, and the two files the same triangles (metres against
// centimetres with Z down) as the leaf areas the command reported.
TEST_F(PlantCli, TheSamplePlantGoesToHeliosAndVegestarWithItsOrgans) {
  const fs::path plan = samplePlan();
  const Result r = leafdig("plant build " + quote(plan) + " -o " + quote(dir_ / "p07.xml") + " -o " +
                           quote(dir_ / "p07.vgx") + " --resolution preview --json");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const json state = json::parse(r.out)["states"][0];
  const auto helios = leafdig::test::readHeliosStrictly(slurp(dir_ / "p07.xml"));
  const auto vgx = leafdig::test::readVgxStrictly(slurp(dir_ / "p07.vgx"));
  ASSERT_EQ(static_cast<long>(helios.triangles.size()), state["triangles"].get<long>());
  ASSERT_EQ(vgx.size(), helios.triangles.size());
  std::set<long> leaves;
  std::map<long, double> bladeArea;  // by leaf, m²
  for (std::size_t i = 0; i < helios.triangles.size(); ++i) {
    const auto& t = helios.triangles[i];
    leaves.insert(t.data.at("leafID"));
    EXPECT_EQ(t.data.at("plantID"), 1);
    const auto& object = helios.objects.at(t.objID);
    EXPECT_EQ(object.at("leafID"), std::to_string(t.data.at("leafID")));
    const auto v = vgx[i].triangle();
    for (std::size_t k = 0; k < 3; ++k) {
      EXPECT_NEAR(v[k][0], t.v[k][0] * 100, 2e-4) << "triangle " << i;
      EXPECT_NEAR(v[k][1], t.v[k][1] * 100, 2e-4) << "triangle " << i;
      EXPECT_NEAR(v[k][2], -t.v[k][2] * 100, 2e-4) << "triangle " << i << ": VegeSTAR's Z points down";
    }
    EXPECT_EQ(vgx[i].value.at("Grp2"), 1);
    const std::string& organ = object.at("organ");
    if (organ.size() > 6 && organ.compare(organ.size() - 6, 6, "/blade") == 0) {
      const std::array<double, 3> a{t.v[1][0] - t.v[0][0], t.v[1][1] - t.v[0][1], t.v[1][2] - t.v[0][2]};
      const std::array<double, 3> b{t.v[2][0] - t.v[0][0], t.v[2][1] - t.v[0][1], t.v[2][2] - t.v[0][2]};
      const std::array<double, 3> n{a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
      bladeArea[t.data.at("leafID")] += 0.5 * std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
      // A leaf row's area for RATP: EchX · EchY · 0.7 in cm².
      EXPECT_NEAR(vgx[i].value.at("EchX") * vgx[i].value.at("EchY") * 0.7,
                  0.5 * std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]) * 1e4, 2e-3);
    }
  }
  EXPECT_EQ(leaves, (std::set<long>{0, 1, 2, 3, 4, 5, 6}));
  for (const auto& leaf : state["leaves"]) {
    const long rank = leaf["rank"];
    EXPECT_NEAR(bladeArea[rank] * 1e6, leaf["area_mm2"].get<double>(), 1e-4 * leaf["area_mm2"].get<double>())
        << "leaf " << rank;
  }
  // Every plant above the ground is below VegeSTAR's zero.
  for (const auto& row : vgx) EXPECT_LE(row.value.at("TransZ"), 1e-9);
}

TEST_F(PlantCli, TheSamePlanTwiceGivesByteIdenticalFiles) {
  const fs::path plan = samplePlan();
  for (const char* run : {"a", "b"}) {
    std::string outputs;
    for (const char* ext : {"glb", "ply", "can", "mtg", "csv", "json"})
      outputs += " -o " + quote(dir_ / (std::string(run) + "." + ext));
    ASSERT_EQ(leafdig("plant build " + quote(plan) + outputs + " --resolution preview").exitCode, 0);
  }
  for (const char* ext : {"glb", "ply", "can", "opt", "mtg", "csv", "json"})
    EXPECT_EQ(slurp(dir_ / (std::string("a.") + ext)), slurp(dir_ / (std::string("b.") + ext))) << ext;
}

TEST_F(PlantCli, ABadPlanExitsTwoNamingTheProblemAndWritesNothing) {
  const fs::path out = dir_ / "never.glb";
  const fs::path twice = write("twice.json", R"({"format": "leafdig.plant/1", "units": "mm", "id": "P",
      "stem": {"height": 500, "base_diameter": 20, "top_diameter": 8},
      "leaves": [{"rank": 1, "markers": "a.json", "insertion_height": 10},
                 {"rank": 1, "markers": "a.json", "insertion_height": 20}]})");
  Result r = leafdig("plant build " + quote(twice) + " -o " + quote(out));
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_NE(r.err.find("rank 1 is given twice"), std::string::npos) << r.err;
  const fs::path above = write("above.json", R"({"format": "leafdig.plant/1", "units": "cm", "id": "P",
      "stem": {"height": 50, "base_diameter": 2, "top_diameter": 0.8},
      "leaves": [{"rank": 1, "markers": "a.json", "insertion_height": 60}]})");
  r = leafdig("plant build " + quote(above) + " -o " + quote(out));
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_NE(r.err.find("600 mm is outside the stem"), std::string::npos) << r.err;
  r = leafdig("plant build " + quote(samplePlan()) + " -o " + quote(dir_ / "plant.3ds"));
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_NE(r.err.find(".3ds"), std::string::npos) << r.err;
  r = leafdig("plant build " + quote(dir_ / "missing.json") + " -o " + quote(out));
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_NE(r.err.find("missing.json"), std::string::npos) << r.err;
  const fs::path noLibrary = write("nolib.json", R"({"format": "leafdig.plant/1", "units": "mm", "id": "P",
      "stem": {"height": 500, "base_diameter": 20, "top_diameter": 8},
      "leaves": [{"rank": 1, "library": {"type": "lower"}, "insertion_height": 10}],
      "library": {"db": "nowhere.sqlite"}})");
  r = leafdig("plant build " + quote(noLibrary) + " -o " + quote(out));
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_NE(r.err.find("nowhere.sqlite does not exist"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir_ / "nowhere.sqlite")) << "a missing library is not created";
  EXPECT_FALSE(fs::exists(out));
}

TEST_F(PlantCli, AGrowthSeriesWritesOneFilePerTimeAndGrowsMonotonically) {
  const fs::path plan = samplePlan();
  const Result r =
      leafdig("plant grow " + quote(plan) + " --times 0:60:5 --resolution preview --json -o " +
              quote(dir_ / "series" / "plant-{t}.glb") + " -o " + quote(dir_ / "series" / "plant-{t}.csv"));
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const json report = json::parse(r.out);
  ASSERT_EQ(report["states"].size(), 13u);
  double lastArea = 0, lastHeight = 0;
  for (const auto& s : report["states"]) {
    EXPECT_GT(s["metrics"]["area_mm2"].get<double>(), lastArea);
    EXPECT_GT(s["stem_height_mm"].get<double>(), lastHeight);
    lastArea = s["metrics"]["area_mm2"];
    lastHeight = s["stem_height_mm"];
  }
  EXPECT_EQ(report["states"][0]["leaves"].size(), 1u) << "one leaf at t = 0, a new one every 4 days";
  EXPECT_EQ(report["states"][12]["leaves"].size(), 6u);
  for (const char* t : {"0", "5", "30", "60"}) {
    EXPECT_TRUE(fs::exists(dir_ / "series" / ("plant-" + std::string(t) + ".glb"))) << t;
    EXPECT_TRUE(fs::exists(dir_ / "series" / ("plant-" + std::string(t) + ".csv"))) << t;
  }
  const std::string validator = std::string(LEAFDIG_SOURCE_DIR) + "/tests/tools/validate-gltf.mjs";
  const Result check = run("node " + quote(validator) + " " + quote(dir_ / "series" / "plant-5.glb"));
  EXPECT_EQ(json::parse(check.out)["numErrors"], 0) << check.out;

  // One animated glTF for the whole series: valid, with its growth animation.
  const Result animated = leafdig("plant grow " + quote(plan) + " --times 0:60:5 --animate --resolution preview -o " +
                                  quote(dir_ / "growth.glb"));
  ASSERT_EQ(animated.exitCode, 0) << animated.err;
  const Result checkAnimated = run("node " + quote(validator) + " " + quote(dir_ / "growth.glb"));
  ASSERT_EQ(checkAnimated.exitCode, 0) << checkAnimated.out << checkAnimated.err;
  const json animatedReport = json::parse(checkAnimated.out);
  EXPECT_EQ(animatedReport["numErrors"], 0) << checkAnimated.out;
  EXPECT_EQ(animatedReport["numWarnings"], 0) << checkAnimated.out;
  EXPECT_NE(slurp(dir_ / "growth.glb").find("\"growth\""), std::string::npos);
  EXPECT_EQ(leafdig("plant grow " + quote(plan) + " --times 0:60:5 --animate -o " + quote(dir_ / "g.obj")).exitCode, 2);

  const Result noPattern = leafdig("plant grow " + quote(plan) + " --times 0:60:5 -o " + quote(dir_ / "x.glb"));
  EXPECT_EQ(noPattern.exitCode, 2);
  EXPECT_NE(noPattern.err.find("{t}"), std::string::npos) << noPattern.err;
  const Result badTimes = leafdig("plant grow " + quote(plan) + " --times 0:60 -o " + quote(dir_ / "x-{t}.glb"));
  EXPECT_EQ(badTimes.exitCode, 2);
  EXPECT_NE(badTimes.err.find("start:end:step"), std::string::npos) << badTimes.err;
}

TEST_F(PlantCli, LibraryLeavesAreDrawnFromApprovedSessionsOfTheRequestedType) {
  const fs::path db = dir_ / "station.sqlite";
  ASSERT_EQ(leafdig("capture --simulate --speed 30 --no-mistakes --db " + quote(db) +
                    " --plant P1 --leaf-position 2 --leaf-type lower </dev/null")
                .exitCode,
            0);
  ASSERT_EQ(leafdig("capture --simulate --speed 30 --no-mistakes --markers " +
                    quote(std::string(LEAFDIG_SOURCE_DIR) + "/data/samples/upper-small-leaf-n17.markers.json") +
                    " --db " + quote(db) + " --plant P1 --leaf-position 9 --leaf-type upper </dev/null")
                .exitCode,
            0);
  ASSERT_EQ(leafdig("capture --simulate --speed 30 --no-mistakes --db " + quote(db) +
                    " --plant P2 --leaf-position 3 --leaf-type lower </dev/null")
                .exitCode,
            0);
  const fs::path plan = write("library.json", R"({"format": "leafdig.plant/1", "units": "mm", "id": "P-lib",
      "seed": 11, "stem": {"height": 900, "base_diameter": 24, "top_diameter": 8},
      "leaves": [{"rank": 1, "library": {"type": "lower"}, "insertion_height": 150},
                 {"rank": 2, "library": {"type": "upper"}, "insertion_height": 500}],
      "library": {"db": "station.sqlite", "ranges": {"scale": [0.9, 1.1]}}})");
  // Nothing approved yet: the draw names what is missing.
  Result r = leafdig("plant build " + quote(plan) + " -o " + quote(dir_ / "p.csv"));
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_NE(r.err.find("sessions approve"), std::string::npos) << r.err;
  for (const char* id : {"1", "2"})
    ASSERT_EQ(leafdig("sessions approve " + std::string(id) + " --who cur --db " + quote(db)).exitCode, 0);
  r = leafdig("plant build " + quote(plan) + " --json -o " + quote(dir_ / "p.csv"));
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const json leaves = json::parse(r.out)["states"][0]["leaves"];
  EXPECT_EQ(leaves[0]["source"], "session 1") << "the only approved lower leaf (session 3 is not approved)";
  EXPECT_EQ(leaves[1]["source"], "session 2");
  for (const auto& l : leaves) {
    EXPECT_GE(l["scale"].get<double>(), 0.9);
    EXPECT_LE(l["scale"].get<double>(), 1.1);
  }
}

TEST_F(PlantCli, ASingleLeafExportsToCaribuMtgAndCsvToo) {
  const std::string markers = std::string(LEAFDIG_SOURCE_DIR) + "/data/samples/upper-curved-leaf-n14.markers.json";
  const Result r =
      leafdig("model build " + quote(markers) + " --frame leaf --resolution preview --json -o " +
              quote(dir_ / "leaf.can") + " -o " + quote(dir_ / "leaf.mtg") + " -o " + quote(dir_ / "leaf.csv"));
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const json counts = json::parse(r.out)["mesh"];
  const auto opt = leafdig::test::readOptStrictly(slurp(dir_ / "leaf.opt"));
  const auto can = leafdig::test::readCanStrictly(slurp(dir_ / "leaf.can"), opt);
  EXPECT_EQ(static_cast<long>(can.size()),
            counts["veins"]["triangles"].get<long>() + counts["blade"]["triangles"].get<long>());
  for (const auto& t : can) EXPECT_NE(t.leaf, 0) << "a leaf is translucent, never the opaque 000";
  const auto mtg = leafdig::test::readMtgStrictly(slurp(dir_ / "leaf.mtg"));
  ASSERT_EQ(mtg.entities.size(), 2u) << "P1 and its leaf";
  EXPECT_EQ(mtg.entities[1].symbol, 'L');
  EXPECT_EQ(mtg.entities[1].features.size(), mtg.features.size());
  const std::string csv = slurp(dir_ / "leaf.csv");
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 2) << csv;
  // The leaf's row carries its blade area's 95 % interval, around the area, read by Python's
  // csv module.
  const Result interval =
      run("python3 -c \"import csv,sys; r=[x for x in csv.DictReader(open(sys.argv[1])) if x['organ']=='leaf'][0]; "
          "print(r['blade_area_low95_mm2'], r['area_mm2'], r['blade_area_high95_mm2'])\" " +
          quote(dir_ / "leaf.csv"));
  ASSERT_EQ(interval.exitCode, 0) << interval.err;
  std::istringstream values(interval.out);
  double low = 0, area = 0, high = 0;
  values >> low >> area >> high;
  EXPECT_GT(low, 0.0);
  EXPECT_LT(low, high);
  EXPECT_NEAR(area, 0.5 * (low + high), 0.05 * area);
  const Result json = leafdig("model build " + quote(markers) + " -o " + quote(dir_ / "leaf.json"));
  EXPECT_EQ(json.exitCode, 2);
  EXPECT_NE(json.err.find("--model-json"), std::string::npos) << json.err;
}

}  // namespace

namespace {

// A CARIBU-style interception from above: the .can's triangles (read strictly, in metres)
// projected onto the ground on a 0.25 mm grid, every grid point under any triangle counted
// once: the area a parallel light from +Z would lose to the leaf. Independent of leafdig's
// silhouette raster (another grid, another inside test, the exported single-precision file).
double interceptionFromAboveMm2(const std::vector<leafdig::test::CanTriangle>& triangles) {
  double lo[2] = {1e300, 1e300}, hi[2] = {-1e300, -1e300};
  for (const auto& t : triangles)
    for (const auto& v : t.v)
      for (int k = 0; k < 2; ++k) {
        lo[k] = std::min(lo[k], 1000.0 * v[static_cast<std::size_t>(k)]);
        hi[k] = std::max(hi[k], 1000.0 * v[static_cast<std::size_t>(k)]);
      }
  const double h = 0.25;
  const auto nx = static_cast<std::size_t>((hi[0] - lo[0]) / h) + 2,
             ny = static_cast<std::size_t>((hi[1] - lo[1]) / h) + 2;
  std::vector<char> covered(nx * ny, 0);
  for (const auto& t : triangles) {
    double x[3], y[3];
    for (int k = 0; k < 3; ++k) {
      x[k] = 1000.0 * t.v[static_cast<std::size_t>(k)][0];
      y[k] = 1000.0 * t.v[static_cast<std::size_t>(k)][1];
    }
    const double d = (y[1] - y[2]) * (x[0] - x[2]) + (x[2] - x[1]) * (y[0] - y[2]);
    if (d == 0) continue;  // edge-on from above
    const auto i0 = static_cast<std::size_t>((std::min({x[0], x[1], x[2]}) - lo[0]) / h);
    const auto i1 = static_cast<std::size_t>((std::max({x[0], x[1], x[2]}) - lo[0]) / h) + 1;
    const auto j0 = static_cast<std::size_t>((std::min({y[0], y[1], y[2]}) - lo[1]) / h);
    const auto j1 = static_cast<std::size_t>((std::max({y[0], y[1], y[2]}) - lo[1]) / h) + 1;
    for (std::size_t j = j0; j <= j1 && j < ny; ++j)
      for (std::size_t i = i0; i <= i1 && i < nx; ++i) {
        const double px = lo[0] + (static_cast<double>(i) + 0.5) * h, py = lo[1] + (static_cast<double>(j) + 0.5) * h;
        const double a = ((y[1] - y[2]) * (px - x[2]) + (x[2] - x[1]) * (py - y[2])) / d;
        const double b = ((y[2] - y[0]) * (px - x[2]) + (x[0] - x[2]) * (py - y[2])) / d;
        if (a >= 0 && b >= 0 && a + b <= 1) covered[j * nx + i] = 1;
      }
  }
  double n = 0;
  for (char c : covered) n += c;
  return n * h * h;
}

TEST_F(PlantCli, ALoneLeafsSilhouetteAndStarAreThePlantPathsAndMatchACaribuStyleInterception) {
  for (const std::string name : {"lower-leaf-n10", "upper-curved-leaf-n14"}) {
    const fs::path can = dir_ / (name + ".can"), csv = dir_ / (name + ".csv");
    const Result r = leafdig("model build " + quote(sample(name + ".markers.json")) + " --json -o " + quote(can) +
                             " -o " + quote(csv));
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const json m = json::parse(r.out).at("metrics");
    const double silhouette = m.at("silhouette_mm2").get<double>();
    const double star = m.at("star").get<double>();
    EXPECT_NEAR(star, silhouette / m.at("mesh_area_mm2").get<double>(), 1e-12);
    EXPECT_GT(star, 0.3);
    EXPECT_LE(star, 1.0);
    EXPECT_LE(silhouette, m.at("projected_area_mm2").get<double>() * 1.01) << "overlaps count once";
    // The plant path's per-leaf numbers for the same leaf and light: the CSV's columns.
    const auto lines = leafdig::test::linesOf(slurp(csv));
    ASSERT_GE(lines.size(), 2u);
    const auto header = leafdig::test::splitExact(lines[0], ',');
    const auto row = leafdig::test::splitExact(lines[1], ',');
    const auto column = [&](const std::string& key) {
      const auto at = std::find(header.begin(), header.end(), key);
      EXPECT_NE(at, header.end()) << key;
      return std::stod(row.at(static_cast<std::size_t>(at - header.begin())));
    };
    EXPECT_NEAR(column("silhouette_mm2"), silhouette, 0.0005) << name;
    EXPECT_NEAR(column("star"), star, 1e-9) << name;
    // CARIBU's view of the exported file: the same area intercepted from above, within 0.5 %.
    const auto opt = leafdig::test::readOptStrictly(slurp(fs::path(can).replace_extension(".opt")));
    const auto triangles = leafdig::test::readCanStrictly(slurp(can), opt);
    // The blade is the leaf's last element (midrib, laterals, contour, blade): the silhouette
    // counts the blade alone, as the plant's does.
    int bladeElement = 0;
    for (const auto& t : triangles) bladeElement = std::max(bladeElement, t.element);
    std::vector<leafdig::test::CanTriangle> blade;
    for (const auto& t : triangles)
      if (t.element == bladeElement) blade.push_back(t);
    const double intercepted = interceptionFromAboveMm2(blade);
    EXPECT_NEAR(intercepted / silhouette, 1.0, 0.005) << name << ": interception " << intercepted;
  }
}

// A plant digitized in place (leafdig.plant-markers/1) measured in its own frame: the shipped
// sample's quick leaves come out at the azimuths, inclinations and sizes they were laid out
// with, the internodes and divergences follow, and a file that cannot make a frame exits 2
// naming the problem.
TEST_F(PlantCli, APlantDigitizedInPlaceIsMeasuredInItsOwnFrame) {
  const std::string sample = std::string(LEAFDIG_SOURCE_DIR) + "/data/plants/sample.plant-markers.json";
  const Result r = leafdig("plant measure " + quote(sample) + " --json");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const json j = json::parse(r.out);
  EXPECT_EQ(j["plant"], "tobacco-p12");
  ASSERT_EQ(j["nodes"].size(), 5u);
  for (std::size_t i = 0; i < 5; ++i) {
    const double heights[] = {70, 160, 245, 325, 400};
    EXPECT_NEAR(j["nodes"][i]["height_mm"].get<double>(), heights[i], 0.01) << i;
  }
  EXPECT_NEAR(j["nodes"][0]["internode_mm"].get<double>(), 70.01, 0.01);
  ASSERT_EQ(j["leaves"].size(), 4u);  // node 5 has none; node 1's is flagged dead
  EXPECT_EQ(j["leaves"][0]["kind"], "none");
  EXPECT_EQ(j["leaves"][0]["state"], "dead");
  EXPECT_TRUE(j["leaves"][0]["azimuth_deg"].is_null());
  const json& full = j["leaves"][1];
  EXPECT_EQ(full["kind"], "full");
  EXPECT_GT(full["area_mm2"].get<double>(), 0.0);
  EXPECT_LT(full["area_95_mm2"][0].get<double>(), full["area_mm2"].get<double>());
  EXPECT_GT(full["area_95_mm2"][1].get<double>(), full["area_mm2"].get<double>());
  const json& q3 = j["leaves"][2];
  // (The sample's coordinates are written to 0.001 mm: angles hold to 0.001°.)
  EXPECT_NEAR(q3["azimuth_deg"].get<double>(), 275.0, 1e-3);
  EXPECT_NEAR(q3["inclination_deg"].get<double>(), 62.0, 1e-3);
  EXPECT_NEAR(q3["chord_mm"].get<double>(), 380.0, 1e-2);
  EXPECT_NEAR(q3["width_mm"].get<double>(), 190.0, 1e-2);
  EXPECT_NEAR(q3["roll_deg"].get<double>(), 0.0, 1e-2);
  EXPECT_NEAR(q3["divergence_deg"].get<double>(),
              std::fmod(q3["azimuth_deg"].get<double>() - full["azimuth_deg"].get<double>() + 360.0, 360.0), 1e-9);
  EXPECT_NEAR(j["leaves"][3]["divergence_deg"].get<double>(), 137.5, 1e-3);
  EXPECT_EQ(j["divergence"]["count"], 2);
  // The text report says the same for a person.
  const Result text = leafdig("plant measure " + quote(sample));
  ASSERT_EQ(text.exitCode, 0) << text.err;
  EXPECT_NE(text.out.find("leaf at node 3 (quick): azimuth 275.0°, inclination 62.0°"), std::string::npos) << text.out;
  EXPECT_NE(text.out.find("leaf at node 1 (none, dead)"), std::string::npos) << text.out;

  // Landmarks along one edge cannot make a frame: exit 2, named, with what to do.
  const fs::path line = write("line.plant-markers.json", R"({"format": "leafdig.plant-markers/1", "units": "mm",
    "landmarks": [[0, 0, 0], [50, 1, 0], [100, 0, 0]], "collar": {"point": [50, -80, 0], "diameter": 20},
    "nodes": [{"point": [50, -80, 60], "diameter": 18}]})");
  const Result bad = leafdig("plant measure " + quote(line));
  EXPECT_EQ(bad.exitCode, 2) << bad.err;
  EXPECT_NE(bad.err.find("nearly on one line"), std::string::npos) << bad.err;
  // A leaf whose tip is its base: the node is named.
  std::string doc = slurp(sample);
  const json sampleDoc = json::parse(doc);
  json broken = sampleDoc;
  broken["nodes"][3]["leaf"]["tip"] = broken["nodes"][3]["leaf"]["base"];
  const Result tipless = leafdig("plant measure " + quote(write("tipless.json", broken.dump())));
  EXPECT_EQ(tipless.exitCode, 2) << tipless.err;
  EXPECT_NE(tipless.err.find("node 4's leaf: the leaf's base and tip are 0.0 mm apart"), std::string::npos)
      << tipless.err;
}

TEST_F(PlantCli, APlantDigitizedInPlaceIsWrittenAsAnMtgInTheAmapConventions) {
  const std::string sample = std::string(LEAFDIG_SOURCE_DIR) + "/data/plants/sample.plant-markers.json";
  const fs::path out = dir_ / "p12.mtg";
  const Result r = leafdig("plant measure " + quote(sample) + " --json --mtg " + quote(out.string()));
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const json j = json::parse(r.out);
  EXPECT_EQ(j["date"], "2026-06-12");  // the file's
  const auto mtg = leafdig::test::readMtgStrictly(slurp(out));
  EXPECT_EQ(mtg.nbScales(), 3);
  std::vector<std::string> names;
  for (const auto& [name, type] : mtg.features) names.push_back(name);
  for (const char* amap :
       {"XX", "YY", "ZZ", "TopDia", "Length", "Width", "Area", "Azimuth", "Inclination", "State", "Date"})
    EXPECT_NE(std::find(names.begin(), names.end(), amap), names.end()) << amap;
  const auto number = [](const auto& e, const char* f) { return std::stod(e.features.at(f)); };
  // The collar I0 at the origin, then one internode per node ending at it, in order.
  std::vector<const leafdig::test::MtgEntity*> stem, leaves;
  for (const auto& e : mtg.entities) {
    if (e.symbol == 'I') stem.push_back(&e);
    if (e.symbol == 'L') leaves.push_back(&e);
  }
  ASSERT_EQ(stem.size(), 6u);
  EXPECT_EQ(stem[0]->index, 0);
  EXPECT_EQ(number(*stem[0], "ZZ"), 0.0);
  EXPECT_NEAR(number(*stem[0], "TopDia"), j["collar_diameter_mm"].get<double>(), 5e-4);
  for (std::size_t k = 1; k < stem.size(); ++k) {
    const json& node = j["nodes"][k - 1];
    EXPECT_EQ(stem[k]->index, static_cast<int>(k));
    EXPECT_EQ(stem[k]->relation, '<');
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(number(*stem[k], std::array{"XX", "YY", "ZZ"}[static_cast<std::size_t>(c)]),
                  node["point_mm"][static_cast<std::size_t>(c)].get<double>(), 5e-4)
          << k;
    EXPECT_NEAR(number(*stem[k], "TopDia"), node["diameter_mm"].get<double>(), 5e-4);
    EXPECT_NEAR(number(*stem[k], "Length"), node["internode_mm"].get<double>(), 5e-4);
    EXPECT_EQ(stem[k]->features.at("Date"), "12/06/2026");
  }
  // Each leaf branches (+) from its node's internode, with the survey's numbers.
  ASSERT_EQ(leaves.size(), j["leaves"].size());
  for (std::size_t k = 0; k < leaves.size(); ++k) {
    const json& leaf = j["leaves"][k];
    const auto& e = *leaves[k];
    EXPECT_EQ(e.relation, '+');
    EXPECT_EQ(e.index, leaf["node"].get<int>());
    EXPECT_EQ(mtg.entities[static_cast<std::size_t>(e.parent)].symbol, 'I');
    EXPECT_EQ(mtg.entities[static_cast<std::size_t>(e.parent)].index, leaf["node"].get<int>());
    EXPECT_EQ(e.features.at("State"), leaf["state"].get<std::string>());
    EXPECT_EQ(e.features.at("Kind"), leaf["kind"].get<std::string>());
    EXPECT_EQ(e.features.at("Date"), "12/06/2026");
    if (leaf["azimuth_deg"].is_null()) {
      EXPECT_EQ(e.features.count("Azimuth"), 0u);
      EXPECT_EQ(e.features.count("XX"), 0u);
    } else {
      EXPECT_NEAR(number(e, "Azimuth"), leaf["azimuth_deg"].get<double>(), 5e-4);
      EXPECT_NEAR(number(e, "Inclination"), leaf["inclination_deg"].get<double>(), 5e-4);
      EXPECT_NEAR(number(e, "Width"), leaf["width_mm"].get<double>(), 5e-4);
      const double length =
          leaf["midrib_length_mm"].is_null() ? leaf["chord_mm"].get<double>() : leaf["midrib_length_mm"].get<double>();
      EXPECT_NEAR(number(e, "Length"), length, 5e-4);
    }
    if (leaf["area_mm2"].is_null())
      EXPECT_EQ(e.features.count("Area"), 0u);
    else
      EXPECT_NEAR(number(e, "Area"), leaf["area_mm2"].get<double>(), 5e-4);
    // Issue 51: a quick leaf's area is its drawn shape's, which the MTG names; a full leaf's is
    // its digitized blade's.
    if (leaf["kind"] == "quick") {
      EXPECT_GT(leaf["area_mm2"].get<double>(), 0.0);
      EXPECT_TRUE(leaf["area_95_mm2"].is_null());
      EXPECT_EQ(e.features.at("Shape").rfind("built-in_sample_shape", 0), 0U) << e.features.at("Shape");
    } else {
      EXPECT_EQ(e.features.count("Shape"), 0u);
    }
  }

  // The same entities as a CSV, one row each in the MTG's order, every row the header's width.
  const fs::path csv = dir_ / "p12.csv";
  ASSERT_EQ(leafdig("plant measure " + quote(sample) + " --csv " + quote(csv.string())).exitCode, 0);
  std::istringstream rows(slurp(csv));
  std::string row;
  std::vector<std::vector<std::string>> table;
  while (std::getline(rows, row)) {
    // RFC 4180 cells: a quoted cell may hold commas (a quick leaf's shape source does).
    std::vector<std::string> fields(1);
    bool quoted = false;
    for (std::size_t i = 0; i < row.size(); ++i) {
      const char c = row[i];
      if (quoted && c == '"' && i + 1 < row.size() && row[i + 1] == '"') {
        fields.back() += '"';
        ++i;
      } else if (c == '"') {
        quoted = !quoted;
      } else if (c == ',' && !quoted) {
        fields.emplace_back();
      } else {
        fields.back() += c;
      }
    }
    table.push_back(fields);
  }
  ASSERT_EQ(table.size(), 1 + mtg.entities.size() - 1);  // the header; every entity but the plant P1
  for (const auto& fields : table) EXPECT_EQ(fields.size(), table[0].size()) << fields[0];
  EXPECT_EQ(table[0][0], "entity");
  EXPECT_EQ(table[0].back(), "area_shape");
  EXPECT_EQ(table[1][0], "I0");
  for (std::size_t k = 1; k < table.size(); ++k) {
    const auto& e = mtg.entities[k];  // entities[0] is P1
    EXPECT_EQ(table[k][0], std::string(1, e.symbol) + std::to_string(e.index));
    EXPECT_EQ(table[k][5], "2026-06-12");
    if (e.features.count("XX")) {
      EXPECT_EQ(table[k][6], e.features.at("XX"));
    }
    if (e.features.count("Azimuth")) {
      EXPECT_EQ(table[k][15], e.features.at("Azimuth"));
    }
    // The drawn shape's source, as written (the MTG's is the same text made an MTG word).
    EXPECT_EQ(table[k].back().rfind("built-in sample shape (synthetic tobacco leaf), no approved leaf", 0) == 0,
              e.features.count("Shape") == 1)
        << table[k].back();
    // A leaf's XX YY ZZ is its tip (PlantFrame draws it from its node to there), BaseX… its base:
    // the two a chord apart (issue 51: the base alone made every leaf a stub in PlantFrame).
    if (e.symbol == 'L' && e.features.count("BaseX")) {
      EXPECT_EQ(table[k][21], e.features.at("BaseX"));
      const double dx = number(e, "XX") - number(e, "BaseX"), dy = number(e, "YY") - number(e, "BaseY"),
                   dz = number(e, "ZZ") - number(e, "BaseZ");
      const auto leaf = std::find_if(j["leaves"].begin(), j["leaves"].end(),
                                     [&](const json& l) { return l["node"].get<int>() == e.index; });
      ASSERT_NE(leaf, j["leaves"].end());
      EXPECT_NEAR(std::sqrt(dx * dx + dy * dy + dz * dz), (*leaf)["chord_mm"].get<double>(), 2e-3) << "L" << e.index;
    }
  }

  // --date is the survey's day over the file's; a day that is not one is refused, nothing written.
  const Result dated =
      leafdig("plant measure " + quote(sample) + " --mtg " + quote((dir_ / "d.mtg").string()) + " --date 2027-02-28");
  ASSERT_EQ(dated.exitCode, 0) << dated.err;
  EXPECT_NE(dated.out.find("(MTG, survey of 2027-02-28)"), std::string::npos) << dated.out;
  EXPECT_NE(slurp(dir_ / "d.mtg").find("\t28/02/2027"), std::string::npos);
  for (const char* day : {"2027-02-29", "26/11/2026", "2026-13-01", "yesterday"}) {
    const fs::path none = dir_ / "none.mtg";
    const Result bad = leafdig("plant measure " + quote(sample) + " --mtg " + quote(none.string()) + " --date " + day);
    EXPECT_EQ(bad.exitCode, 2) << day << ": " << bad.err;
    EXPECT_NE(bad.err.find("is not a day: give the survey's day as YYYY-MM-DD"), std::string::npos) << bad.err;
    EXPECT_FALSE(fs::exists(none)) << day;
  }
  // A file's date that is not a day is the file's fault, named.
  json doc = json::parse(slurp(sample));
  doc["date"] = "2026-06-31";
  const Result badFile = leafdig("plant measure " + quote(write("baddate.json", doc.dump())));
  EXPECT_EQ(badFile.exitCode, 2) << badFile.err;
  EXPECT_NE(badFile.err.find("date: must be the survey's day as \"YYYY-MM-DD\""), std::string::npos) << badFile.err;
}

}  // namespace

namespace {

// The frame error's lever: a point d mm from the collar moves by about σ d / R when the rim's
// landmarks (radius R) carry noise σ (docs/plants.md, "How exact").
double nodeTolerance(double noise, double distanceMm) {
  return 3.0 * noise * (2.0 + distanceMm / 110.0);
}

}  // namespace

TEST_F(PlantCli, ASyntheticPlantSeenThroughATransmitterAtARandomPoseIsMeasuredWithinTheDigitizersNoise) {
  constexpr double kNoise = 0.3;
  for (int seed = 1; seed <= 4; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    const fs::path markers = dir_ / ("s" + std::to_string(seed) + ".plant-markers.json");
    const fs::path truthFile = dir_ / ("s" + std::to_string(seed) + ".truth.json");
    const Result made = leafdig("synth plant --nodes 9 --seed " + std::to_string(seed) + " --noise 0.3 --markers " +
                                quote(markers) + " --truth " + quote(truthFile) + " --json");
    ASSERT_EQ(made.exitCode, 0) << made.err;
    const json summary = json::parse(made.out);
    EXPECT_EQ(summary["nodes"], 9);
    EXPECT_GE(summary["full_leaves"].get<int>(), 2);
    EXPECT_GE(summary["quick_leaves"].get<int>(), 3);
    const json truth = json::parse(slurp(truthFile));
    // The transmitter is somewhere else: the file's points are not in the plant's frame.
    const json raw = json::parse(slurp(markers));
    EXPECT_GT(std::abs(raw["collar"]["point"][0].get<double>()) + std::abs(raw["collar"]["point"][1].get<double>()),
              1.0);

    const Result r = leafdig("plant measure " + quote(markers) + " --json");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const json got = json::parse(r.out);
    ASSERT_EQ(got["nodes"].size(), truth["nodes"].size());
    double worst = 0.0;
    for (std::size_t k = 0; k < got["nodes"].size(); ++k) {
      double d2 = 0.0, r2 = 0.0;
      for (std::size_t c = 0; c < 3; ++c) {
        const double t = truth["nodes"][k]["point_mm"][c].get<double>();
        d2 += std::pow(got["nodes"][k]["point_mm"][c].get<double>() - t, 2);
        r2 += t * t;
      }
      EXPECT_LE(std::sqrt(d2), nodeTolerance(kNoise, std::sqrt(r2))) << "node " << k + 1;
      worst = std::max(worst, std::sqrt(d2));
      EXPECT_NEAR(got["nodes"][k]["diameter_mm"].get<double>(), truth["nodes"][k]["diameter_mm"].get<double>(), 0.1);
    }
    // Leaves: the same nodes, kinds and states; angles within 2°; full leaves' areas inside
    // their 95 % interval, quick leaves' sizes within the noise.
    ASSERT_EQ(got["leaves"].size(), truth["leaves"].size());
    for (std::size_t k = 0; k < got["leaves"].size(); ++k) {
      const json& g = got["leaves"][k];
      const json& t = truth["leaves"][k];
      SCOPED_TRACE("leaf of node " + std::to_string(t["node"].get<int>()));
      EXPECT_EQ(g["node"], t["node"]);
      EXPECT_EQ(g["kind"], t["kind"]);
      EXPECT_EQ(g["state"], t["state"]);
      if (t["azimuth_deg"].is_null()) continue;
      const double dAzimuth = std::remainder(g["azimuth_deg"].get<double>() - t["azimuth_deg"].get<double>(), 360.0);
      EXPECT_LE(std::abs(dAzimuth), 2.0);
      EXPECT_LE(std::abs(g["inclination_deg"].get<double>() - t["inclination_deg"].get<double>()), 2.0);
      if (t["kind"] == "full") {
        const double area = t["area_mm2"].get<double>();
        EXPECT_LE(g["area_95_mm2"][0].get<double>(), area);
        EXPECT_GE(g["area_95_mm2"][1].get<double>(), area);
        EXPECT_NEAR(g["midrib_length_mm"].get<double>(), t["length_mm"].get<double>(),
                    0.01 * t["length_mm"].get<double>());
      } else {
        EXPECT_NEAR(g["chord_mm"].get<double>(), t["length_mm"].get<double>(), 6 * kNoise);
        EXPECT_NEAR(g["width_mm"].get<double>(), t["width_mm"].get<double>(), 6 * kNoise);
      }
    }
    std::cout << "seed " << seed << ": worst node " << worst << " mm\n";
  }
  // Without noise and in the plant's own frame, the measure gives the truth back.
  const fs::path exact = dir_ / "exact.plant-markers.json";
  const fs::path exactTruth = dir_ / "exact.truth.json";
  ASSERT_EQ(leafdig("synth plant --noise 0 --pose plant --markers " + quote(exact) + " --truth " + quote(exactTruth))
                .exitCode,
            0);
  const json got = json::parse(leafdig("plant measure " + quote(exact) + " --json").out);
  const json truth = json::parse(slurp(exactTruth));
  for (std::size_t k = 0; k < got["nodes"].size(); ++k)
    for (std::size_t c = 0; c < 3; ++c)
      EXPECT_NEAR(got["nodes"][k]["point_mm"][c].get<double>(), truth["nodes"][k]["point_mm"][c].get<double>(), 0.02);
  for (std::size_t k = 0; k < got["leaves"].size(); ++k)
    if (!truth["leaves"][k]["azimuth_deg"].is_null()) {
      EXPECT_NEAR(got["leaves"][k]["azimuth_deg"].get<double>(), truth["leaves"][k]["azimuth_deg"].get<double>(), 0.01);
    }
  // Bad options exit 2 and write nothing.
  const fs::path none = dir_ / "none.json";
  for (const std::string bad : {"--nodes 1", "--full-every 0", "--noise -1", "--pose sideways", "--date 2026-02-30"}) {
    const Result r = leafdig("synth plant " + bad + " --markers " + quote(none) + " --truth " + quote(none));
    EXPECT_EQ(r.exitCode, 2) << bad << ": " << r.err;
    EXPECT_FALSE(fs::exists(none)) << bad;
  }
}

TEST_F(PlantCli, APlantProtocolIsCheckedAndItsStepsListedInTheOrderTheCaptureAsks) {
  const Result builtIn = leafdig("plant protocol");
  ASSERT_EQ(builtIn.exitCode, 0) << builtIn.err;
  EXPECT_NE(builtIn.out.find("built-in protocol: tobacco, 2 entities"), std::string::npos) << builtIn.out;
  EXPECT_NE(builtIn.out.find("  4. internode (I, one after another) · node · stylus\n"), std::string::npos)
      << builtIn.out;
  EXPECT_NE(builtIn.out.find("  5. internode (I, one after another) · diameter · caliper\n"), std::string::npos);
  const std::string maize = std::string(LEAFDIG_SOURCE_DIR) + "/data/protocols/maize.plant-protocol.json";
  const Result m = leafdig("plant protocol " + quote(maize) + " --json");
  ASSERT_EQ(m.exitCode, 0) << m.err;
  const json j = json::parse(m.out);
  EXPECT_EQ(j["species"], "maize");
  EXPECT_EQ(j["entities"][1]["leaf"]["quick_points"], json({"ligule", "tip", "widest"}));
  EXPECT_EQ(j["landmarks"]["min"], 3);  // defaults filled in
  // A protocol that names an entity twice: exit 2, the entity and what to do.
  const fs::path twice = write("twice.json", R"({"format": "leafdig.plant-protocol/1", "species": "tobacco",
    "entities": [{"name": "internode", "class": "I", "points": ["node"]},
                 {"name": "internode", "class": "J", "parent": "internode", "points": ["node"]}]})");
  const Result bad = leafdig("plant protocol " + quote(twice));
  EXPECT_EQ(bad.exitCode, 2) << bad.err;
  EXPECT_NE(bad.err.find("twice.json: entity 2 (internode): the name \"internode\" is already an entity's; give each "
                         "entity its own name"),
            std::string::npos)
      << bad.err;
  EXPECT_EQ(leafdig("plant protocol " + quote(dir_ / "missing.json")).exitCode, 2);
  // What `plant capture` cannot follow, `plant protocol` does not pass (issue 47, 23): the same
  // check, the same words.
  for (const auto& [name, text, words] : std::vector<std::tuple<std::string, std::string, std::string>>{
           {"order3.json", R"({"format": "leafdig.plant-protocol/1", "species": "x", "entities": [
               {"name": "internode", "class": "I", "repeat": true, "points": ["node"]},
               {"name": "branch", "class": "B", "parent": "internode", "relation": "+", "order": 2, "repeat": true,
                "points": ["node"]},
               {"name": "twig", "class": "T", "parent": "branch", "relation": "+", "order": 3, "repeat": true,
                "points": ["node"]}]})",
            "an axis of order 3"},
           {"two-branches.json", R"({"format": "leafdig.plant-protocol/1", "species": "x", "entities": [
               {"name": "internode", "class": "I", "repeat": true, "points": ["node"]},
               {"name": "b1", "class": "B", "parent": "internode", "relation": "+", "order": 2, "repeat": true,
                "points": ["node"]},
               {"name": "b2", "class": "C", "parent": "internode", "relation": "+", "order": 2, "repeat": true,
                "points": ["node"]}]})",
            "two branch"}}) {
    const Result r = leafdig("plant protocol " + quote(write(name, text)));
    EXPECT_EQ(r.exitCode, 2) << name << ": " << r.out << r.err;
    EXPECT_NE(r.err.find(words), std::string::npos) << name << ": " << r.err;
    EXPECT_NE(r.err.find("plant capture cannot follow it"), std::string::npos) << name << ": " << r.err;
  }
}

TEST_F(PlantCli, APlantDigitizedThroughTheSimulatedDevicesIsStoredVerifiedAndExportedAsItsFileMeasures) {
  const fs::path markers = synthPlant(5, 8);
  const fs::path db = dir_ / "station.sqlite";
  const Result r = leafdig("plant capture --simulate --plant-markers " + quote(markers) + " --db " + quote(db) +
                           " --speed 20 --seed 5 --stylus-noise 0.3 --json --project survey-2026");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const std::vector<json> lines = jsonLines(r.out);
  ASSERT_GE(lines.size(), 3U);
  EXPECT_EQ(lines.front().at("event"), "session");
  const std::int64_t id = lines.front().at("session");
  EXPECT_EQ(lines.back().at("event"), "complete");
  EXPECT_EQ(lines.back().at("session"), id);
  EXPECT_EQ(lines.back().at("nodes"), 8);
  // Every line is a committed event, in order.
  std::int64_t last = 0;
  for (std::size_t k = 1; k + 1 < lines.size(); ++k) {
    EXPECT_GT(lines[k].at("seq").get<std::int64_t>(), last) << lines[k];
    last = lines[k].at("seq");
  }
  // Listed as a plant; its chain verifies; shown as a plant.
  const json list = json::parse(leafdig("sessions list --json --db " + quote(db)).out);
  ASSERT_EQ(list.size(), 1U);
  EXPECT_EQ(list[0].at("kind"), "plant");
  EXPECT_EQ(list[0].at("status"), "complete");
  EXPECT_EQ(list[0].at("project"), "survey-2026");
  EXPECT_EQ(leafdig("sessions verify --db " + quote(db)).exitCode, 0);
  const Result show = leafdig("sessions show " + std::to_string(id) + " --db " + quote(db));
  EXPECT_EQ(show.exitCode, 0) << show.err;
  EXPECT_NE(show.out.find("plant survey-2026/"), std::string::npos) << show.out;
  EXPECT_NE(show.out.find("step: Plant complete"), std::string::npos) << show.out;
  // Its exports: the MTG through the strict reader; the survey equals `plant measure` of the
  // file within the stylus's noise (every press is the mean of the samples around it).
  const fs::path out = dir_ / "out";
  const Result exported = leafdig("sessions export " + std::to_string(id) + " --db " + quote(db) + " --out " +
                                  quote(out) + " --format mtg,csv,markers,json --json");
  ASSERT_EQ(exported.exitCode, 0) << exported.err;
  EXPECT_EQ(json::parse(exported.out).at("outputs").size(), 4U);
  const std::string base = (out / ("session-" + std::to_string(id))).string();
  const auto mtg = leafdig::test::readMtgStrictly(slurp(base + ".mtg"));
  int stem = 0;
  for (const auto& e : mtg.entities) {
    stem += e.symbol == 'I';
    if (e.symbol == 'I' || e.symbol == 'L') {
      EXPECT_EQ(e.features.count("Date") ? e.features.at("Date") : "", "12/06/2026") << e.symbol << e.index;
    }
  }
  EXPECT_EQ(stem, 9);  // the collar and 8 nodes
  // Helios and VegeSTAR on request, the blades alone: the leaves' triangles, by leaf.
  const Result light = leafdig("sessions export " + std::to_string(id) + " --db " + quote(db) + " --out " + quote(out) +
                               " --format xml,vgx --organs blade --resolution preview --json");
  ASSERT_EQ(light.exitCode, 0) << light.err;
  const auto helios = leafdig::test::readHeliosStrictly(slurp(base + ".helios.xml"));
  const auto vgx = leafdig::test::readVgxStrictly(slurp(base + ".vgx"));
  ASSERT_FALSE(helios.triangles.empty());
  EXPECT_EQ(vgx.size(), helios.triangles.size());
  for (const auto& t : helios.triangles) EXPECT_GT(t.data.at("leafID"), 0) << "the wood is left out";
  const json got = json::parse(slurp(base + ".survey.json"));
  const Result measured = leafdig("plant measure " + quote(markers) + " --json");
  ASSERT_EQ(measured.exitCode, 0) << measured.err;
  const json want = json::parse(measured.out);
  ASSERT_EQ(got.at("nodes").size(), want.at("nodes").size());
  for (std::size_t k = 0; k < got.at("nodes").size(); ++k)
    for (std::size_t c = 0; c < 3; ++c)
      EXPECT_NEAR(got["nodes"][k]["point_mm"][c].get<double>(), want["nodes"][k]["point_mm"][c].get<double>(), 1.0)
          << "node " << k + 1;
  ASSERT_EQ(got.at("leaves").size(), want.at("leaves").size());
  for (std::size_t k = 0; k < got.at("leaves").size(); ++k) {
    const json &g = got["leaves"][k], &w = want["leaves"][k];
    EXPECT_EQ(g.at("kind"), w.at("kind"));
    EXPECT_EQ(g.at("state"), w.at("state"));
    if (w.contains("azimuth_deg") && !w["azimuth_deg"].is_null()) {
      double d = std::fmod(std::abs(g["azimuth_deg"].get<double>() - w["azimuth_deg"].get<double>()), 360.0);
      EXPECT_LT(std::min(d, 360.0 - d), 1.0) << "leaf " << k;
      EXPECT_NEAR(g["inclination_deg"].get<double>(), w["inclination_deg"].get<double>(), 1.0) << "leaf " << k;
    }
    if (w.contains("area_mm2") && !w["area_mm2"].is_null()) {
      EXPECT_NEAR(g["area_mm2"].get<double>(), w["area_mm2"].get<double>(), 0.01 * w["area_mm2"].get<double>());
    }
  }
}

TEST_F(PlantCli, APlantCaptureKilledMidwayLosesNothingAcknowledgedAndResumesToTheSamePlant) {
  const fs::path markers = synthPlant(7, 6);
  const fs::path db = dir_ / "station.sqlite", out = dir_ / "out.jsonl", err = dir_ / "err.txt";
  std::int64_t id = 0;
  std::mt19937 rng(7);
  for (int run = 0; run < 4; ++run) {
    // Killed after its k-th acknowledged event: mid-capture by construction, not by a timer.
    const std::size_t k = std::uniform_int_distribution<std::size_t>(5, 40)(rng);
    std::vector<std::string> args{
        "plant", "capture", "--db", db.string(), "--speed", "20", "--json", "--seed", std::to_string(run + 1)};
    if (id == 0) {
      args.insert(args.end(), {"--simulate", "--plant-markers", markers.string()});
    } else {
      args.insert(args.end(), {"--resume", std::to_string(id)});
    }
    const std::vector<json> lines = killAfterLines(args, k, out, err);
    ASSERT_FALSE(lines.empty()) << slurp(err);
    id = lines.front().at("session");
    // Every acknowledged event is in the file, and the chain verifies.
    std::int64_t acknowledged = 0;
    for (const json& j : lines)
      if (j.contains("seq")) acknowledged = std::max(acknowledged, j.at("seq").get<std::int64_t>());
    const json list = json::parse(leafdig("sessions list --json --db " + quote(db)).out);
    ASSERT_EQ(list.size(), 1U);
    EXPECT_GE(list[0].at("events").get<std::int64_t>(), acknowledged) << "run " << run;
    EXPECT_EQ(leafdig("sessions verify --db " + quote(db)).exitCode, 0) << "run " << run;
    if (list[0].at("status") == "complete") break;
  }
  // Resumed to the end, the plant is the file's plant.
  const Result done =
      leafdig("plant capture --resume " + std::to_string(id) + " --db " + quote(db) + " --speed 20 --json </dev/null");
  ASSERT_EQ(done.exitCode, 0) << done.err;
  const json list = json::parse(leafdig("sessions list --json --db " + quote(db)).out);
  EXPECT_EQ(list[0].at("status"), "complete");
  const Result exported = leafdig("sessions export " + std::to_string(id) + " --db " + quote(db) + " --out " +
                                  quote(dir_ / "x") + " --format json");
  ASSERT_EQ(exported.exitCode, 0) << exported.err;
  const json got = json::parse(slurp(dir_ / "x" / ("session-" + std::to_string(id) + ".survey.json")));
  const json want = json::parse(leafdig("plant measure " + quote(markers) + " --json").out);
  ASSERT_EQ(got.at("nodes").size(), want.at("nodes").size());
  ASSERT_EQ(got.at("leaves").size(), want.at("leaves").size());
  for (std::size_t k = 0; k < got.at("leaves").size(); ++k)
    EXPECT_EQ(got["leaves"][k]["kind"], want["leaves"][k]["kind"]);
}

// A plant with a sucker (data/plants/branched.plant-markers.json) captured by the virtual
// technician with the branched protocol, devices on pseudo-terminals: the branch is begun and
// ended by the technician's commands, committed as node_placed, and the exports hang it where
// it grows — the MTG for the strict reader (+I3 from I2, I5 after I2), the GLB for the Khronos
// validator (the branch's tube under its own internodes) — and the plan is refused in words.
TEST_F(PlantCli, ABranchedPlantIsCapturedAndExportedWithItsBranchWhereItGrows) {
  const fs::path db = dir_ / "station.sqlite";
  const std::string data = std::string(LEAFDIG_SOURCE_DIR) + "/data";
  const Result r =
      leafdig("plant capture --simulate --db " + quote(db) + " --speed 20 --seed 3 --json --plant-markers " +
              quote(data + "/plants/branched.plant-markers.json") + " --protocol " +
              quote(data + "/protocols/branched.plant-protocol.json"));
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const std::vector<json> lines = jsonLines(r.out);
  const std::int64_t id = lines.front().at("session");
  std::vector<json> placed;
  for (const json& j : lines)
    if (j.value("event", "") == "node_placed") placed.push_back(j);
  ASSERT_EQ(placed.size(), 2U) << r.out;
  EXPECT_EQ(placed[0].at("node"), 3);
  EXPECT_EQ(placed[0].at("relation"), "+");
  EXPECT_EQ(placed[1].at("node"), 5);
  EXPECT_EQ(placed[1].at("parent"), 2);
  const fs::path out = dir_ / "out";
  const Result exported = leafdig("sessions export " + std::to_string(id) + " --db " + quote(db) + " --out " +
                                  quote(out) + " --format mtg,csv,json,glb --json");
  ASSERT_EQ(exported.exitCode, 0) << exported.err;
  const std::string base = (out / ("session-" + std::to_string(id))).string();
  const leafdig::test::MtgFile mtg = leafdig::test::readMtgStrictly(slurp(base + ".mtg"));
  std::map<std::string, std::pair<std::string, char>> hang;
  const auto label = [&](int k) {
    const auto& e = mtg.entities[static_cast<std::size_t>(k)];
    return std::string(1, e.symbol) + std::to_string(e.index);
  };
  for (std::size_t k = 0; k < mtg.entities.size(); ++k)
    if (mtg.entities[k].symbol != 'P' && mtg.entities[k].parent >= 0)
      hang[label(static_cast<int>(k))] = {label(mtg.entities[k].parent), mtg.entities[k].relation};
  EXPECT_EQ(hang["I3"], (std::pair<std::string, char>{"I2", '+'}));
  EXPECT_EQ(hang["I4"], (std::pair<std::string, char>{"I3", '<'}));
  EXPECT_EQ(hang["L4"], (std::pair<std::string, char>{"I4", '+'}));
  EXPECT_EQ(hang["I5"], (std::pair<std::string, char>{"I2", '<'}));
  // The survey equals the file's own (plant measure), node by node, where each hangs included.
  const json got = json::parse(slurp(base + ".survey.json"));
  const json want =
      json::parse(leafdig("plant measure " + quote(data + "/plants/branched.plant-markers.json") + " --json").out);
  ASSERT_EQ(got.at("nodes").size(), want.at("nodes").size());
  for (std::size_t k = 0; k < got.at("nodes").size(); ++k) {
    EXPECT_EQ(got["nodes"][k]["parent"], want["nodes"][k]["parent"]) << k;
    EXPECT_EQ(got["nodes"][k]["relation"], want["nodes"][k]["relation"]) << k;
    EXPECT_NEAR(got["nodes"][k]["internode_mm"].get<double>(), want["nodes"][k]["internode_mm"].get<double>(), 0.5);
  }
  const Result check = run("node " + quote(std::string(LEAFDIG_SOURCE_DIR) + "/tests/tools/validate-gltf.mjs") + " " +
                           quote(base + ".glb"));
  ASSERT_EQ(check.exitCode, 0) << check.out << check.err;
  EXPECT_EQ(json::parse(check.out)["numErrors"], 0) << check.out;
  const std::string glb = slurp(base + ".glb");
  for (const char* node : {"\"plant/branch-3/I3\"", "\"plant/branch-3/I4\"", "\"plant/stem/I5\""})
    EXPECT_NE(glb.find(node), std::string::npos) << node;
  // A plan holds one stem: asked for, refused by node; in "everything", left out and said.
  const Result plan = leafdig("sessions export " + std::to_string(id) + " --db " + quote(db) + " --out " + quote(out) +
                              " --format plan");
  EXPECT_EQ(plan.exitCode, 2);
  EXPECT_NE(plan.err.find("node 3 starts a branch (from node 2): a leafdig.plant/1 plan holds one stem"),
            std::string::npos)
      << plan.err;
  const Result all = leafdig("sessions export " + std::to_string(id) + " --db " + quote(db) + " --out " +
                             quote(dir_ / "all") + " --json");
  ASSERT_EQ(all.exitCode, 0) << all.err;
  EXPECT_NE(all.out.find("no leafdig.plant/1 plan: the plant has branches"), std::string::npos) << all.out;
  EXPECT_FALSE(fs::exists(dir_ / "all" / ("session-" + std::to_string(id) + ".plant.json")));
}

std::string samplePlantMeasure() {
  return "plant measure " + quote(std::string(LEAFDIG_SOURCE_DIR) + "/data/plants/sample.plant-markers.json") +
         " --json";
}

// The survey of a captured sample plant against the file's own (plant measure): every node within
// the digitizer's noise, every leaf's azimuth and inclination within 2°.
// `want`: `plant measure` of the sample's file (samplePlantMeasure()).
void expectTheSamplePlant(const json& got, const json& want) {
  ASSERT_EQ(got.at("nodes").size(), want.at("nodes").size());
  for (std::size_t k = 0; k < got.at("nodes").size(); ++k)
    for (std::size_t c = 0; c < 3; ++c)
      EXPECT_NEAR(got["nodes"][k]["point_mm"][c].get<double>(), want["nodes"][k]["point_mm"][c].get<double>(), 1.5)
          << "node " << k + 1;
  ASSERT_EQ(got.at("leaves").size(), want.at("leaves").size());
  for (std::size_t k = 0; k < got.at("leaves").size(); ++k) {
    if (want["leaves"][k]["azimuth_deg"].is_null()) continue;
    const double da = std::remainder(
        got["leaves"][k]["azimuth_deg"].get<double>() - want["leaves"][k]["azimuth_deg"].get<double>(), 360.0);
    EXPECT_LT(std::abs(da), 2.0) << "leaf " << k;
    EXPECT_NEAR(got["leaves"][k]["inclination_deg"].get<double>(), want["leaves"][k]["inclination_deg"].get<double>(),
                2.0)
        << "leaf " << k;
  }
}

// The transmitter moved mid-capture (issue 29): after 30 accepted points the virtual
// technician says "move", the simulated transmitter goes to a random pose and the landmarks are
// taken again; the fit is committed, and the plant comes out where the same plant without the
// move does — every node within the digitizer's noise, every leaf's angles within 2°.
TEST_F(PlantCli, AMovedTransmitterIsFittedFromTheLandmarksAndThePlantComesOutTheSame) {
  const fs::path db = dir_ / "station.sqlite";
  const Result r =
      leafdig("plant capture --simulate --db " + quote(db) + " --speed 20 --seed 5 --json --relocate-source-after 30");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const std::vector<json> lines = jsonLines(r.out);
  const std::int64_t id = lines.front().at("session");
  std::vector<std::string> steps;
  int again = 0;
  for (const json& j : lines) {
    if (j.value("event", "") == "relocation") steps.push_back(j.at("step"));
    if (j.value("what", "") == "landmark_again") ++again;
    if (j.value("step", "") == "fitted") {
      EXPECT_LT(j.at("rms_mm").get<double>(), 1.5) << j;
    }
  }
  EXPECT_EQ(steps, (std::vector<std::string>{"started", "fitted"})) << r.out;
  EXPECT_EQ(again, 4);  // the sample's four landmarks
  const fs::path out = dir_ / "out";
  ASSERT_EQ(leafdig("sessions export " + std::to_string(id) + " --db " + quote(db) + " --out " + quote(out) +
                    " --format json")
                .exitCode,
            0);
  const json survey = json::parse(slurp(out / ("session-" + std::to_string(id) + ".survey.json")));
  expectTheSamplePlant(survey, json::parse(leafdig(samplePlantMeasure()).out));
  // Which points came from which position, and the fit's residual: in the survey and the review.
  ASSERT_EQ(survey.at("transmitter_positions").size(), 2U) << survey.dump();
  const json& moved = survey["transmitter_positions"][1];
  EXPECT_EQ(moved.at("position"), 2);
  EXPECT_LT(moved.at("rms_mm").get<double>(), 1.5);
  EXPECT_GE(moved.at("worst_mm").get<double>(), moved.at("rms_mm").get<double>());
  EXPECT_GE(moved.at("worst_landmark").get<int>(), 1);
  EXPECT_EQ(survey["nodes"][0].at("transmitter_position"), 1);
  EXPECT_EQ(survey["nodes"].back().at("transmitter_position"), 2);
  // Node 2's full leaf was taken across the move (after 30 points, inside its rows): its area
  // interval is drawn with the fit's residual added to the digitizer's noise, and still holds
  // the area; the other leaves are from one position and keep the stated accuracy.
  int widened = 0;
  for (const json& leaf : survey.at("leaves")) {
    if (!leaf.contains("area_interval_sigma_mm")) continue;
    ++widened;
    EXPECT_EQ(leaf.at("node"), 2);
    EXPECT_NEAR(leaf["area_interval_sigma_mm"].get<double>(), std::hypot(0.762, moved.at("rms_mm").get<double>()),
                1e-9);
    EXPECT_LT(leaf["area_95_mm2"][0].get<double>(), leaf["area_mm2"].get<double>());
    EXPECT_GT(leaf["area_95_mm2"][1].get<double>(), leaf["area_mm2"].get<double>());
  }
  EXPECT_EQ(widened, 1);
  const json shown = json::parse(leafdig("sessions show " + std::to_string(id) + " --json --db " + quote(db)).out);
  EXPECT_EQ(shown.at("transmitter_positions"), survey.at("transmitter_positions"));
  int fromFirst = 0, fromSecond = 0;
  std::set<int> leafPositions;  // node 2's full leaf was taken across the move: its markers say so
  for (const json& p : shown.at("points")) {
    if (p.at("what").get<std::string>().rfind("node", 0) == 0) {
      ASSERT_TRUE(p.contains("transmitter_position")) << p;
      if (p.at("what").get<std::string>().rfind("node2.", 0) == 0)
        leafPositions.insert(p["transmitter_position"].get<int>());
      continue;
    }
    if (!p.contains("transmitter_position")) continue;
    (p["transmitter_position"] == 1 ? fromFirst : fromSecond) += 1;
  }
  EXPECT_EQ(leafPositions, (std::set<int>{1, 2}));
  EXPECT_EQ(fromFirst, survey["transmitter_positions"][0].at("points").get<int>());
  EXPECT_EQ(fromSecond, moved.at("points").get<int>() + 4) << "its points and the four landmarks taken again";
  const Result human = leafdig("sessions show " + std::to_string(id) + " --db " + quote(db));
  EXPECT_NE(human.out.find("transmitter moved: position 2"), std::string::npos) << human.out;
  // With devices the technician types "move": the option is the simulation's.
  const Result real =
      leafdig("plant capture --db " + quote(db) +
              " --digitizer fastrak:/dev/null --caliper sylvac:/dev/null --plant p --relocate-source-after 3");
  EXPECT_EQ(real.exitCode, 2);
  EXPECT_NE(real.err.find("goes with --simulate"), std::string::npos) << real.err;
  // The tolerance of a move's fit is the session's, set when it begins, within 0.1–10 mm.
  for (const std::string bad : {"0.01", "11", "-1"}) {
    const Result refused = leafdig("plant capture --simulate --db " + quote(dir_ / "other.sqlite") +
                                   " --speed 20 --relocation-tolerance " + bad);
    EXPECT_EQ(refused.exitCode, 2) << bad;
    EXPECT_NE(refused.err.find("--relocation-tolerance must be a residual in mm, 0.1 to 10"), std::string::npos)
        << bad << ": " << refused.err;
  }
  const Result resumed = leafdig("plant capture --simulate --db " + quote(db) + " --resume " + std::to_string(id) +
                                 " --relocation-tolerance 2");
  EXPECT_EQ(resumed.exitCode, 2);
  EXPECT_NE(resumed.err.find("a resumed session keeps its own"), std::string::npos) << resumed.err;
  EXPECT_FALSE(fs::exists(dir_ / "other.sqlite"));
}

// The pot turned 30° during the capture with a reference receiver on it (issue 29): the simulated
// FASTRAK reports two receivers, the driver takes every stylus sample into the reference's frame,
// and the plant comes out as the file says — the same as a capture on a still pot. The stored
// raw records show both receivers and the turn (the reference's azimuth 35° at the start, 65° at
// the last node).
TEST_F(PlantCli, APotTurnedThirtyDegreesUnderAReferenceReceiverChangesNothing) {
  const fs::path db = dir_ / "station.sqlite";
  const Result r = leafdig("plant capture --simulate --db " + quote(db) +
                           " --speed 20 --seed 5 --json --reference-receiver --pot-turn 30");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const std::int64_t id = jsonLines(r.out).front().at("session");
  const fs::path out = dir_ / "out";
  ASSERT_EQ(leafdig("sessions export " + std::to_string(id) + " --db " + quote(db) + " --out " + quote(out) +
                    " --format json,mtg")
                .exitCode,
            0);
  const std::string base = (out / ("session-" + std::to_string(id))).string();
  expectTheSamplePlant(json::parse(slurp(base + ".survey.json")), json::parse(leafdig(samplePlantMeasure()).out));
  (void)leafdig::test::readMtgStrictly(slurp(base + ".mtg"));
  // The raw records of the first and the last stylus point: receiver 1 then receiver 2, whose
  // azimuth (the 2nd angle column after x, y, z) went from 35° to 65° with the pot.
  const auto rawOf = [&](const char* order) {
    return run("python3 -c \"import sqlite3,sys; c=sqlite3.connect(sys.argv[1]); print(c.execute(\\\"select raw from "
               "events where kind='accepted' and payload_json like '%position_mm%' order by seq " +
               std::string(order) + " limit 1\\\").fetchone()[0])\" " + quote(db))
        .out;
  };
  const auto azimuthOfReference = [](const std::string& raw) {
    const std::size_t at = raw.find("\n02");
    EXPECT_NE(at, std::string::npos) << raw;
    return at == std::string::npos ? 0.0 : std::stod(raw.substr(at + 1 + 3 + 21, 7));
  };
  const std::string first = rawOf("asc"), last = rawOf("desc");
  EXPECT_EQ(first.rfind("01", 0), 0U) << first;
  EXPECT_NEAR(azimuthOfReference(first), 35.0, 0.05);
  EXPECT_NEAR(azimuthOfReference(last), 65.0, 0.05);
  // The pot turns only under a reference receiver, and only in a simulation.
  const Result alone = leafdig("plant capture --simulate --db " + quote(db) + " --pot-turn 30");
  EXPECT_EQ(alone.exitCode, 2);
  EXPECT_NE(alone.err.find("goes with --simulate --reference-receiver"), std::string::npos) << alone.err;
  const Result bad = leafdig("plant capture --db " + quote(db) +
                             " --digitizer fastrak:/dev/null,reference=1 --caliper sylvac:/dev/null --plant p");
  EXPECT_EQ(bad.exitCode, 2);
  EXPECT_NE(bad.err.find("the reference receiver is a number from 2"), std::string::npos) << bad.err;
}

// kill -9 across a move of the transmitter (issue 29): killed between the move and its fit (the
// simulated transmitter's pose died with the process: the virtual technician undoes the half-done
// move and goes on from the first position), or just after the fit (the resumed simulation stands
// where the fitted position stood) — the plant comes out as its file says either way.
TEST_F(PlantCli, APlantKilledAcrossAMoveOfTheTransmitterResumesAndIsTheSamePlant) {
  for (const std::string after : {"started", "fitted"}) {
    const fs::path db = dir_ / (after + ".sqlite"), out = dir_ / "out.jsonl", err = dir_ / "err.txt";
    const std::vector<json> killed = killWhen(
        {"plant", "capture", "--simulate", "--db", db.string(), "--speed", "20", "--seed", "5", "--json",
         "--relocate-source-after", "30"},
        [&](const std::vector<json>& lines) {
          const auto at = std::find_if(lines.begin(), lines.end(), [&](const json& j) {
            return j.value("event", "") == "relocation" && j.value("step", "") == after;
          });
          return at != lines.end() && lines.end() - at > 2;
        },
        out, err);
    ASSERT_FALSE(killed.empty()) << slurp(err);
    const std::int64_t id = killed.front().at("session");
    const Result done = leafdig("plant capture --resume " + std::to_string(id) + " --db " + quote(db) +
                                " --speed 20 --json </dev/null");
    ASSERT_EQ(done.exitCode, 0) << after << ": " << done.err;
    int cancelled = 0;
    for (const json& j : jsonLines(done.out)) cancelled += j.value("step", "") == "cancelled";
    EXPECT_EQ(cancelled, after == "started" ? 1 : 0) << after;
    const fs::path x = dir_ / ("x-" + after);
    ASSERT_EQ(leafdig("sessions export " + std::to_string(id) + " --db " + quote(db) + " --out " + quote(x) +
                      " --format json")
                  .exitCode,
              0);
    const json survey = json::parse(slurp(x / ("session-" + std::to_string(id) + ".survey.json")));
    EXPECT_EQ(survey.contains("transmitter_positions"), after == "fitted") << after;
    expectTheSamplePlant(survey, json::parse(leafdig(samplePlantMeasure()).out));
  }
}

// kill -9 on a turning pot: the capture is killed twice after a random acknowledged event and
// resumed with the pot turning again from where the resumed simulation starts; the session keeps
// its reference receiver, so every point before and after the kills is in the receiver's frame
// and the plant comes out as its file says.
TEST_F(PlantCli, APlantOnATurningPotKilledAndResumedKeepsItsReferenceFrame) {
  const fs::path db = dir_ / "station.sqlite", out = dir_ / "out.jsonl", err = dir_ / "err.txt";
  std::int64_t id = 0;
  std::mt19937 rng(11);
  for (int run = 0; run < 2; ++run) {
    const std::size_t k = std::uniform_int_distribution<std::size_t>(20, 60)(rng);
    std::vector<std::string> args{"plant",
                                  "capture",
                                  "--db",
                                  db.string(),
                                  "--speed",
                                  "20",
                                  "--json",
                                  "--pot-turn",
                                  "30",
                                  "--seed",
                                  std::to_string(run + 1)};
    if (id == 0)
      args.insert(args.end(), {"--simulate", "--reference-receiver"});
    else
      args.insert(args.end(), {"--resume", std::to_string(id)});
    const std::vector<json> lines = killAfterLines(args, k, out, err);
    ASSERT_FALSE(lines.empty()) << slurp(err);
    id = lines.front().at("session");
  }
  const Result done = leafdig("plant capture --resume " + std::to_string(id) + " --db " + quote(db) +
                              " --speed 20 --pot-turn 30 --json </dev/null");
  ASSERT_EQ(done.exitCode, 0) << done.err;
  const json list = json::parse(leafdig("sessions list --json --db " + quote(db)).out);
  ASSERT_EQ(list.size(), 1U);
  EXPECT_EQ(list[0].at("status"), "complete");
  ASSERT_EQ(leafdig("sessions export " + std::to_string(id) + " --db " + quote(db) + " --out " + quote(dir_ / "x") +
                    " --format json")
                .exitCode,
            0);
  expectTheSamplePlant(json::parse(slurp(dir_ / "x" / ("session-" + std::to_string(id) + ".survey.json"))),
                       json::parse(leafdig(samplePlantMeasure()).out));
  // A session begun without the reference receiver is not turned on resume.
  const fs::path plain = dir_ / "plain.sqlite";
  ASSERT_EQ(leafdig("plant capture --simulate --db " + quote(plain) + " --speed 20 --json </dev/null").exitCode, 0);
  const Result refused = leafdig("plant capture --resume 1 --db " + quote(plain) + " --pot-turn 30");
  EXPECT_EQ(refused.exitCode, 2);
  EXPECT_NE(refused.err.find("was not begun as a simulation with a reference receiver"), std::string::npos)
      << refused.err;
}

TEST_F(PlantCli, ACapturedPlantIsExportedAsAModelEveryReaderOpensAndAsAPlanPlantBuildTakes) {
  const fs::path db = dir_ / "station.sqlite";
  const Result r = leafdig("plant capture --simulate --db " + quote(db) + " --speed 20 --seed 3 --json");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const std::int64_t id = jsonLines(r.out).front().at("session");
  const fs::path out = dir_ / "out";
  const Result exported = leafdig("sessions export " + std::to_string(id) + " --db " + quote(db) + " --out " +
                                  quote(out) + " --format json,glb,obj,can,model,plan --json");
  ASSERT_EQ(exported.exitCode, 0) << exported.err;
  const json report = json::parse(exported.out);
  const std::string base = (out / ("session-" + std::to_string(id))).string();
  std::set<std::string> written;
  for (const json& f : report.at("outputs")) written.insert(f.get<std::string>());
  for (const std::string ext : {".survey.json", ".glb", ".obj", ".can", ".opt", ".plant-model.json", ".plant.json"})
    EXPECT_EQ(written.count(base + ext), 1U) << ext;
  EXPECT_EQ(written.count(base + ".leaves/leaf-2.markers.json"), 1U);
  // The sample's two quick leaves were chosen as "lower" leaves; this station approved none.
  ASSERT_EQ(report.at("notes").size(), 2U) << report;
  for (const json& n : report.at("notes")) {
    EXPECT_NE(n.get<std::string>().find("built-in sample shape"), std::string::npos) << n;
    EXPECT_NE(n.get<std::string>().find("no approved leaf of type \"lower\""), std::string::npos) << n;
  }

  // glTF: the Khronos validator; the stem and the three leaves with points (nodes 2, 3, 4).
  const Result check = run("node " + quote(std::string(LEAFDIG_SOURCE_DIR) + "/tests/tools/validate-gltf.mjs") + " " +
                           quote(base + ".glb"));
  ASSERT_EQ(check.exitCode, 0) << check.out << check.err;
  EXPECT_EQ(json::parse(check.out)["numErrors"], 0) << check.out;
  const std::string glb = slurp(base + ".glb");
  for (const char* node : {"\"plant/stem/I1\"", "\"plant/stem/I5\"", "\"plant/leaf-2/blade\"", "\"plant/leaf-3/blade\"",
                           "\"plant/leaf-4/blade\""})
    EXPECT_NE(glb.find(node), std::string::npos) << node;
  EXPECT_EQ(glb.find("\"plant/leaf-1/"), std::string::npos);  // node 1 has no leaf
  // One glTF node per MTG entity: I0 then each I<k> a child of the internode it follows, each
  // L<k> a child of I<k> holding its organs, the stem's piece between node k-1 and node k
  // under I<k> (the collar for k = 1), nothing left under I0; each entity's MTG
  // features in its extras, equal to the survey's. Read from the GLB's JSON chunk.
  {
    ASSERT_GT(glb.size(), 20U);
    std::uint32_t length = 0;
    std::memcpy(&length, glb.data() + 12, 4);
    const json gltf = json::parse(glb.substr(20, length));
    const json& nodes = gltf.at("nodes");
    std::map<std::string, std::size_t> at;
    for (std::size_t i = 0; i < nodes.size(); ++i) at[nodes[i].at("name").get<std::string>()] = i;
    const auto children = [&](const std::string& name) {
      std::set<std::string> out;
      for (const json& c : nodes[at.at(name)].value("children", json::array()))
        out.insert(nodes[c.get<std::size_t>()].at("name").get<std::string>());
      return out;
    };
    const json& root = nodes[gltf.at("scenes")[0].at("nodes")[0].get<std::size_t>()];
    EXPECT_EQ(root.at("name"), "tobacco-p12");
    EXPECT_EQ(root.at("extras").at("date"), "2026-06-12");
    EXPECT_EQ(children("I0"), (std::set<std::string>{"I1"}));
    EXPECT_EQ(children("I1"), (std::set<std::string>{"I2", "L1", "plant/stem/I1"}));
    EXPECT_EQ(children("I4"), (std::set<std::string>{"I5", "L4", "plant/stem/I4"}));
    EXPECT_EQ(children("I5"), (std::set<std::string>{"plant/stem/I5"}));
    // Each internode's piece lies between its two nodes' heights (glTF +Y is the frame's +Z,
    // in metres).
    const json& accessors = gltf.at("accessors");
    const json& meshes = gltf.at("meshes");
    const json heights = json::parse(slurp(base + ".survey.json")).at("nodes");
    for (int k = 1; k <= 5; ++k) {
      const json& piece = nodes[at.at("plant/stem/I" + std::to_string(k))];
      const json& position = accessors[meshes[piece.at("mesh").get<std::size_t>()]
                                           .at("primitives")[0]
                                           .at("attributes")
                                           .at("POSITION")
                                           .get<std::size_t>()];
      const double below = k == 1 ? 0.0 : heights[k - 2].at("height_mm").get<double>() / 1000.0;
      const double above = heights[k - 1].at("height_mm").get<double>() / 1000.0;
      EXPECT_GE(position.at("min")[1].get<double>(), below - 0.02) << k;  // a ring's radius of slack
      EXPECT_LE(position.at("max")[1].get<double>(), above + 0.02) << k;
      EXPECT_GT(position.at("max")[1].get<double>(), below) << k;
    }
    EXPECT_TRUE(children("L1").empty()) << "node 1's leaf is dead, not drawn";
    EXPECT_EQ(nodes[at.at("L1")].at("extras").at("State"), "dead");
    const std::set<std::string> leaf2 = children("L2");
    EXPECT_EQ(leaf2.count("plant/leaf-2/blade"), 1U);
    EXPECT_EQ(leaf2.count("plant/leaf-2/midrib"), 1U);
    const json survey = json::parse(slurp(base + ".survey.json"));
    for (const json& l : survey.at("leaves")) {
      if (l.at("kind") == "none") continue;
      const json& extras = nodes[at.at("L" + std::to_string(l.at("node").get<int>()))].at("extras");
      EXPECT_NEAR(extras.at("Azimuth").get<double>(), l.at("azimuth_deg").get<double>(), 1e-9) << l;
      EXPECT_NEAR(extras.at("Inclination").get<double>(), l.at("inclination_deg").get<double>(), 1e-9) << l;
      EXPECT_EQ(extras.at("Kind"), l.at("kind")) << l;
    }
    for (const json& n : survey.at("nodes"))
      EXPECT_NEAR(nodes[at.at("I" + std::to_string(n.at("node").get<int>()))].at("extras").at("TopDia").get<double>(),
                  n.at("diameter_mm").get<double>(), 1e-9);
  }
  ASSERT_EQ(run("command -v assimp").exitCode, 0) << "assimp is not installed: run scripts/setup.sh";
  EXPECT_EQ(run("assimp info " + quote(base + ".obj")).exitCode, 0);
  EXPECT_EQ(run("assimp info " + quote(base + ".glb")).exitCode, 0);
  // CARIBU: the strict reader; the stem (leaf field 0) and leaves 2, 3 and 4.
  const auto can =
      leafdig::test::readCanStrictly(slurp(base + ".can"), leafdig::test::readOptStrictly(slurp(base + ".opt")));
  std::set<int> leaves;
  for (const auto& t : can) leaves.insert(t.leaf);
  EXPECT_EQ(leaves, (std::set<int>{0, 2, 3, 4}));
  // For a light model (issue 51): the blades alone at the preview resolution — no stem, no vein
  // tubes, a fraction of the triangles — read by the same strict reader; the GLB of the same
  // choice is valid and names no vein. The full leaf alone likewise (a leaf's export).
  const fs::path light = dir_ / "light";
  ASSERT_EQ(leafdig("sessions export " + std::to_string(id) + " --db " + quote(db) + " --out " + quote(light) +
                    " --format can,glb --organs blade --resolution preview")
                .exitCode,
            0);
  const std::string lightBase = (light / ("session-" + std::to_string(id))).string();
  const auto blades = leafdig::test::readCanStrictly(slurp(lightBase + ".can"),
                                                     leafdig::test::readOptStrictly(slurp(lightBase + ".opt")));
  std::set<int> bladeLeaves;
  for (const auto& t : blades) bladeLeaves.insert(t.leaf);
  EXPECT_EQ(bladeLeaves, (std::set<int>{2, 3, 4}));
  EXPECT_LT(blades.size() * 4, can.size()) << blades.size() << " of " << can.size();
  const std::string lightGlb = slurp(lightBase + ".glb");
  EXPECT_EQ(lightGlb.find("midrib"), std::string::npos);
  EXPECT_NE(lightGlb.find("plant/leaf-2/blade"), std::string::npos);
  ASSERT_EQ(leafdig("sessions export " + std::to_string(id) + " --db " + quote(db) + " --out " + quote(light) +
                    " --node 2 --format obj --organs blade")
                .exitCode,
            0);
  for (const auto& e : fs::directory_iterator(light))
    if (e.path().extension() == ".obj") {
      const std::string obj = slurp(e.path());
      EXPECT_NE(obj.find("\no blade\n"), std::string::npos) << e.path();
      EXPECT_EQ(obj.find("\no midrib\n"), std::string::npos) << e.path();
    }
  EXPECT_EQ(leafdig("sessions export " + std::to_string(id) + " --db " + quote(db) + " --out " + quote(light) +
                    " --organs leaves")
                .exitCode,
            2);

  // The full leaf's area in the model is the survey's (the same markers, meshed).
  const json survey = json::parse(slurp(base + ".survey.json"));
  const json model = json::parse(slurp(base + ".plant-model.json"));
  double fullArea = 0.0;
  for (const json& l : survey.at("leaves"))
    if (l.at("node") == 2) fullArea = l.at("area_mm2").get<double>();
  ASSERT_GT(fullArea, 0.0);
  for (const json& l : model.at("leaves")) {
    if (l.at("rank") == 2) {
      EXPECT_NEAR(l.at("area_mm2").get<double>(), fullArea, 0.01 * fullArea);
      EXPECT_EQ(l.at("source"), "digitized");
    }
  }

  // The plan and its leaves' files: valid against the shipped schemas (Ajv).
  const std::string schemas = std::string(LEAFDIG_SOURCE_DIR) + "/data/schema/";
  const std::string ajv = "node " + quote(std::string(LEAFDIG_SOURCE_DIR) + "/tests/tools/validate-schema.mjs") + " ";
  const Result planValid =
      run(ajv + quote(schemas + "leafdig.plant-1.schema.json") + " " + quote(base + ".plant.json"));
  EXPECT_EQ(planValid.exitCode, 0) << planValid.out << planValid.err;
  const Result leafValid =
      run(ajv + quote(schemas + "leafdig.markers-1.schema.json") + " " + quote(base + ".leaves/leaf-3.markers.json"));
  EXPECT_EQ(leafValid.exitCode, 0) << leafValid.out << leafValid.err;
  // The plan: plant build takes it as it is (from another folder), with every leaf, and the
  // full leaf keeps its area; its stem is as tall as the one digitized.
  const Result built = leafdig("plant build " + quote(base + ".plant.json") + " -o " + quote(dir_ / "again.glb") +
                               " --resolution preview --json");
  ASSERT_EQ(built.exitCode, 0) << built.err;
  const json state = json::parse(built.out).at("states").at(0);
  ASSERT_EQ(state.at("leaves").size(), 3U);
  for (const json& l : state.at("leaves")) {
    if (l.at("rank") == 2) {
      EXPECT_NEAR(l.at("area_mm2").get<double>(), fullArea, 0.02 * fullArea);
    }
  }
  double along = 0.0;  // the polyline through collar and nodes, as the plan measures it
  std::array<double, 3> below{0, 0, 0};
  for (const json& n : survey.at("nodes")) {
    double d2 = 0;
    for (std::size_t c = 0; c < 3; ++c) d2 += std::pow(n.at("point_mm")[c].get<double>() - below[c], 2);
    along += std::sqrt(d2);
    for (std::size_t c = 0; c < 3; ++c) below[c] = n.at("point_mm")[c].get<double>();
  }
  EXPECT_NEAR(state.at("stem_height_mm").get<double>(), along, 1e-6);
  // A format the plant does not have is named, with the ones it has.
  const Result bad = leafdig("sessions export " + std::to_string(id) + " --db " + quote(db) + " --out " +
                             quote(dir_ / "bad") + " --format gltf");
  EXPECT_EQ(bad.exitCode, 2);
  EXPECT_NE(bad.err.find("glb, obj, ply, stl, can, model, plan, xml (Helios) or vgx (VegeSTAR)"), std::string::npos)
      << bad.err;
  EXPECT_FALSE(fs::exists(dir_ / "bad"));
}

TEST_F(PlantCli, APlantsFullLeafIsExportedAloneAsADetachedLeafIs) {
  const fs::path db = dir_ / "station.sqlite";
  const Result r = leafdig("plant capture --simulate --db " + quote(db) + " --speed 20 --seed 4 --json");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const std::string id = std::to_string(jsonLines(r.out).front().at("session").get<std::int64_t>());
  const fs::path out = dir_ / "out";
  ASSERT_EQ(
      leafdig("sessions export " + id + " --db " + quote(db) + " --out " + quote(out) + " --format json").exitCode, 0);
  const Result leaf =
      leafdig("sessions export " + id + " --db " + quote(db) + " --out " + quote(out) + " --node 2 --json");
  ASSERT_EQ(leaf.exitCode, 0) << leaf.err;
  const json report = json::parse(leaf.out);
  const std::string base = (out / ("session-" + id + ".node-2")).string();
  std::set<std::string> written;
  for (const json& f : report.at("outputs")) written.insert(f.get<std::string>());
  for (const std::string ext : {".glb", ".obj", ".ply", ".stl", ".model.json", ".markers.json", ".markers.csv",
                                ".thickness.csv", ".metrics.csv"})
    EXPECT_EQ(written.count(base + ext), 1U) << ext;
  // Its area is the survey's for that leaf: the same markers, the same model.
  double surveyed = 0.0;
  const json survey = json::parse(slurp(out / ("session-" + id + ".survey.json")));
  for (const json& l : survey.at("leaves"))
    if (l.at("node") == 2) surveyed = l.at("area_mm2").get<double>();
  ASSERT_GT(surveyed, 0.0);
  EXPECT_NEAR(report.at("metrics").at("blade_area_mm2").get<double>(), surveyed, 1e-3 * surveyed);
  // The Khronos validator takes its GLB; its markers are a leaf's file `model build` reads.
  const Result check = run("node " + quote(std::string(LEAFDIG_SOURCE_DIR) + "/tests/tools/validate-gltf.mjs") + " " +
                           quote(base + ".glb"));
  ASSERT_EQ(check.exitCode, 0) << check.out << check.err;
  EXPECT_EQ(json::parse(check.out)["numErrors"], 0) << check.out;
  const Result rebuilt = leafdig("model build " + quote(base + ".markers.json") + " --json");
  ASSERT_EQ(rebuilt.exitCode, 0) << rebuilt.err;
  const json again = json::parse(rebuilt.out);
  EXPECT_EQ(again.at("leaf"), "tobacco-p12 node 2");
  EXPECT_NEAR(again.at("metrics").at("blade_area_mm2").get<double>(), surveyed, 1e-3 * surveyed);
  // The CSV holds that leaf's items alone, in a leaf's words.
  const std::string csv = slurp(base + ".markers.csv");
  EXPECT_EQ(csv.find("node"), std::string::npos);
  EXPECT_EQ(csv.find("landmark"), std::string::npos);
  EXPECT_NE(csv.find(",tip,"), std::string::npos) << csv.substr(0, 200);
  // A node whose leaf was not taken in full, and a leaf session, are refused in words.
  const Result quick =
      leafdig("sessions export " + id + " --db " + quote(db) + " --out " + quote(dir_ / "q") + " --node 3");
  EXPECT_EQ(quick.exitCode, 2);
  EXPECT_NE(quick.err.find("has no full leaf at node 3: its full leaves are at node 2"), std::string::npos)
      << quick.err;
  EXPECT_FALSE(fs::exists(dir_ / "q"));
}

// A curator corrects a captured plant through `sessions correct`: a node's point moves the
// exported node, a full leaf's marker its leaf; what does not fit is refused with exit 2 and
// nothing written; the corrected plant approves as any other.
TEST_F(PlantCli, ACuratorCorrectsAPlantsPointAndAFullLeafsMarkerThroughSessionsCorrect) {
  const fs::path db = dir_ / "station.sqlite";
  const Result r = leafdig("plant capture --simulate --db " + quote(db) + " --speed 20 --seed 4 --json");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const std::string id = std::to_string(jsonLines(r.out).front().at("session").get<std::int64_t>());
  const auto survey = [&](const std::string& dir) {
    EXPECT_EQ(leafdig("sessions export " + id + " --db " + quote(db) + " --out " + quote(dir_ / dir) +
                      " --format json,markers")
                  .exitCode,
              0);
    return std::make_pair(json::parse(slurp(dir_ / dir / ("session-" + id + ".survey.json"))),
                          json::parse(slurp(dir_ / dir / ("session-" + id + ".plant-markers.json"))));
  };
  const auto [before, markersBefore] = survey("before");
  const json p4 = markersBefore.at("nodes").at(3).at("point");
  const std::string moved = std::to_string(p4[0].get<double>() + 3.0) + "," + std::to_string(p4[1].get<double>()) +
                            "," + std::to_string(p4[2].get<double>());
  // The plant-markers file's points are the digitizer's: said so (a plant's default is the plant frame).
  const Result fixed = leafdig("sessions correct " + id + " --db " + quote(db) + " --what point --row 4 --position " +
                               moved + " --frame digitizer --who kim --why 'stylus off the node'");
  ASSERT_EQ(fixed.exitCode, 0) << fixed.err;
  EXPECT_NE(fixed.out.find("point corrected by kim"), std::string::npos) << fixed.out;
  const Result leaf =
      leafdig("sessions correct " + id + " --db " + quote(db) +
              " --node 2 --what midrib_thickness --row 3 --col 4 --value 0.9 --who kim --why 'on the vein'");
  ASSERT_EQ(leaf.exitCode, 0) << leaf.err;
  const auto [after, markersAfter] = survey("after");
  EXPECT_NEAR(markersAfter.at("nodes").at(3).at("point")[0].get<double>(), p4[0].get<double>() + 3.0, 1e-5);
  EXPECT_EQ(markersAfter.at("nodes").at(2), markersBefore.at("nodes").at(2));  // nothing else moved
  const json n4a = after.at("nodes").at(3).at("point_mm"), n4b = before.at("nodes").at(3).at("point_mm");
  EXPECT_NEAR(std::hypot(n4a[0].get<double>() - n4b[0].get<double>(), n4a[1].get<double>() - n4b[1].get<double>()), 3.0,
              0.05);  // the node moved 3 mm across, in the plant frame too
  EXPECT_EQ(leafdig("sessions verify " + id + " --db " + quote(db)).exitCode, 0);
  // `sessions show` names both corrections, with who and why, and the corrected point.
  const json shown = json::parse(leafdig("sessions show " + id + " --json --db " + quote(db)).out);
  EXPECT_EQ(shown.at("kind"), "plant");
  EXPECT_EQ(shown.at("status"), "complete");
  EXPECT_EQ(shown.at("nodes"), 5);
  ASSERT_EQ(shown.at("corrections").size(), 2U);
  EXPECT_EQ(shown.at("corrections")[0].at("what"), "point");
  EXPECT_EQ(shown.at("corrections")[0].at("reason"), "stylus off the node");
  EXPECT_EQ(shown.at("corrections")[1].at("what"), "node2.midrib_thickness");
  for (const json& p : shown.at("points"))
    if (p.at("what") == "point" && p.at("row") == 4) {
      EXPECT_NEAR(p.at("position_mm")[0].get<double>(), p4[0].get<double>() + 3.0, 1e-5);
    }
  EXPECT_EQ(shown.at("leaves")[1].at("kind"), "full");
  // Every point is shown in the plant frame too, where the survey has it.
  for (const json& p : shown.at("points")) {
    if (p.at("what") != "point" || p.at("row") != 4) continue;
    for (int k = 0; k < 3; ++k) {
      EXPECT_NEAR(p.at("position_plant_mm")[k].get<double>(), n4a[k].get<double>(), 1e-6);
    }
  }
  // By default a plant's point is corrected in the plant frame, as the survey reads: node 5's
  // point 2 mm up there is 2 mm up in the survey, whatever the digitizer's axes.
  const json n5 = after.at("nodes").at(4).at("point_mm");
  const std::string up = std::to_string(n5[0].get<double>()) + "," + std::to_string(n5[1].get<double>()) + "," +
                         std::to_string(n5[2].get<double>() + 2.0);
  // First as a dry run: node 5 would stand 2 mm higher, nothing written.
  const Result dry = leafdig("sessions correct " + id + " --db " + quote(db) + " --what point --row 5 --position " +
                             up + " --dry-run --json --who kim --why 'pressed below the node'");
  ASSERT_EQ(dry.exitCode, 0) << dry.err;
  bool height = false;
  const json dryEffect = json::parse(dry.out);
  for (const json& ch : dryEffect.at("changes"))
    if (ch.at("what") == "node 5 height_mm") {
      height = true;
      EXPECT_NEAR(ch.at("after").get<double>() - ch.at("before").get<double>(), 2.0, 1e-4);
    }
  EXPECT_TRUE(height) << dry.out;
  EXPECT_EQ(json::parse(leafdig("sessions show " + id + " --json --db " + quote(db)).out).at("corrections").size(), 2U);
  const Result inPlant = leafdig("sessions correct " + id + " --db " + quote(db) + " --what point --row 5 --position " +
                                 up + " --who kim --why 'pressed below the node' --json");
  ASSERT_EQ(inPlant.exitCode, 0) << inPlant.err;
  EXPECT_EQ(json::parse(inPlant.out).at("frame"), "plant");
  EXPECT_NEAR(json::parse(inPlant.out).at("moved_mm").get<double>(), 2.0, 1e-4);
  const auto [upped, markersUpped] = survey("upped");
  for (int k = 0; k < 3; ++k)
    EXPECT_NEAR(upped.at("nodes").at(4).at("point_mm")[k].get<double>(), n5[k].get<double>() + (k == 2 ? 2.0 : 0.0),
                1e-4);
  // Refused, exit 2, named, nothing written.
  const std::int64_t events =
      json::parse(leafdig("sessions show " + id + " --json --db " + quote(db)).out).at("events");
  for (const auto& [args, words] : std::vector<std::pair<std::string, std::string>>{
           {"--what stem --row 1 --value 3", "is not an item"},
           {"--what reading --row 9 --value 3", "has no reading 9"},
           {"--what reading --row 2 --position 1,2,3", "with a value in mm"},
           {"--node 3 --what marker --row 1 --col 1 --position 1,2,3", "that node has no full leaf"},
           {"--node 2 --what landmark --row 1 --position 1,2,3", "node 2 is a full leaf: its items are tip, marker"},
           {"--what collar_diameter --value 1e9", "outside this session's range"}}) {
    const Result bad = leafdig("sessions correct " + id + " --db " + quote(db) + " " + args + " --who kim --why x");
    EXPECT_EQ(bad.exitCode, 2) << args << ": " << bad.err;
    EXPECT_NE(bad.err.find(words), std::string::npos) << args << ": " << bad.err;
  }
  EXPECT_EQ(json::parse(leafdig("sessions show " + id + " --json --db " + quote(db)).out).at("events"), events);
  ASSERT_EQ(leafdig("sessions approve " + id + " --db " + quote(db) + " --who kim --why 'against the photos'").exitCode,
            0);
  EXPECT_EQ(leafdig("sessions correct " + id + " --db " + quote(db) +
                    " --what reading --row 2 --value 9 --who kim "
                    "--why late")
                .exitCode,
            2);
  // Every file of the approved plant says where it came from (issue 49): the MTG's and the
  // CSV's `#` lines (the strict MTG reader still takes it), the survey's JSON.
  ASSERT_EQ(leafdig("sessions export " + id + " --db " + quote(db) + " --out " + quote(dir_ / "approved") +
                    " --format mtg,csv,json")
                .exitCode,
            0);
  const std::string base = (dir_ / "approved" / ("session-" + id)).string();
  const std::string mtg = slurp(base + ".mtg");
  EXPECT_EQ(mtg.rfind("# session: " + id + "\n", 0), 0U) << mtg.substr(0, 300);
  EXPECT_NE(mtg.find("\n# decision: approved\n# curator: kim\n"), std::string::npos) << mtg.substr(0, 300);
  EXPECT_NE(mtg.find("\n# corrections: 3\n"), std::string::npos) << mtg.substr(0, 300);
  EXPECT_NO_THROW((void)leafdig::test::readMtgStrictly(mtg));
  EXPECT_NE(slurp(base + ".plant.csv").find("\n# status: approved\n"), std::string::npos);
  const json provenance = json::parse(slurp(base + ".survey.json")).at("provenance");
  EXPECT_EQ(provenance.at("curator"), "kim");
  EXPECT_EQ(provenance.at("session"), id);
}

TEST_F(PlantCli, RepeatSurveysOfOnePlantAreListedByTheirDay) {
  const fs::path db = dir_ / "station.sqlite";
  // The sample plant surveyed in July, then again dated by its file (12 June); another plant.
  ASSERT_EQ(leafdig("plant capture --simulate --db " + quote(db) + " --speed 20 --date 2026-07-01").exitCode, 0);
  ASSERT_EQ(leafdig("plant capture --simulate --db " + quote(db) + " --speed 20").exitCode, 0);
  ASSERT_EQ(
      leafdig("plant capture --simulate --db " + quote(db) + " --speed 20 --plant-markers " + quote(synthPlant(4, 3)))
          .exitCode,
      0);
  const Result r = leafdig("plant surveys tobacco-p12 --db " + quote(db) + " --json");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const json j = json::parse(r.out);
  EXPECT_EQ(j.at("plant"), "tobacco-p12");
  const json& surveys = j.at("surveys");
  ASSERT_EQ(surveys.size(), 2U) << j;
  EXPECT_EQ(surveys[0].at("date"), "2026-06-12");
  EXPECT_EQ(surveys[0].at("session"), 2);
  EXPECT_EQ(surveys[1].at("date"), "2026-07-01");
  EXPECT_EQ(surveys[1].at("session"), 1);
  for (const json& s : surveys) {
    EXPECT_EQ(s.at("status"), "complete");
    EXPECT_TRUE(s.at("verified").get<bool>());
    EXPECT_EQ(s.at("nodes"), 5);
    EXPECT_EQ(s.at("leaves"), (json{{"full", 1}, {"quick", 2}, {"none", 2}}));
  }
  // Each survey's MTG carries its own day.
  const Result exported =
      leafdig("sessions export 1 --db " + quote(db) + " --out " + quote(dir_ / "x") + " --format mtg");
  ASSERT_EQ(exported.exitCode, 0) << exported.err;
  EXPECT_NE(slurp(dir_ / "x" / "session-1.mtg").find("01/07/2026"), std::string::npos);
  // In words; a plant never surveyed has none; no file, no listing.
  const Result text = leafdig("plant surveys tobacco-p12 --db " + quote(db));
  EXPECT_NE(text.out.find("2 survey(s)"), std::string::npos) << text.out;
  EXPECT_NE(text.out.find("2026-06-12  session 2  complete  5 nodes (1 full, 2 quick, 2 without a leaf)"),
            std::string::npos)
      << text.out;
  EXPECT_EQ(json::parse(leafdig("plant surveys nobody --db " + quote(db) + " --json").out).at("surveys").size(), 0U);
  const Result missing = leafdig("plant surveys tobacco-p12 --db " + quote(dir_ / "none.sqlite"));
  EXPECT_EQ(missing.exitCode, 2);
  EXPECT_NE(missing.err.find("no station database"), std::string::npos) << missing.err;
  EXPECT_FALSE(fs::exists(dir_ / "none.sqlite"));
}

// A simulated plant capture that gets nowhere is stopped in words and kept, never waited on for
// ever. Here at real speed with a 1-s limit: the first landmark's gesture alone takes 1.4 s of
// the device's clock (travel, settle, press), so nothing can be taken within the second — on
// any machine; a slower one only takes longer.
TEST_F(PlantCli, ASimulatedPlantCaptureThatGetsNowhereIsStoppedInWordsAndKept) {
  const fs::path db = dir_ / "station.sqlite";
  const Result r = leafdig("plant capture --simulate --speed 1 --give-up-after 1 --db " + quote(db) + " </dev/null");
  EXPECT_EQ(r.exitCode, 1) << r.out << r.err;
  EXPECT_NE(r.err.find("the simulated technician got nowhere for 1 s before its first input was taken"),
            std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("'leafdig sessions show 1 --db "), std::string::npos) << r.err;
  EXPECT_NE(r.out.find("plant session 1 kept open"), std::string::npos) << r.out;
  const Result listed = leafdig("sessions list --json --db " + quote(db));
  ASSERT_EQ(listed.exitCode, 0) << listed.err;
  const json sessions = json::parse(listed.out);
  ASSERT_EQ(sessions.size(), 1U);
  EXPECT_EQ(sessions[0].at("status"), "open");
  EXPECT_EQ(leafdig("plant capture --simulate --give-up-after 0.5 --db " + quote(dir_ / "x.sqlite")).exitCode, 2);
}

TEST_F(PlantCli, PlantCaptureRefusesWhatItCannotDoInWordsBeforeTheStoreIsTouched) {
  const fs::path db = dir_ / "station.sqlite";
  const Result real = leafdig("plant capture --db " + quote(db));
  EXPECT_EQ(real.exitCode, 2);
  EXPECT_NE(real.err.find("give the devices"), std::string::npos) << real.err;
  // A branch's branches: a protocol plant capture cannot follow.
  std::ofstream(dir_ / "deep.plant-protocol.json")
      << R"({"format": "leafdig.plant-protocol/1", "species": "x", "entities": [
           {"name": "internode", "class": "I", "repeat": true, "points": ["node"]},
           {"name": "branch", "class": "B", "parent": "internode", "relation": "+", "repeat": true, "points": ["node"]},
           {"name": "twig", "class": "T", "parent": "branch", "relation": "+", "repeat": true, "points": ["node"]}]})";
  const Result branched =
      leafdig("plant capture --simulate --db " + quote(db) + " --protocol " + quote(dir_ / "deep.plant-protocol.json"));
  EXPECT_NE(branched.exitCode, 0);
  EXPECT_NE(branched.err.find("axis of order 3"), std::string::npos) << branched.err;
  const Result date = leafdig("plant capture --simulate --db " + quote(db) + " --date 2026-02-30");
  EXPECT_EQ(date.exitCode, 2);
  EXPECT_NE(date.err.find("YYYY-MM-DD"), std::string::npos) << date.err;
  const Result missing =
      leafdig("plant capture --simulate --db " + quote(db) + " --plant-markers " + quote(dir_ / "nowhere.json"));
  EXPECT_EQ(missing.exitCode, 2);
  // Nothing of these was stored (the refused protocol wrote no session either).
  const Result list = leafdig("sessions list --json --db " + quote(db));
  if (list.exitCode == 0) {
    EXPECT_EQ(json::parse(list.out).size(), 0U);
  }
}

// A plant digitized with devices on real ports: the digitizer and caliper of `leafdig sim` on
// pseudo-terminals, named like any serial port. The loop takes their records (a landmark
// accepted or a press refused in words), commands come on standard input, `quit` keeps the
// session open with its ports recorded, and `--resume` goes on with them.
TEST_F(PlantCli, APlantIsTakenWithDevicesOnTheOperatorsPortsAndCommandsOnStandardInput) {
  const std::string db = (dir_ / "station.sqlite").string();
  const fs::path fk = dir_ / "fastrak", sv = dir_ / "sylvac";
  const std::string leaf = sample("upper-small-leaf-n17.markers.json");
  const pid_t fastrak =
      spawn({"sim", "fastrak", "--markers", leaf, "--link", fk.string(), "--seconds", "12", "--seed", "3"},
            dir_ / "fk.out", dir_ / "fk.err");
  const pid_t sylvac =
      spawn({"sim", "sylvac", "--markers", leaf, "--link", sv.string(), "--press-every", "1", "--seconds", "12"},
            dir_ / "sv.out", dir_ / "sv.err");
  for (int i = 0; i < 100 && !(fs::exists(fk) && fs::exists(sv)); ++i) ::usleep(50'000);
  ASSERT_TRUE(fs::exists(fk) && fs::exists(sv)) << slurp(dir_ / "fk.err") << slurp(dir_ / "sv.err");
  // Node 1's leaf chosen by command, a word the loop does not know refused, a retake of what was
  // not taken refused by the engine and one that names no item by the command's words, then quit
  // after 8 s.
  const Result r =
      run("(echo 'leaf 1 quick lower'; echo 'leaf 1 sideways'; echo 'retake landmark 99'; "
          "echo 'retake stem 2'; sleep 8; echo quit) | " +
          quote(LEAFDIG_CLI) + " plant capture --digitizer fastrak:" + quote(fk.string()) +
          " --caliper sylvac:" + quote(sv.string()) + " --plant P-ports --db " + quote(db) + " --json");
  EXPECT_EQ(r.exitCode, 0) << r.err;
  const std::vector<json> lines = jsonLines(r.out);
  ASSERT_FALSE(lines.empty());
  EXPECT_EQ(lines.front().value("event", ""), "session");
  std::set<std::string> streaming, events;
  for (const json& j : lines) {
    events.insert(j.value("event", ""));
    if (j.value("event", "") == "device" && j.value("state", "") == "streaming")
      streaming.insert(j.value("device", ""));
  }
  EXPECT_EQ(streaming, (std::set<std::string>{"FASTRAK", "Sylvac"})) << r.out;
  EXPECT_TRUE(events.count("leaf_chosen")) << r.out;
  EXPECT_TRUE(events.count("accepted") || events.count("rejected")) << "the ports' records reach the plant: " << r.out;
  EXPECT_NE(r.err.find("sideways"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("retake stem?"), std::string::npos) << r.err;
  bool retakeRefused = false;
  for (const json& j : lines)
    retakeRefused =
        retakeRefused || (j.value("event", "") == "rejected" &&
                          j.value("reason", "").find("nothing was captured as landmark 99") != std::string::npos);
  EXPECT_TRUE(retakeRefused) << r.out;
  {
    const Result list = leafdig("sessions list --db " + quote(db) + " --json");
    ASSERT_EQ(list.exitCode, 0) << list.err;
    const json sessions = json::parse(list.out);
    ASSERT_EQ(sessions.size(), 1u);
    EXPECT_EQ(sessions[0].value("kind", ""), "plant");
    EXPECT_EQ(sessions[0].value("plant", ""), "P-ports");
    EXPECT_EQ(sessions[0].value("status", ""), "open");
  }
  reap(fastrak);
  reap(sylvac);
  // Resumed on the recorded ports, now gone: the session goes on, the device says why in words.
  const Result again =
      run("(sleep 1; echo quit) | " + quote(LEAFDIG_CLI) + " plant capture --resume 1 --db " + quote(db));
  EXPECT_EQ(again.exitCode, 0) << again.err;
  EXPECT_NE(again.out.find("digitizer fastrak:" + fk.string()), std::string::npos) << again.out;
  EXPECT_NE(again.err.find("cannot open " + fk.string()), std::string::npos) << again.err;
  EXPECT_NE(again.out.find("kept open"), std::string::npos) << again.out;
}

TEST_F(PlantCli, APlantCaptureWithoutItsDevicesOrPlantIsRefusedBeforeAnythingIsWritten) {
  const std::string db = (dir_ / "station.sqlite").string();
  struct Case {
    std::string args, says;
  };
  for (const Case& c : std::vector<Case>{
           {"plant capture --plant P --db " + quote(db), "--digitizer fastrak:/dev/ttyUSB0"},
           {"plant capture --digitizer fastrak:/dev/ttyS0 --caliper sylvac:/dev/ttyS1 --db " + quote(db), "--plant ID"},
           {"plant capture --digitizer wand:/dev/ttyS0 --caliper sylvac:/dev/ttyS1 --plant P --db " + quote(db),
            "wand"},
           {"plant capture --simulate --digitizer fastrak:/dev/ttyS0 --db " + quote(db), "leave out --digitizer"},
       }) {
    const Result r = leafdig(c.args);
    EXPECT_EQ(r.exitCode, 2) << c.args << "\n" << r.err;
    EXPECT_NE(r.err.find(c.says), std::string::npos) << c.args << "\n" << r.err;
    EXPECT_FALSE(fs::exists(db)) << c.args;
  }
}
