// `leafdig field check|list|show` driven as a technician would (issue 50): the simulated FASTRAK in
// a field bent by the steel-bench preset, a virtual technician touching the shipped jig's divots
// as prompted; the verdict, the correction chosen by its error on divots it did not see, the error
// map, the check stored and read back. A clean field passes, a field bent past correcting fails
// with its own exit code, and what is wrong with the request is said before anything runs.
#include <Eigen/Geometry>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "cli_support.hpp"

namespace {

class FieldCli : public Cli {
 protected:
  std::string bench() const { return quote(fs::path(LEAFDIG_SOURCE_DIR) / "data/fields/steel-bench.field.json"); }
  std::string db() const { return " --db " + quote(dir_ / "station.sqlite"); }
  static json lastLine(const std::string& out) {
    const auto end = out.find_last_not_of('\n');
    const auto start = out.rfind('\n', end);
    return json::parse(out.substr(start == std::string::npos ? 0 : start + 1, end - start));
  }
};

TEST_F(FieldCli, ABenchOfSteelIsFoundMappedAndCorrectedOnDivotsTheFitNeverSaw) {
  const Result r = leafdig("field check --simulate --speed 10 --json --operator ana --distortion " + bench() + db() +
                           " --map " + quote(dir_ / "map.svg") + " </dev/null");
  ASSERT_EQ(r.exitCode, 0) << r.err << r.out;
  // Every divot prompted in the jig's order, then the result.
  EXPECT_NE(r.out.find(R"("text":"touch divot A1 (1 of 22))"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find(R"("text":"touch divot C4 (22 of 22))"), std::string::npos);
  const json result = lastLine(r.out);
  EXPECT_EQ(result["calibration_id"], 1);
  EXPECT_EQ(result["tolerance_mm"], 1.5);
  EXPECT_EQ(result["operator"], "ana");
  // The plate 250 mm below bends the lowest level most: millimetres, the worst on it.
  EXPECT_GT(result["rms_mm"].get<double>(), 1.5);
  EXPECT_LT(result["rms_mm"].get<double>(), 6.0);
  EXPECT_EQ(result["worst_point"].get<std::string>().substr(0, 1), "A");
  // A smooth bend: a polynomial does far better on divots it did not see than the rigid fit.
  EXPECT_EQ(result["correction"]["model"].get<std::string>().substr(0, 11), "polynomial-");
  EXPECT_LT(result["correction"]["holdout_rms_mm"].get<double>(), 1.5);
  EXPECT_GT(result["correction"]["holdout_max_mm"].get<double>(), result["correction"]["holdout_rms_mm"].get<double>());
  EXPECT_EQ(result["verdict"], "correctable");
  // The error map: an arrow per divot from above and from the side, red beyond tolerance.
  const std::string svg = slurp(dir_ / "map.svg");
  std::size_t arrows = 0;
  for (auto at = svg.find("marker-end"); at != std::string::npos; at = svg.find("marker-end", at + 1)) ++arrows;
  EXPECT_EQ(arrows, 44U);
  EXPECT_NE(svg.find("#d73027"), std::string::npos);
  // Stored, listed and shown again as it was (recomputed from its presses on the way).
  const Result list = leafdig("field list --json" + db());
  ASSERT_EQ(list.exitCode, 0) << list.err;
  ASSERT_EQ(json::parse(list.out).size(), 1U);
  EXPECT_EQ(json::parse(list.out)[0], result);
  const Result show = leafdig("field show 1 --json" + db());
  ASSERT_EQ(show.exitCode, 0) << show.err;
  EXPECT_EQ(json::parse(show.out), result);
  const Result text = leafdig("field show 1" + db());
  EXPECT_NE(text.out.find("verdict: correctable"), std::string::npos) << text.out;
  EXPECT_NE(text.out.find("on divots it did not see RMS"), std::string::npos) << text.out;
  EXPECT_EQ(leafdig("field show 2" + db()).exitCode, 2);
}

TEST_F(FieldCli, ACleanFieldPassesAndOneBentPastCorrectingFails) {
  const Result clean = leafdig("field check --simulate --speed 10 --json" + db() + " </dev/null");
  ASSERT_EQ(clean.exitCode, 0) << clean.err;
  const json pass = lastLine(clean.out);
  EXPECT_EQ(pass["verdict"], "pass");
  EXPECT_LT(pass["rms_mm"].get<double>(), 0.5);
  EXPECT_EQ(pass["correction"]["model"], "none");
  // A plate 100 mm below, taking back 30 % of the coupling: centimetres, and no correction saves it.
  ASSERT_EQ(
      leafdig("field model steel-bench --below-mm 100 --strength 0.3 -o " + quote(dir_ / "bad.field.json")).exitCode,
      0);
  const Result bad = leafdig("field check --simulate --speed 10 --json --distortion " + quote(dir_ / "bad.field.json") +
                             db() + " </dev/null");
  EXPECT_EQ(bad.exitCode, 3) << bad.err;
  const json fail = lastLine(bad.out);
  EXPECT_EQ(fail["verdict"], "fail");
  EXPECT_GT(fail["rms_mm"].get<double>(), 10.0);
  EXPECT_EQ(fail["calibration_id"], 2);
  const Result text = leafdig("field list" + db());
  EXPECT_NE(text.out.find("pass"), std::string::npos) << text.out;
  EXPECT_NE(text.out.find("fail"), std::string::npos) << text.out;
}

TEST_F(FieldCli, WhatIsWrongIsSaidBeforeAnythingRuns) {
  Result r = leafdig("field check" + db());
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_NE(r.err.find("give --digitizer KIND:PORT"), std::string::npos) << r.err;
  r = leafdig("field check --digitizer fastrak:/dev/ttyUSB0 --distortion " + bench() + db());
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_NE(r.err.find("goes with --simulate"), std::string::npos) << r.err;
  r = leafdig("field check --simulate --jig-pose 1,2" + db());
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_NE(r.err.find("--jig-pose is x,y,z,yaw_deg"), std::string::npos) << r.err;
  r = leafdig("field check --simulate --jig " + quote(sample("lower-leaf-n10.markers.json")) + db());
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_NE(r.err.find("this is not a jig file"), std::string::npos) << r.err;
  r = leafdig("field check --simulate --operator '' " + db());
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_NE(r.err.find("--operator: a field check is signed"), std::string::npos) << r.err;
  r = leafdig("field study --plant-jig-pose 1,2");
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_NE(r.err.find("--plant-jig-pose is x,y,z,yaw_deg"), std::string::npos) << r.err;
  // How old a check may be: the flag, else the station's settings file; refused in words, before
  // a session is made.
  r = leafdig("capture --simulate --field-check-max-age-hours 0" + db());
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_NE(r.err.find("--field-check-max-age-hours 0"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("from 1 to 8760"), std::string::npos) << r.err;
  const fs::path config = dir_ / "config";
  fs::create_directories(config / "leafdig");
  std::ofstream(config / "leafdig" / "station.ini") << "[station]\nid=bench-9\n[field]\nmax_check_age_hours=a week\n";
  const char* before = std::getenv("XDG_CONFIG_HOME");
  const std::string saved = before ? before : "";
  ::setenv("XDG_CONFIG_HOME", config.c_str(), 1);
  const Result leaf = leafdig("capture --simulate" + db());
  const Result plant = leafdig("plant capture --simulate" + db());
  if (before)
    ::setenv("XDG_CONFIG_HOME", saved.c_str(), 1);
  else
    ::unsetenv("XDG_CONFIG_HOME");
  for (const Result* refused : {&leaf, &plant}) {
    EXPECT_EQ(refused->exitCode, 2);
    EXPECT_NE(refused->err.find("station.ini: [field] max_check_age_hours = a week is not a number of hours"),
              std::string::npos)
        << refused->err;
  }
  EXPECT_FALSE(fs::exists(dir_ / "station.sqlite")) << "nothing was written";
  r = leafdig("field list" + db());
  EXPECT_NE(r.exitCode, 0);
  EXPECT_NE(r.err.find("no database at"), std::string::npos) << r.err;
}

}  // namespace

namespace {

// Every [x, y, z] of a document, in its order.
void triples(const json& j, std::vector<Eigen::Vector3d>& out) {
  if (j.is_array() && j.size() == 3 && j[0].is_number() && j[1].is_number() && j[2].is_number()) {
    out.emplace_back(j[0].get<double>(), j[1].get<double>(), j[2].get<double>());
    return;
  }
  if (j.is_array() || j.is_object())
    for (const auto& v : j) triples(v, out);
}

// The RMS distance of `got` from `truth` once the best rigid motion puts one on the other: the
// shape's error, whatever frame a correction left the points in.
double shapeRms(const std::vector<Eigen::Vector3d>& got, const std::vector<Eigen::Vector3d>& truth) {
  EXPECT_EQ(got.size(), truth.size());
  const auto n = static_cast<Eigen::Index>(std::min(got.size(), truth.size()));
  Eigen::Matrix3Xd a(3, n), b(3, n);
  for (Eigen::Index i = 0; i < n; ++i) {
    a.col(i) = got[static_cast<std::size_t>(i)];
    b.col(i) = truth[static_cast<std::size_t>(i)];
  }
  const Eigen::Matrix4d t = Eigen::umeyama(a, b, false);
  double sum = 0;
  for (Eigen::Index i = 0; i < n; ++i)
    sum += ((t.topLeftCorner<3, 3>() * a.col(i) + t.topRightCorner<3, 1>()) - b.col(i)).squaredNorm();
  return std::sqrt(sum / static_cast<double>(n));
}

}  // namespace

TEST_F(FieldCli, ALeafAndAPlantCapturedThroughTheCheckedFieldAreCorrectedAgainstTheirTruth) {
  const std::string run = " --simulate --speed 12 --seed 4 --no-mistakes --json" + db();
  // Before any check, a capture that asks for the latest is refused in words, nothing captured.
  Result r = leafdig("capture" + run + " --field-calibration latest --distortion " + bench() + " </dev/null");
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_NE(r.err.find("no field check in"), std::string::npos) << r.err;
  ASSERT_EQ(leafdig("field check --simulate --speed 10 --json --distortion " + bench() + db() + " </dev/null").exitCode,
            0);
  // The same leaf three times: through the bent field corrected, uncorrected, and in a clean field.
  ASSERT_EQ(leafdig("capture" + run + " --field-calibration latest --distortion " + bench() + " </dev/null").exitCode,
            0);
  ASSERT_EQ(leafdig("capture" + run + " --distortion " + bench() + " </dev/null").exitCode, 0);
  ASSERT_EQ(leafdig("capture" + run + " </dev/null").exitCode, 0);
  std::vector<Eigen::Vector3d> truth;
  triples(json::parse(slurp(sample("lower-leaf-n10.markers.json")))["rows"], truth);
  std::vector<double> rms;
  for (int id = 1; id <= 3; ++id) {
    ASSERT_EQ(leafdig("sessions export " + std::to_string(id) + " --format markers --frame digitizer --out " +
                      quote(dir_) + db())
                  .exitCode,
              0);
    std::vector<Eigen::Vector3d> got;
    triples(json::parse(slurp(dir_ / ("session-" + std::to_string(id) + ".markers.json")))["rows"], got);
    rms.push_back(shapeRms(got, truth));
  }
  std::cerr << "leaf shape RMS (mm): corrected " << rms[0] << ", uncorrected " << rms[1] << ", clean field " << rms[2]
            << "\n";
  // Corrected: within the clean field's error (1 mm RMS); uncorrected, the bend is plain.
  EXPECT_LT(rms[0], 1.0) << rms[0];
  EXPECT_LT(rms[2], 1.0) << rms[2];
  EXPECT_GT(rms[1], 1.5 * rms[0]) << rms[1] << " vs " << rms[0];
  // Which check applied: sessions show (text and JSON), and the interval widened by its held-out
  // error (a session without one shows no field).
  const json shown = json::parse(leafdig("sessions show 1 --json" + db()).out);
  EXPECT_EQ(shown["field_calibration"]["id"], 1);
  EXPECT_EQ(shown["field_calibration"]["correction"]["model"].get<std::string>().substr(0, 11), "polynomial-");
  EXPECT_FALSE(json::parse(leafdig("sessions show 2 --json" + db()).out).contains("field_calibration"));
  EXPECT_NE(leafdig("sessions show 1" + db()).out.find("field: field check 1 of "), std::string::npos);
  ASSERT_EQ(leafdig("sessions export 1 --format csv --out " + quote(dir_) + db()).exitCode, 0);
  EXPECT_NE(slurp(dir_ / "session-1.markers.csv").find("# field_calibration: field check 1 of "), std::string::npos);
  // A resumed session keeps its check: the flag is refused.
  r = leafdig("sessions resume 1 --field-calibration latest" + db());
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_NE(r.err.find("goes on through the field check it began with"), std::string::npos) << r.err;
  // The plant: the jig laid where the plant stands (check 2), then its every point through the
  // field, corrected and not, against the simulated plant.
  ASSERT_EQ(leafdig("field check --simulate --speed 10 --json --jig-pose 480,-100,-330,90 --distortion " + bench() +
                    db() + " </dev/null")
                .exitCode,
            0);
  const std::string plant = " --simulate --speed 12 --seed 3 --json --distortion " + bench() + db();
  ASSERT_EQ(leafdig("plant capture" + plant + " --field-calibration 2 </dev/null").exitCode, 0);
  ASSERT_EQ(leafdig("plant capture" + plant + " </dev/null").exitCode, 0);
  std::vector<Eigen::Vector3d> plantTruth;
  triples(json::parse(slurp(fs::path(LEAFDIG_SOURCE_DIR) / "data/plants/sample.plant-markers.json")), plantTruth);
  std::vector<double> plantRms;
  for (int id = 4; id <= 5; ++id) {
    ASSERT_EQ(
        leafdig("sessions export " + std::to_string(id) + " --format markers --out " + quote(dir_) + db()).exitCode, 0);
    std::vector<Eigen::Vector3d> got;
    triples(json::parse(slurp(dir_ / ("session-" + std::to_string(id) + ".plant-markers.json"))), got);
    plantRms.push_back(shapeRms(got, plantTruth));
  }
  std::cerr << "plant shape RMS (mm): corrected " << plantRms[0] << ", uncorrected " << plantRms[1] << "\n";
  EXPECT_LT(plantRms[0], plantRms[1]) << plantRms[0] << " vs " << plantRms[1];
  EXPECT_NE(leafdig("sessions show 4" + db()).out.find("field: field check 2 of "), std::string::npos);
  // Each node's tolerance takes in the correction's error on divots it did not see: in the survey
  // sessions show gives, its words and the JSON export; the uncorrected plant's nodes have the
  // digitizer's own, which goes unsaid as before.
  const double heldOut = json::parse(leafdig("field show 2 --json" + db()).out)["correction"]["holdout_rms_mm"];
  ASSERT_GT(heldOut, 0.0);
  const json surveyed = json::parse(leafdig("sessions show 4 --json" + db()).out)["survey"];
  ASSERT_FALSE(surveyed["nodes"].empty());
  for (const json& n : surveyed["nodes"])
    EXPECT_NEAR(n["position_tolerance_mm"].get<double>(), 2.7955 * std::hypot(0.762, heldOut), 1e-9) << n.dump();
  EXPECT_FALSE(json::parse(leafdig("sessions show 5 --json" + db()).out)["survey"]["nodes"][0].contains(
      "position_tolerance_mm"));
  EXPECT_NE(leafdig("sessions show 4" + db()).out.find("node tolerance (95 %): up to "), std::string::npos);
  ASSERT_EQ(leafdig("sessions export 4 --format json --out " + quote(dir_) + db()).exitCode, 0);
  EXPECT_EQ(json::parse(slurp(dir_ / "session-4.survey.json"))["nodes"], surveyed["nodes"]);
}

// A stylus whose sensor sits up its shaft, away from the tip (issue 50's tip calibration): the
// technician pivots it in a divot, leafdig fits the tip and keeps it, and every capture after goes
// through it — a leaf captured without it is bent by the hand's tilt, with it it is the leaf.
TEST_F(FieldCli, ATipCalibrationFindsTheStylusTipAndEveryCaptureGoesThroughIt) {
  // A stylus 20 mm longer than its digitizer takes it for (a replacement tip), a little bent.
  const std::string sim = " --simulate --sim-tip 2,-1,20 --speed 8";
  Result r = leafdig("field tip" + sim + " --json --operator ana" + db() + " </dev/null");
  ASSERT_EQ(r.exitCode, 0) << r.err << r.out;
  const json tip = lastLine(r.out);
  EXPECT_EQ(tip["verdict"], "pass");
  EXPECT_EQ(tip["calibration_id"], 1);
  EXPECT_EQ(tip["device"], "fastrak:simulated");
  EXPECT_NEAR(tip["tip_mm"][0].get<double>(), 2.0, 0.5) << tip.dump();
  EXPECT_NEAR(tip["tip_mm"][1].get<double>(), -1.0, 0.5) << tip.dump();
  EXPECT_NEAR(tip["tip_mm"][2].get<double>(), 20.0, 0.5) << tip.dump();
  EXPECT_LT(tip["rms_mm"].get<double>(), 1.0);
  EXPECT_GE(tip["samples"].get<int>(), 20);
  EXPECT_GT(tip["tilt_spread_deg"].get<double>(), 30.0);
  EXPECT_NE(r.out.find("\"event\":\"prompt\""), std::string::npos);
  const json listed = json::parse(leafdig("field tips --json" + db()).out);
  ASSERT_EQ(listed.size(), 1U);
  EXPECT_EQ(listed[0]["tip_mm"], tip["tip_mm"]);
  EXPECT_NE(leafdig("field tips" + db()).out.find("fastrak:simulated  tip ("), std::string::npos);

  // The same leaf through the tip (the newest passing calibration: the default) and without it.
  const std::string run = sim + " --seed 4 --no-mistakes --json" + db();
  ASSERT_EQ(leafdig("capture" + run + " </dev/null").exitCode, 0);
  ASSERT_EQ(leafdig("capture" + run + " --tip-calibration none </dev/null").exitCode, 0);
  std::vector<Eigen::Vector3d> truth;
  triples(json::parse(slurp(sample("lower-leaf-n10.markers.json")))["rows"], truth);
  std::vector<double> rms;
  for (int id = 1; id <= 2; ++id) {
    ASSERT_EQ(leafdig("sessions export " + std::to_string(id) + " --format markers --frame digitizer --out " +
                      quote(dir_) + db())
                  .exitCode,
              0);
    std::vector<Eigen::Vector3d> got;
    triples(json::parse(slurp(dir_ / ("session-" + std::to_string(id) + ".markers.json")))["rows"], got);
    rms.push_back(shapeRms(got, truth));
  }
  std::cerr << "leaf shape RMS (mm): through the tip " << rms[0] << ", without " << rms[1] << "\n";
  EXPECT_LT(rms[0], 1.0) << rms[0];
  EXPECT_GT(rms[1], 3.0 * rms[0]) << rms[1] << " vs " << rms[0];
  // Which calibration applied, in sessions show (text and JSON) and the exports' provenance.
  const json shown = json::parse(leafdig("sessions show 1 --json" + db()).out);
  EXPECT_EQ(shown["tip_calibration"]["id"], 1);
  EXPECT_EQ(shown["tip_calibration"]["device"], "fastrak:simulated");
  EXPECT_FALSE(json::parse(leafdig("sessions show 2 --json" + db()).out).contains("tip_calibration"));
  EXPECT_NE(leafdig("sessions show 1" + db()).out.find("stylus tip: tip calibration 1 of "), std::string::npos);
  ASSERT_EQ(leafdig("sessions export 1 --format csv --out " + quote(dir_) + db()).exitCode, 0);
  EXPECT_NE(slurp(dir_ / "session-1.markers.csv").find("# tip_calibration: tip calibration 1 of "), std::string::npos);
  // A resumed session keeps its own; a calibration that is not there is refused in words.
  r = leafdig("sessions resume 1 --tip-calibration none" + db());
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_NE(r.err.find("goes on with the tip calibration it began with"), std::string::npos) << r.err;
  r = leafdig("capture" + run + " --tip-calibration 7 </dev/null");
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_NE(r.err.find("there is no tip calibration 7"), std::string::npos) << r.err;
  r = leafdig("capture --simulate --sim-tip 0,0,900" + db() + " </dev/null");
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_NE(r.err.find("--sim-tip is x,y,z in mm, each within 500"), std::string::npos) << r.err;
  // A plant captured with the same stylus goes through it too.
  ASSERT_EQ(leafdig("plant capture" + sim + " --seed 3 --json" + db() + " </dev/null").exitCode, 0);
  EXPECT_EQ(json::parse(leafdig("sessions show 3 --json" + db()).out)["tip_calibration"]["id"], 1);
  // A field check with the same stylus touches the divots through the tip and keeps which (its
  // record, its JSON, its words); told not to, it keeps none — and its presses are the sensor's.
  r = leafdig("field check" + sim + " --json" + db() + " </dev/null");
  ASSERT_EQ(r.exitCode, 0) << r.err << r.out;
  const json through = lastLine(r.out);
  EXPECT_EQ(through["tip_calibration"], 1) << through.dump();
  EXPECT_EQ(through["verdict"], "pass") << through.dump();
  EXPECT_NE(leafdig("field show 1" + db()).out.find("stylus tip: tip calibration 1 of "), std::string::npos);
  r = leafdig("field check" + sim + " --tip-calibration none --json" + db() + " </dev/null");
  ASSERT_TRUE(r.exitCode == 0 || r.exitCode == 3) << r.err << r.out;
  const json without = lastLine(r.out);
  EXPECT_TRUE(without["tip_calibration"].is_null()) << without.dump();
  EXPECT_GT(without["rms_mm"].get<double>(), through["rms_mm"].get<double>()) << without.dump();
  EXPECT_NE(leafdig("field show 2" + db()).out.find("stylus tip: none"), std::string::npos);
}

namespace {

// A row's numbers from the study's Markdown: the cells after `prefix` (e.g. "| lower-leaf-n10 | 71 | corrected |").
std::vector<double> rowNumbers(const std::string& report, const std::string& prefix) {
  const auto at = report.find(prefix);
  if (at == std::string::npos) return {};
  const std::string line = report.substr(at + prefix.size(), report.find('\n', at) - at - prefix.size());
  std::vector<double> out;
  std::istringstream cells(line);
  std::string cell;
  while (std::getline(cells, cell, '|'))
    if (cell.find_first_not_of(' ') != std::string::npos) out.push_back(std::stod(cell));
  return out;
}

}  // namespace

// The study of issue 50's "Measured": the sample leaves and plant through the steel bench,
// clean, uncorrected and corrected, against their truth (docs/field-study.md is its report).
TEST_F(FieldCli, TheFieldStudyShowsTheCorrectionBringingLeavesBackToTheCleanFieldsError) {
  const fs::path out = dir_ / "field-study.md";
  ASSERT_EQ(leafdig("field study --repeats 3 -o " + quote(out)).exitCode, 0);
  const std::string report = slurp(out);
  EXPECT_NE(report.find("Generated by `leafdig field study --repeats 3 -o field-study.md`"), std::string::npos);
  // The check reports what the field is: reported ÷ truth within 20 %.
  const std::vector<double> ratio = rowNumbers(report, "| reported ÷ truth |");
  ASSERT_FALSE(ratio.empty()) << report;
  EXPECT_GT(ratio[0], 0.8);
  EXPECT_LT(ratio[0], 1.2);
  for (const std::string leaf : {"lower-leaf-n10 | 71", "upper-curved-leaf-n14 | 99", "upper-small-leaf-n17 | 120"}) {
    const auto clean = rowNumbers(report, "| " + leaf + " | clean |");
    const auto bent = rowNumbers(report, "| " + leaf + " | uncorrected |");
    const auto fixed = rowNumbers(report, "| " + leaf + " | corrected |");
    ASSERT_EQ(clean.size(), 3U) << leaf << "\n" << report;
    ASSERT_EQ(fixed.size(), 3U);
    ASSERT_EQ(bent.size(), 3U);
    // Shape: corrected within the clean field's error (≤ 1 mm, and near the noise alone);
    // area: within 0.5 % and better than uncorrected.
    EXPECT_LT(fixed[1], 1.0) << leaf;
    EXPECT_LT(fixed[1], clean[1] * 1.25) << leaf;
    EXPECT_LT(fixed[1], bent[1]) << leaf;
    EXPECT_LT(fixed[2], 0.5) << leaf;
    EXPECT_LT(fixed[2], bent[2]) << leaf;
  }
  // The bench's worst leaf is millimetres off uncorrected.
  EXPECT_GT(rowNumbers(report, "| lower-leaf-n10 | 71 | uncorrected |")[1], 1.5);
  // The plant: its nodes and area nearer the truth corrected than not.
  const auto plantBent = rowNumbers(report, "| sample plant | 5 | 3 | uncorrected |");
  const auto plantFixed = rowNumbers(report, "| sample plant | 5 | 3 | corrected |");
  ASSERT_EQ(plantFixed.size(), 3U) << report;
  EXPECT_LT(plantFixed[0], plantBent[0]);
  EXPECT_LT(plantFixed[2], plantBent[2]);
  // With no noise the clean capture is the truth.
  const Result exact = leafdig("field study --repeats 1 --noise-mm 0 --counts 22");
  ASSERT_EQ(exact.exitCode, 0) << exact.err;
  EXPECT_EQ(rowNumbers(exact.out, "| lower-leaf-n10 | 71 | clean |"), (std::vector<double>{0, 0, 0}));
  // A count the jig does not have is refused in words.
  const Result tooMany = leafdig("field study --repeats 1 --counts 40");
  EXPECT_EQ(tooMany.exitCode, 2);
  EXPECT_NE(tooMany.err.find("a jig count of 40 divots: the jig has 22"), std::string::npos) << tooMany.err;
}

// Sentinel divots (issue 50): before the first leaf, a few of the check's divots taken again where
// the jig lay for the check. In the field the check found they hold, and the session keeps them
// with its check; with the metal moved nearer (the plate 150 mm below instead of 250) they do not,
// and the capture stops in words before a session is made.
TEST_F(FieldCli, SentinelDivotsConfirmTheCheckBeforeACaptureAndStopItWhenTheFieldMoved) {
  ASSERT_EQ(leafdig("field check --simulate --speed 10 --json --distortion " + bench() + db() + " </dev/null").exitCode,
            0);
  const std::string run = " --simulate --speed 12 --seed 4 --no-mistakes --json" + db();
  Result r =
      leafdig("capture" + run + " --field-calibration latest --sentinels 4 --distortion " + bench() + " </dev/null");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  // Prompted as the check's divots are, then the capture's own prompts.
  EXPECT_NE(r.out.find(" (1 of 4) and press"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find(" (4 of 4) and press"), std::string::npos);
  EXPECT_LT(r.out.find(R"("event":"sentinels")"), r.out.find(R"("event":"session")")) << "before the session";
  const json shown = json::parse(leafdig("sessions show 1 --json" + db()).out);
  const json& sentinels = shown["field_calibration"]["sentinels"];
  EXPECT_EQ(shown["field_calibration"]["id"], 1);
  EXPECT_EQ(sentinels["verdict"], "held");
  ASSERT_EQ(sentinels["divots"].size(), 4U);
  EXPECT_LT(sentinels["max_mm"].get<double>(), 0.5) << "the same field, the same places";
  const std::string text = leafdig("sessions show 1" + db()).out;
  EXPECT_NE(text.find("sentinels: 4 sentinel divots of field check 1 taken again: the largest move "),
            std::string::npos)
      << text;
  // The metal moved: the plate 150 mm below. A plant capture through check 1 stops before it begins.
  ASSERT_EQ(leafdig("field model steel-bench --below-mm 150 -o " + quote(dir_ / "moved.field.json")).exitCode, 0);
  r = leafdig("plant capture --simulate --speed 12 --seed 3 --json --field-calibration 1 --sentinels 3 --distortion " +
              quote(dir_ / "moved.field.json") + db() + " </dev/null");
  EXPECT_EQ(r.exitCode, 3) << r.err;
  EXPECT_NE(r.err.find("beyond its 1.50 mm: the field moved since the check"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("no session was made"), std::string::npos) << r.err;
  EXPECT_EQ(json::parse(leafdig("sessions list --json" + db()).out).size(), 1U) << "nothing was made";
  // What is wrong is said before anything runs: sentinels of no check, a count the rule does not
  // take, sentinels on a resumed session; a station setting of sentinels without a check is moot.
  r = leafdig("capture" + run + " --sentinels 4 </dev/null");
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_NE(r.err.find("--sentinels takes a field check's divots again: they go with --field-calibration"),
            std::string::npos)
      << r.err;
  r = leafdig("plant capture --simulate --field-calibration 1 --sentinels 2" + db() + " </dev/null");
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_NE(r.err.find("--sentinels 2: take 3 to 5"), std::string::npos) << r.err;
  r = leafdig("sessions resume 1 --sentinels 3" + db());
  EXPECT_NE(r.exitCode, 0);
  EXPECT_EQ(json::parse(leafdig("sessions list --json" + db()).out).size(), 1U);
}
