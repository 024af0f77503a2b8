// `leafdig leaf2d scan|build`, `synth scan` and `model build --measured-area-scan`: scans of
// known area, outlines read by Ajv against the shipped schema, meshes opened by the Khronos
// validator and assimp, and the refusals.
#include "cli_support.hpp"

namespace {

class Leaf2dCli : public Cli {
 protected:
  // A synthetic scan and its truth (exact flat blade area).
  json makeScan(const fs::path& png, const std::string& options) {
    const fs::path truth = png.string() + ".truth.json";
    const Result r = leafdig("synth scan " + options + " -o " + quote(png) + " --truth " + quote(truth));
    EXPECT_EQ(r.exitCode, 0) << r.err;
    return json::parse(slurp(truth));
  }
  std::string tools() const { return std::string(LEAFDIG_SOURCE_DIR) + "/tests/tools/"; }
};

TEST_F(Leaf2dCli, AScanOfKnownAreaGivesItsAreaAndAnOutlineTheSchemaAccepts) {
  const fs::path png = dir_ / "elliptic.png", outline = dir_ / "elliptic.outline.json";
  const json truth = makeScan(png, "--shape elliptic --length 180 --serration round --teeth 16");
  const Result r = leafdig("leaf2d scan " + quote(png) + " --dpi 300 -o " + quote(outline) + " --json");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const json s = json::parse(r.out);
  const double exact = truth["area_mm2"].get<double>();
  EXPECT_NEAR(s["area_mm2"].get<double>(), exact, 0.002 * exact);
  EXPECT_EQ(s["holes"], 0);
  EXPECT_FALSE(s["petiole"].get<bool>());
  EXPECT_FALSE(s["touches_border"].get<bool>());
  // The outline file: valid against the shipped schema (Ajv), in mm, with the measured area.
  const Result valid =
      run("node " + quote(tools() + "validate-schema.mjs") + " " +
          quote(std::string(LEAFDIG_SOURCE_DIR) + "/data/schema/leafdig.outline-1.schema.json") + " " + quote(outline));
  EXPECT_EQ(valid.exitCode, 0) << valid.out << valid.err;
  const json o = json::parse(slurp(outline));
  EXPECT_EQ(o["units"], "mm");
  EXPECT_NEAR(o["measured_area_mm2"].get<double>(), exact, 0.002 * exact);
  // The same leaf as a TIFF, as many flatbed scanners write.
  const fs::path tif = dir_ / "elliptic.tif";
  makeScan(tif, "--shape elliptic --length 180 --serration round --teeth 16");
  const Result t = leafdig("leaf2d scan " + quote(tif) + " --dpi 300 --json");
  ASSERT_EQ(t.exitCode, 0) << t.err;
  EXPECT_NEAR(json::parse(t.out)["area_mm2"].get<double>(), s["area_mm2"].get<double>(), 1e-6);
}

TEST_F(Leaf2dCli, BuildsACurledLeafFromAScanWithAPetioleAndItsExportsOpenElsewhere) {
  const fs::path png = dir_ / "ovate.png", glb = dir_ / "ovate.glb", obj = dir_ / "ovate.obj", ply = dir_ / "ovate.ply";
  const json truth = makeScan(png, "--shape ovate --length 150 --petiole-length 35");
  const Result r = leafdig("leaf2d build " + quote(png) + " --dpi 300 --curl auto --light 0.2,0.1,1 -o " + quote(glb) +
                           " -o " + quote(obj) + " -o " + quote(ply) + " --json");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const json b = json::parse(r.out);
  const double exact = truth["area_mm2"].get<double>();
  ASSERT_TRUE(b["scan"]["petiole"].get<bool>()) << r.out;
  // The petiole is set apart: the blade's area is the truth's; the base where it joins.
  EXPECT_NEAR(b["measured_area_mm2"].get<double>(), exact, 0.003 * exact);
  EXPECT_NEAR(b["base_mm"][0].get<double>(), truth["base_mm"][0].get<double>(), 1.0);
  EXPECT_NEAR(b["base_mm"][1].get<double>(), truth["base_mm"][1].get<double>(), 1.0);
  EXPECT_NEAR(b["length_mm"].get<double>(), truth["length_mm"].get<double>(), 1.5);
  // The area constraint holds; auto chose the candidate catching the most light.
  EXPECT_LT(std::abs(b["area_difference_percent"].get<double>()), 0.1);
  ASSERT_EQ(b["candidates"].size(), 2u);
  double most = 0.0;
  std::string best;
  for (const json& c : b["candidates"]) {
    if (c["projected_area_mm2"].get<double>() > most) {
      most = c["projected_area_mm2"].get<double>();
      best = c["curl"].get<std::string>();
    }
  }
  EXPECT_EQ(b["curl"], best);
  EXPECT_LE(b["projected_area_mm2"].get<double>(), b["model_area_mm2"].get<double>());
  EXPECT_GT(b["silhouette_area_mm2"].get<double>(), 0.8 * exact);
  const Result check = run("node " + quote(tools() + "validate-gltf.mjs") + " " + quote(glb));
  ASSERT_EQ(check.exitCode, 0) << check.out << check.err;
  EXPECT_EQ(json::parse(check.out)["numErrors"], 0) << check.out;
  EXPECT_EQ(run("assimp info " + quote(obj)).exitCode, 0);
  EXPECT_EQ(run("assimp info " + quote(ply)).exitCode, 0);
}

TEST_F(Leaf2dCli, BuildsFromJsonAndCsvOutlinesInMillimetres) {
  // An ellipse 100 x 40 mm as CSV with a header, and as JSON with base and tip given.
  std::string csv = "x_mm,y_mm\n";
  json points = json::array();
  for (int i = 0; i < 360; ++i) {
    const double t = 2 * M_PI * i / 360;
    csv += std::to_string(50 * std::cos(t)) + "," + std::to_string(20 * std::sin(t)) + "\n";
    points.push_back({50 * std::cos(t), 20 * std::sin(t)});
  }
  std::ofstream(dir_ / "e.csv") << csv;
  std::ofstream(dir_ / "e.json") << json{
      {"format", "leafdig.outline/1"}, {"units", "mm"}, {"points", points}, {"base", {-50, 0}}, {"tip", {50, 0}},
      {"measured_area_mm2", 2500}}.dump();
  const Result c = leafdig("leaf2d build " + quote(dir_ / "e.csv") + " --curl sine --amplitude 4 --json");
  ASSERT_EQ(c.exitCode, 0) << c.err;
  const json cj = json::parse(c.out);
  EXPECT_NEAR(cj["outline_area_mm2"].get<double>(), M_PI * 50 * 20, 0.002 * M_PI * 1000);
  EXPECT_NEAR(cj["length_mm"].get<double>(), 100.0, 1e-3);
  EXPECT_EQ(cj["curl"], "sine");
  EXPECT_DOUBLE_EQ(cj["amplitude_mm"].get<double>(), 4.0);
  const Result j = leafdig("leaf2d build " + quote(dir_ / "e.json") + " --json");
  ASSERT_EQ(j.exitCode, 0) << j.err;
  const json jj = json::parse(j.out);
  EXPECT_NEAR(jj["model_area_mm2"].get<double>(), 2500.0, 0.0025);  // the file's measured area, held
  EXPECT_EQ(jj["curl"], "parabola");
  // The text report names what a user needs.
  const Result t = leafdig("leaf2d build " + quote(dir_ / "e.json"));
  ASSERT_EQ(t.exitCode, 0) << t.err;
  EXPECT_NE(t.out.find("area constraint"), std::string::npos) << t.out;
  EXPECT_NE(t.out.find("silhouette"), std::string::npos) << t.out;
}

TEST_F(Leaf2dCli, ACordateOutlineIsMeshedInsideItsSinus) {
  // The shipped heart-shaped sample, the base at the sinus's apex: the flat leaf is the
  // outline's region (reported as trimmed, no warning, no drawing in), and its meshes open
  // elsewhere.
  const std::string heart = std::string(LEAFDIG_SOURCE_DIR) + "/data/samples/cordate.outline.json";
  const Result valid =
      run("node " + quote(tools() + "validate-schema.mjs") + " " +
          quote(std::string(LEAFDIG_SOURCE_DIR) + "/data/schema/leafdig.outline-1.schema.json") + " " + quote(heart));
  EXPECT_EQ(valid.exitCode, 0) << valid.out << valid.err;
  const fs::path obj = dir_ / "heart.obj", glb = dir_ / "heart.glb";
  const Result r =
      leafdig("leaf2d build " + quote(heart) + " --curl none -o " + quote(obj) + " -o " + quote(glb) + " --json");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const json b = json::parse(r.out);
  EXPECT_EQ(b["flat_leaf"], "trimmed-to-outline");
  EXPECT_TRUE(b["warnings"].empty()) << r.out;
  const double outline = b["outline_area_mm2"].get<double>();
  EXPECT_NEAR(b["flat_model_area_mm2"].get<double>(), outline, 0.003 * outline);
  EXPECT_NEAR(b["in_plane_scale"].get<double>(), 1.0, 0.002);
  EXPECT_NEAR(b["length_mm"].get<double>(), 66.0, 1e-6);  // sinus apex to the heart's point
  EXPECT_EQ(run("assimp info " + quote(obj)).exitCode, 0);
  const Result v = run("node " + quote(tools() + "validate-gltf.mjs") + " " + quote(glb));
  ASSERT_EQ(v.exitCode, 0) << v.out << v.err;
  EXPECT_EQ(json::parse(v.out)["numErrors"], 0) << v.out;
  const Result t = leafdig("leaf2d build " + quote(heart));
  ASSERT_EQ(t.exitCode, 0) << t.err;
  EXPECT_NE(t.out.find("trimmed to the outline"), std::string::npos) << t.out;
  EXPECT_EQ(t.out.find("warning"), std::string::npos) << t.out;
}

TEST_F(Leaf2dCli, RefusesWhatItCannotReadAndWritesNothing) {
  const fs::path png = dir_ / "s.png", out = dir_ / "out.glb";
  makeScan(png, "--shape oblong --length 120");
  const auto refused = [&](const std::string& args, const std::string& words) {
    const Result r = leafdig(args);
    EXPECT_EQ(r.exitCode, 2) << args << "\n" << r.out;
    EXPECT_NE(r.err.find(words), std::string::npos) << args << "\n" << r.err;
    EXPECT_FALSE(fs::exists(out)) << args;
  };
  refused("leaf2d build " + quote(png) + " -o " + quote(out), "give --dpi");
  std::ofstream(dir_ / "px.json") << R"({"format": "leafdig.outline/1", "units": "px", "points": [[0,0],[1,0],[1,1]]})";
  refused("leaf2d build " + quote(dir_ / "px.json") + " -o " + quote(out), "millimetres");
  std::ofstream(dir_ / "garbage.png") << "not an image at all";
  refused("leaf2d build " + quote(dir_ / "garbage.png") + " --dpi 300 -o " + quote(out), "cannot decode");
  refused("leaf2d build " + quote(png) + " --dpi 300 -o " + quote(dir_ / "out.xyz"), ".xyz");
  refused("leaf2d build " + quote(png) + " --dpi 300 --curl helix -o " + quote(out), "helix");
  refused("leaf2d build " + quote(png) + " --dpi 300 --amplitude -3 -o " + quote(out), "amplitude");
  refused("model build " + quote(sample("lower-leaf-n10.markers.json")) + " --measured-area-scan " + quote(png) +
              " -o " + quote(out),
          "--dpi");
}

TEST_F(Leaf2dCli, ACapturedLeafsAreaConstraintTakesAScan) {
  const fs::path png = dir_ / "meter.png";
  const json truth = makeScan(png, "--shape tobacco --length 200");
  const Result r = leafdig("model build " + quote(sample("lower-leaf-n10.markers.json")) + " --measured-area-scan " +
                           quote(png) + " --dpi 300 --json");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const json b = json::parse(r.out);
  const double exact = truth["area_mm2"].get<double>();
  EXPECT_NEAR(b["measured_area_scan"]["filled_area_mm2"].get<double>(), exact, 0.002 * exact);
  EXPECT_NEAR(b["metrics"]["area_constraint"]["measured_mm2"].get<double>(),
              b["measured_area_scan"]["filled_area_mm2"].get<double>(), 1e-6);
}

// A scan is reported in one shape wherever it appears: `leaf2d scan --json` (with the
// command's own `input`, `outline` and `milliseconds`), `leaf2d build`'s `scan` and
// `model build`'s `measured_area_scan` hold the same keys and the same values.
TEST_F(Leaf2dCli, AScanHasOneJsonShapeInEveryCommandThatReportsIt) {
  const fs::path png = dir_ / "one.png";
  makeScan(png, "--shape ovate --length 150 --petiole-length 20");
  const Result a = leafdig("leaf2d scan " + quote(png) + " --dpi 300 --json");
  const Result b = leafdig("leaf2d build " + quote(png) + " --dpi 300 --json");
  const Result c = leafdig("model build " + quote(sample("lower-leaf-n10.markers.json")) + " --measured-area-scan " +
                           quote(png) + " --dpi 300 --json");
  ASSERT_EQ(a.exitCode, 0) << a.err;
  ASSERT_EQ(b.exitCode, 0) << b.err;
  ASSERT_EQ(c.exitCode, 0) << c.err;
  json scan = json::parse(a.out);
  EXPECT_EQ(scan["input"], png.string());
  EXPECT_TRUE(scan["milliseconds"]["scan"].is_number()) << a.out;
  for (const char* own : {"input", "outline", "milliseconds"}) scan.erase(own);
  const json inBuild = json::parse(b.out)["scan"];
  const json inModel = json::parse(c.out)["measured_area_scan"];
  EXPECT_EQ(scan, inBuild) << scan.dump(1) << "\n" << inBuild.dump(1);
  EXPECT_EQ(scan, inModel) << scan.dump(1) << "\n" << inModel.dump(1);
  EXPECT_EQ(scan["file"], png.string());
  EXPECT_EQ(scan["dpi"], 300.0);
  EXPECT_TRUE(scan["petiole"].get<bool>());
  for (const char* key :
       {"area_mm2", "filled_area_mm2", "holes", "holes_area_mm2", "petiole_area_mm2", "other_objects", "touches_border",
        "dark_background", "width_px", "height_px", "threshold", "pixel_mm", "outline_points", "base_mm"})
    EXPECT_TRUE(scan.contains(key)) << key;
}

}  // namespace
