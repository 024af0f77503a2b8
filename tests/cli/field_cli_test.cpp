// `leafdig field check|list|show` driven as a technician would (issue 50): the simulated FASTRAK in
// a field bent by the steel-bench preset, a virtual technician touching the shipped jig's divots
// as prompted; the verdict, the correction chosen by its error on divots it did not see, the error
// map, the check stored and read back. A clean field passes, a field bent past correcting fails
// with its own exit code, and what is wrong with the request is said before anything runs.
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
  EXPECT_FALSE(fs::exists(dir_ / "station.sqlite")) << "nothing was written";
  r = leafdig("field list" + db());
  EXPECT_NE(r.exitCode, 0);
  EXPECT_NE(r.err.find("no database at"), std::string::npos) << r.err;
}

}  // namespace
