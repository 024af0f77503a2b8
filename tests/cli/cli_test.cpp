// Drives the `leafdig` executable as a user would and checks exit codes, messages, files,
// and that the exported files open in other tools (Khronos glTF validator, assimp).
#include <set>

#include "cli_support.hpp"

namespace {

TEST_F(Cli, helpAndVersionExitZero) {
  const Result help = leafdig("--help");
  EXPECT_EQ(help.exitCode, 0);
  EXPECT_NE(help.out.find("Exit codes"), std::string::npos);
  const Result version = leafdig("--version");
  EXPECT_EQ(version.exitCode, 0);
  ASSERT_EQ(version.out.rfind("leafdig ", 0), 0u) << version.out;
  EXPECT_EQ(std::count(version.out.begin(), version.out.end(), '.'), 2) << version.out;
  EXPECT_TRUE(std::isdigit(static_cast<unsigned char>(version.out[8]))) << version.out;
  const Result buildHelp = leafdig("model build --help");
  EXPECT_EQ(buildHelp.exitCode, 0);
  EXPECT_NE(buildHelp.out.find("--resolution"), std::string::npos);
}

TEST_F(Cli, unknownOptionIsBadInput) {
  const Result r = leafdig("model build " + quote(sample("lower-leaf-n10.markers.json")) + " --resolution ultra");
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_NE(r.err.find("ultra"), std::string::npos) << r.err;
}

TEST_F(Cli, jsonReportsTable1CountsAndMetricsForEverySample) {
  struct Row {
    const char* file;
    int vv, vq, bv, bq;
    bool broadBase;  // its lowest veins meet the margin far up: the base-row warning stands
  };
  for (const Row& row : {Row{"lower-leaf-n10.markers.json", 3610, 3500, 1581, 1500, false},
                         Row{"upper-small-leaf-n17.markers.json", 6130, 5950, 2666, 2550, true},
                         Row{"upper-curved-leaf-n14.markers.json", 5050, 4900, 2201, 2100, false}}) {
    const Result r = leafdig("model build " + quote(sample(row.file)) + " --resolution paper --json");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const json out = json::parse(r.out);
    EXPECT_EQ(out["mesh"]["veins"]["vertices"], row.vv);
    EXPECT_EQ(out["mesh"]["veins"]["quads"], row.vq);
    EXPECT_EQ(out["mesh"]["blade"]["vertices"], row.bv);
    EXPECT_EQ(out["mesh"]["blade"]["quads"], row.bq);
    EXPECT_GT(out["metrics"]["blade_area_mm2"].get<double>(), 0.0);
    EXPECT_LE(out["metrics"]["projected_area_mm2"].get<double>(), out["metrics"]["blade_area_mm2"].get<double>());
    EXPECT_TRUE(out["metrics"]["area_resolution"]["converged"].get<bool>());
    EXPECT_TRUE(out["metrics"]["area_constraint"].is_object());
    // The samples' last rows are at the leaf base; the small upper leaf's wide wings make
    // its lowest veins meet the margin far up, which the warning names as its second cause.
    if (row.broadBase) {
      ASSERT_EQ(out["metrics"]["warnings"].size(), 1u) << row.file;
      EXPECT_EQ(out["metrics"]["warnings"][0]["name"], "last-row-not-at-base");
      EXPECT_NE(out["metrics"]["warnings"][0]["message"].get<std::string>().find("winged"), std::string::npos);
    } else {
      EXPECT_TRUE(out["metrics"]["warnings"].empty()) << row.file << ": " << out["metrics"]["warnings"].dump();
    }
  }
}

TEST_F(Cli, measuredAreaOptionDrivesTheAreaConstraint) {
  const Result base = leafdig("model build " + quote(sample("lower-leaf-n10.markers.json")) + " --json");
  ASSERT_EQ(base.exitCode, 0) << base.err;
  const double area = json::parse(base.out)["metrics"]["blade_area_mm2"].get<double>();
  const Result close = leafdig("model build " + quote(sample("lower-leaf-n10.markers.json")) +
                               " --json --measured-area " + std::to_string(area * 1.02));
  const json c = json::parse(close.out)["metrics"]["area_constraint"];
  EXPECT_FALSE(c["exceeded"].get<bool>());
  EXPECT_NEAR(c["difference_percent"].get<double>(), -100.0 * 0.02 / 1.02, 1e-3);
  const Result far = leafdig("model build " + quote(sample("lower-leaf-n10.markers.json")) +
                             " --json --measured-area " + std::to_string(area * 1.2));
  EXPECT_TRUE(json::parse(far.out)["metrics"]["area_constraint"]["exceeded"].get<bool>());
}

TEST_F(Cli, glbPassesTheKhronosValidatorForEveryBladeKindAndFrame) {
  const std::string validator = std::string(LEAFDIG_SOURCE_DIR) + "/tests/tools/validate-gltf.mjs";
  ASSERT_TRUE(fs::exists(std::string(LEAFDIG_SOURCE_DIR) + "/tests/tools/node_modules/gltf-validator"))
      << "the glTF validator is not installed: run scripts/setup.sh";
  for (const char* blade : {"interp", "approx", "bezier", "nurbs"}) {
    for (const char* frame : {"digitizer", "leaf"}) {
      const fs::path glb = dir_ / (std::string(blade) + "-" + frame + ".glb");
      const Result build = leafdig("model build " + quote(sample("upper-curved-leaf-n14.markers.json")) + " -o " +
                                   quote(glb) + " --blade " + blade + " --frame " + frame);
      ASSERT_EQ(build.exitCode, 0) << build.err;
      const Result check = run("node " + quote(validator) + " " + quote(glb));
      EXPECT_EQ(check.exitCode, 0) << check.out << check.err;
      const json report = json::parse(check.out);
      EXPECT_EQ(report["numErrors"], 0) << check.out;
    }
  }
}

// Parses `assimp info -r` (raw import, no post-processing) into its counts.
std::map<std::string, long> assimpCounts(const std::string& text) {
  // (std::regex is avoided: GCC 12 warns inside it under -O2 with sanitizers.)
  std::map<std::string, long> counts;
  for (const std::string key : {"Meshes", "Vertices", "Faces"}) {
    const std::size_t at = text.find("\n" + key + ":");
    if (at == std::string::npos) continue;
    counts[key] = std::stol(text.substr(at + key.size() + 2));
  }
  return counts;
}

TEST_F(Cli, objPlyAndStlLoadInAssimpWithTheExpectedCounts) {
  ASSERT_EQ(run("command -v assimp").exitCode, 0) << "assimp is not installed: run scripts/setup.sh";
  const fs::path obj = dir_ / "leaf.obj";
  const fs::path ply = dir_ / "leaf.ply";
  const fs::path stl = dir_ / "leaf.stl";
  const Result build =
      leafdig("model build " + quote(sample("lower-leaf-n10.markers.json")) + " --resolution paper --json -o " +
              quote(obj) + " -o " + quote(ply) + " -o " + quote(stl));
  ASSERT_EQ(build.exitCode, 0) << build.err;
  const json counts = json::parse(build.out)["mesh"];
  const long triangles = counts["veins"]["triangles"].get<long>() + counts["blade"]["triangles"].get<long>();
  const long vertices = counts["veins"]["vertices"].get<long>() + counts["blade"]["vertices"].get<long>();
  const long organs = 2 * 10 + 2 + 1;

  const auto objInfo = assimpCounts(run("assimp info " + quote(obj) + " -r").out);
  EXPECT_EQ(objInfo.at("Meshes"), organs);
  EXPECT_EQ(objInfo.at("Faces"), triangles);
  EXPECT_EQ(objInfo.at("Vertices"), 3 * triangles);  // assimp's OBJ reader unshares vertices

  const auto plyInfo = assimpCounts(run("assimp info " + quote(ply) + " -r").out);
  EXPECT_EQ(plyInfo.at("Vertices"), vertices);
  EXPECT_EQ(plyInfo.at("Faces"), triangles);

  const auto stlInfo = assimpCounts(run("assimp info " + quote(stl) + " -r").out);
  EXPECT_EQ(stlInfo.at("Faces"), triangles);

  EXPECT_NE(slurp(obj).find("# units: mm"), std::string::npos);
  EXPECT_NE(slurp(ply).find("comment organ_id 0 midrib"), std::string::npos);
}

TEST_F(Cli, modelJsonMatchesTheSpecShape) {
  const fs::path model = dir_ / "leaf.model.json";
  const Result r = leafdig("model build " + quote(sample("upper-small-leaf-n17.markers.json")) + " --model-json " +
                           quote(model) + " --frame leaf");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const json doc = json::parse(slurp(model));
  EXPECT_EQ(doc["format"], "leafdig.model/1");
  EXPECT_EQ(doc["frame"], "leaf");
  EXPECT_EQ(doc["veins"].size(), 2u * 17 + 2);
  EXPECT_EQ(doc["veins"][1]["name"], "lateral-1-right");
  EXPECT_EQ(doc["veins"][0]["knots"].size(), doc["veins"][0]["control_balls"].size() + 4);
  EXPECT_EQ(doc["blade"]["kind"], "interp");
  EXPECT_EQ(doc["blade"]["control_net"].size(), 17u + 3);
  EXPECT_EQ(doc["blade"]["control_net"][0].size(), 9u);
  // In the leaf frame the last midrib marker is the origin.
  const auto last = doc["veins"][0]["data_balls"].back();
  EXPECT_NEAR(last[0].get<double>(), 0.0, 1e-9);
  EXPECT_NEAR(last[1].get<double>(), 0.0, 1e-9);
  EXPECT_NEAR(last[2].get<double>(), 0.0, 1e-9);
}

TEST_F(Cli, writeFailureExitsOneAndLeavesNoTemporaryFile) {
  const fs::path out = dir_ / "no-such-folder" / "leaf.glb";
  const Result r = leafdig("model build " + quote(sample("lower-leaf-n10.markers.json")) + " -o " + quote(out));
  EXPECT_EQ(r.exitCode, 1);
  EXPECT_NE(r.err.find("no-such-folder"), std::string::npos) << r.err;
  // A destination that is a folder is refused by name (exit 2: it is never replaced). The OBJ
  // before it in the same command is written; nothing else is left behind.
  const fs::path into = dir_ / "into";
  fs::create_directories(into / "leaf.glb");
  const Result again = leafdig("model build " + quote(sample("lower-leaf-n10.markers.json")) + " -o " +
                               quote(into / "leaf.obj") + " -o " + quote(into / "leaf.glb"));
  EXPECT_EQ(again.exitCode, 2);
  EXPECT_NE(again.err.find("leaf.glb is not a regular file (a folder)"), std::string::npos) << again.err;
  std::set<std::string> left;
  for (const auto& e : fs::directory_iterator(into)) left.insert(e.path().filename().string());
  EXPECT_EQ(left, (std::set<std::string>{"leaf.glb", "leaf.obj"})) << "a temporary file was left behind";
  EXPECT_TRUE(fs::is_directory(into / "leaf.glb"));
}

TEST_F(Cli, rejectsNaNCoordinateNamingRowAndPoint) {
  json doc = sampleJson();
  std::string text = doc.dump();
  doc["rows"][2]["points"][4][1] = 123456.789;
  text = doc.dump();
  text.replace(text.find("123456.789"), 10, "NaN");
  expectBadInput(text, "row 3, point 5", "NaN");
}

TEST_F(Cli, rejectsInfiniteCoordinateNamingRowAndPoint) {
  json doc = sampleJson();
  doc["rows"][1]["points"][0][2] = 123456.789;
  std::string text = doc.dump();
  text.replace(text.find("123456.789"), 10, "1e999");
  expectBadInput(text, "row 2, point 1", "not a finite number");
}

TEST_F(Cli, rejectsARowWithoutSevenPoints) {
  json doc = sampleJson();
  doc["rows"][3]["points"].erase(6);
  expectBadInput(doc.dump(), "row 4", "has 6 points");
}

TEST_F(Cli, rejectsCoincidentConsecutiveMarkers) {
  json doc = sampleJson();
  doc["rows"][1]["points"][3] = doc["rows"][1]["points"][2];
  expectBadInput(doc.dump(), "row 2, point 3 and row 2, point 4", "coincide");
}

TEST_F(Cli, rejectsZeroThickness) {
  json doc = sampleJson();
  doc["rows"][4]["midrib_thickness"] = 0;
  expectBadInput(doc.dump(), "row 5", "positive number of millimetres");
}

TEST_F(Cli, rejectsNegativeThickness) {
  json doc = sampleJson();
  doc["rows"][0]["vein_origin_thickness"] = -0.4;
  expectBadInput(doc.dump(), "row 1", "vein_origin_thickness");
}

TEST_F(Cli, rejectsMissingThicknessForTheMode) {
  json doc = sampleJson();
  doc["rows"][6].erase("vein_origin_thickness");
  expectBadInput(doc.dump(), "row 7", "vein_origin_thickness (r_i4^2) is missing");
  doc = sampleJson();
  doc["mode"] = "full";
  expectBadInput(doc.dump(), "row 1, point 1", "full mode needs all 7");
  doc = sampleJson();
  doc.erase("edge_thickness");
  expectBadInput(doc.dump(), "leaf", "edge_thickness (d, the margin thickness) is missing");
}

TEST_F(Cli, rejectsUnknownUnits) {
  json doc = sampleJson();
  doc["units"] = "furlong";
  expectBadInput(doc.dump(), "units", "unknown unit \"furlong\"");
}

TEST_F(Cli, rejectsATruncatedFile) {
  const std::string text = slurp(sample("lower-leaf-n10.markers.json"));
  expectBadInput(text.substr(0, text.size() / 2), "not valid JSON", "truncated");
}

TEST_F(Cli, rejectsAFileThatIsNotJson) {
  expectBadInput("row,point,x,y,z\n1,1,0,0,0\n", "not valid JSON", "line 1");
}

TEST_F(Cli, rejectsAFileWithNoRows) {
  json doc = sampleJson();
  doc["rows"] = json::array();
  expectBadInput(doc.dump(), "rows", "no rows");
}

TEST_F(Cli, rejectsAMissingRequiredKey) {
  json doc = sampleJson();
  doc.erase("tip");
  expectBadInput(doc.dump(), "\"tip\"", "missing");
}

TEST_F(Cli, rejectsAMissingFile) {
  const Result r = leafdig("model build " + quote((dir_ / "nope.json").string()));
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_NE(r.err.find("nope.json"), std::string::npos) << r.err;
}

}  // namespace
