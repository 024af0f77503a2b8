// `leafdig synth leaf|figure`: the files a user gets, read by independent readers
// (Python's json through the markers reader of `model build`, the Khronos validator,
// assimp), the errors and what is (not) written.
#include "cli_support.hpp"

namespace {

class SynthCli : public Cli {};

TEST_F(SynthCli, LeafWritesMarkersTruthAndTheTrueSurface) {
  const fs::path markers = dir_ / "leaf.markers.json", truth = dir_ / "leaf.truth.json", glb = dir_ / "truth.glb",
                 svg = dir_ / "leaf.svg";
  const Result r = leafdig(
      "synth leaf --shape ovate --serration sharp --teeth 15 --rows 10 --noise 0.4 --seed 3 "
      "--markers " +
      quote(markers) + " --truth " + quote(truth) + " -o " + quote(glb) + " --svg " + quote(svg) + " --json");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const json summary = json::parse(r.out);
  const json t = json::parse(slurp(truth));
  EXPECT_EQ(t["format"], "leafdig.truth/1");
  EXPECT_EQ(t["spec"]["serration"], "sharp");
  EXPECT_DOUBLE_EQ(t["area_mm2"].get<double>(), summary["area_mm2"].get<double>());
  EXPECT_LT(t["area_relative_error"].get<double>(), 1e-6);
  // The markers file: 10 rows of 7, the area a leaf area meter would read, and the last
  // row at the leaf base (the leaf frame's origin, within the noise).
  const json m = json::parse(slurp(markers));
  EXPECT_EQ(m["format"], "leafdig.markers/1");
  ASSERT_EQ(m["rows"].size(), 10u);
  EXPECT_NEAR(m["leaf"]["measured_area_mm2"].get<double>(), t["area_mm2"].get<double>(), 0.5);
  const json base = m["rows"][9]["points"][3];
  EXPECT_LT(std::hypot(base[0].get<double>(), base[1].get<double>(), base[2].get<double>()), 3.0);
  // Noise: markers differ from the exact ones by about σ.
  double sq = 0.0;
  int n = 0;
  for (std::size_t i = 0; i < 10; ++i)
    for (std::size_t j = 0; j < 7; ++j)
      for (std::size_t k = 0; k < 3; ++k) {
        const double d = m["rows"][i]["points"][j][k].get<double>() - t["markers_exact"]["rows"][i][j][k].get<double>();
        sq += d * d;
        ++n;
      }
  EXPECT_NEAR(std::sqrt(sq / n), 0.4, 0.1);
  // The markers build into a model whose blade area is near the truth.
  const Result model = leafdig("model build " + quote(markers) + " --json");
  ASSERT_EQ(model.exitCode, 0) << model.err;
  const double area = json::parse(model.out)["metrics"]["blade_area_mm2"].get<double>();
  EXPECT_NEAR(area / t["area_mm2"].get<double>(), 1.0, 0.03);
  // The true surface opens in the Khronos validator without errors and in assimp.
  const std::string validator = std::string(LEAFDIG_SOURCE_DIR) + "/tests/tools/validate-gltf.mjs";
  const Result check = run("node " + quote(validator) + " " + quote(glb));
  ASSERT_EQ(check.exitCode, 0) << check.out << check.err;
  EXPECT_EQ(json::parse(check.out)["numErrors"], 0) << check.out;
  EXPECT_EQ(run("assimp info " + quote(glb)).exitCode, 0);
  EXPECT_NE(slurp(svg).find("<polygon"), std::string::npos);
}

TEST_F(SynthCli, LeafIsReproducibleAndTheSeedMatters) {
  const auto make = [&](const std::string& name, int seed) {
    const fs::path markers = dir_ / (name + ".markers.json");
    const Result r = leafdig("synth leaf --noise 0.5 --seed " + std::to_string(seed) + " --markers " + quote(markers) +
                             " --truth " + quote(dir_ / (name + ".truth.json")));
    EXPECT_EQ(r.exitCode, 0) << r.err;
    return slurp(markers);
  };
  const std::string a = make("a", 7), b = make("b", 7), c = make("c", 8);
  EXPECT_EQ(a, b);
  EXPECT_NE(a, c);
}

TEST_F(SynthCli, LeafRefusesBadOptionsAndWritesNothing) {
  const fs::path markers = dir_ / "m.json", truth = dir_ / "t.json";
  const auto refused = [&](const std::string& options, const std::string& words) {
    const Result r = leafdig("synth leaf " + options + " --markers " + quote(markers) + " --truth " + quote(truth));
    EXPECT_EQ(r.exitCode, 2) << options;
    EXPECT_NE(r.err.find(words), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(markers));
    EXPECT_FALSE(fs::exists(truth));
  };
  refused("--serration round --tooth-depth 90", "tooth depth");
  refused("--tooth-depth 2", "--serration");
  refused("--rows 1", "rows");
  refused("--noise -1", "noise");
  refused("--width-term 0.1", "--width-term");
  refused("--shape heart", "shape");
  refused("--symmetry 0.7 --shape ovate", "symmetry");
}

TEST_F(SynthCli, FigureDrawsEveryShapeAndSerration) {
  const fs::path svg = dir_ / "shapes.svg";
  const Result r = leafdig("synth figure -o " + quote(svg));
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const std::string text = slurp(svg);
  for (const char* word : {"oblong", "elliptic", "ovate", "obovate", "tobacco", "round teeth", "sharp teeth",
                           "straight teeth", "acuminate teeth"})
    EXPECT_NE(text.find(std::string(">") + word), std::string::npos) << word;
  std::size_t polygons = 0;
  for (std::size_t at = text.find("<polygon"); at != std::string::npos; at = text.find("<polygon", at + 1)) ++polygons;
  EXPECT_EQ(polygons, 10u);
}

}  // namespace

namespace {

TEST_F(SynthCli, StudyWritesTheReportItsCsvAndFigures) {
  const fs::path report = dir_ / "accuracy.md";
  const Result r = leafdig("synth study --quick --threads 2 -o " + quote(report) + " --json");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const json summary = json::parse(r.out);
  EXPECT_GT(summary["reconstructions"].get<int>(), 0);
  EXPECT_GE(summary["interval_holds_truth"].get<double>(), 0.9 * summary["interval_checked"].get<double>());
  EXPECT_NE(slurp(report).find("# Accuracy of captured leaves"), std::string::npos);
  // The CSV opens in Python's csv reader with one row per reconstruction.
  const Result rows = run("python3 -c \"import csv,sys; print(len(list(csv.DictReader(open(sys.argv[1])))))\" " +
                          quote(dir_ / "accuracy.csv"));
  ASSERT_EQ(rows.exitCode, 0) << rows.err;
  EXPECT_EQ(std::stoi(rows.out), summary["reconstructions"].get<int>());
  for (const auto& f : summary["figures"]) EXPECT_NE(slurp(f.get<std::string>()).find("<svg"), std::string::npos);
}

TEST_F(SynthCli, StudyRefusesAReportItCannotWrite) {
  Result r = leafdig("synth study --quick -o " + quote(dir_ / "accuracy.txt"));
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_NE(r.err.find(".md"), std::string::npos) << r.err;
  r = leafdig("synth study --quick -o " + quote(dir_ / "missing" / "accuracy.md"));
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_NE(r.err.find("does not exist"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir_ / "missing"));
}

TEST_F(SynthCli, ModelBuildReportsTheAreaInterval) {
  const fs::path markers = dir_ / "leaf.markers.json";
  ASSERT_EQ(leafdig("synth leaf --rows 12 --noise 0.7 --seed 4 --markers " + quote(markers) + " --truth " +
                    quote(dir_ / "t.json"))
                .exitCode,
            0);
  const Result model = leafdig("model build " + quote(markers) + " --json");
  ASSERT_EQ(model.exitCode, 0) << model.err;
  const json metrics = json::parse(model.out)["metrics"];
  const double area = metrics["blade_area_mm2"].get<double>();
  const json interval = metrics["blade_area_95_mm2"];
  ASSERT_EQ(interval.size(), 2u);
  EXPECT_LT(interval[0].get<double>(), area);
  EXPECT_GT(interval[1].get<double>(), area);
  const double truth = json::parse(slurp(dir_ / "t.json"))["area_mm2"].get<double>();
  EXPECT_GE(truth, interval[0].get<double>());
  EXPECT_LE(truth, interval[1].get<double>());
  EXPECT_DOUBLE_EQ(metrics["area_interval"]["digitizer_sigma_mm"].get<double>(), 0.762);
}

}  // namespace
