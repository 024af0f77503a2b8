// `leafdig devices`, `sim` and `doctor`, driven as a user would from a shell.
#include <chrono>
#include <thread>

#include "cli_support.hpp"

namespace {

using namespace std::chrono_literals;

class DevicesCli : public Cli {
 protected:
  // Starts `leafdig sim ARGS --link LINK` in the background; waits for the link.
  fs::path startSim(const std::string& args, double seconds) {
    const fs::path link = dir_ / "sim-port";
    const std::string cmd = quote(LEAFDIG_CLI) + " sim " + args + " --link " + quote(link) + " --seconds " +
                            std::to_string(seconds) + " >" + quote(dir_ / "sim.out") + " 2>" + quote(dir_ / "sim.err") +
                            " &";
    EXPECT_EQ(std::system(cmd.c_str()), 0);
    for (int i = 0; i < 200 && !fs::exists(link); ++i) std::this_thread::sleep_for(20ms);
    EXPECT_TRUE(fs::exists(link)) << slurp(dir_ / "sim.err");
    return link;
  }
  void waitSimEnd(const fs::path& link) {
    for (int i = 0; i < 600 && fs::is_symlink(link); ++i) std::this_thread::sleep_for(20ms);
  }
};

TEST_F(DevicesCli, ListOnAMachineWithoutDevicesIsAFriendlyAnswer) {
  const Result r = leafdig("devices list");
  EXPECT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(r.out.find("Serial ports"), std::string::npos);
  EXPECT_NE(r.out.find("HID devices"), std::string::npos);
  const Result j = leafdig("devices list --json");
  ASSERT_EQ(j.exitCode, 0);
  const json parsed = json::parse(j.out);
  EXPECT_TRUE(parsed["serial"].is_array());
  EXPECT_TRUE(parsed["hid"].is_array());
  EXPECT_TRUE(parsed["usb"].is_array());
}

TEST_F(DevicesCli, DoctorNamesEveryCheckWithARemedy) {
  const Result r = leafdig("doctor --json");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const json checks = json::parse(r.out);
  ASSERT_GE(checks.size(), 6u);
  bool udev = false;
  for (const auto& c : checks) {
    if (!c["ok"].get<bool>()) {
      EXPECT_FALSE(c["remedy"].get<std::string>().empty()) << c.dump();
    }
    udev |= c["check"] == "udev rule";
  }
  EXPECT_TRUE(udev);
}

TEST_F(DevicesCli, SimAndListenTalkOverAPseudoTerminalInJsonLines) {
  const fs::path link = startSim("fastrak --markers " + quote(sample("lower-leaf-n10.markers.json")), 4);
  const Result r = leafdig("devices listen --digitizer fastrak --port " + quote(link) + " --count 30 --json");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  std::istringstream lines(r.out);
  std::string line;
  int n = 0;
  while (std::getline(lines, line)) {
    const json s = json::parse(line);
    ASSERT_TRUE(s["t"].is_number());
    EXPECT_EQ(s["station"], 1);
    ASSERT_EQ(s["position_mm"].size(), 3u);
    EXPECT_EQ(s["orientation_deg"].size(), 3u);
    EXPECT_TRUE(s["button"].is_boolean());
    EXPECT_EQ(s["status"], "ok");
    EXPECT_EQ(s["raw"].get<std::string>().substr(0, 2), "01");
    ++n;
  }
  EXPECT_EQ(n, 30);
  EXPECT_NE(r.err.find("[streaming]"), std::string::npos);
  waitSimEnd(link);
  EXPECT_NE(slurp(dir_ / "sim.err").find("sent"), std::string::npos);
}

TEST_F(DevicesCli, ListenToASimulatedSylvacWithPcTriggeredReads) {
  const fs::path link = startSim("sylvac --markers " + quote(sample("lower-leaf-n10.markers.json")), 4);
  const Result r = leafdig("devices listen --caliper sylvac --port " + quote(link) + " --poll-ms 100 --count 3 --json");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  std::istringstream lines(r.out);
  std::string line;
  int n = 0;
  while (std::getline(lines, line)) {
    const json s = json::parse(line);
    EXPECT_GT(s["value_mm"].get<double>(), 0.0);
    EXPECT_EQ(s["unit"], "mm");
    ++n;
  }
  EXPECT_EQ(n, 3);
  waitSimEnd(link);
}

TEST_F(DevicesCli, ADeadPortEndsWithTheLastStateAndWhatToDo) {
  const Result r = leafdig("devices listen --digitizer fastrak --port /dev/ttyLEAFDIG-missing --seconds 1");
  EXPECT_EQ(r.exitCode, 1);
  EXPECT_NE(r.err.find("no samples received"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("/dev/ttyLEAFDIG-missing"), std::string::npos);
  EXPECT_NE(r.err.find("what to do"), std::string::npos);
}

TEST_F(DevicesCli, BadOptionsAreExitCode2WithTheFix) {
  Result r = leafdig("devices listen --digitizer polaris --port /dev/null");
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_NE(r.err.find("fastrak, patriot, liberty, microscribe or line"), std::string::npos) << r.err;
  r = leafdig("devices listen --digitizer fastrak");
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_NE(r.err.find("--port"), std::string::npos);
  r = leafdig("devices listen --caliper hid --hid zz:yy");
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_NE(r.err.find("VID:PID"), std::string::npos);
  r = leafdig("sim fastrak --markers " + quote(sample("lower-leaf-n10.markers.json")) + " --faults wobble=0.1");
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_NE(r.err.find("unknown fault 'wobble'"), std::string::npos) << r.err;
  r = leafdig("sim fastrak --markers " + quote(sample("lower-leaf-n10.markers.json")) + " --faults garbage=2");
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_NE(r.err.find("probability"), std::string::npos);
  r = leafdig("sim fastrak --markers /nonexistent.markers.json");
  EXPECT_EQ(r.exitCode, 2);
  const fs::path cfg = write("line.json", R"({"unit": "furlong"})");
  r = leafdig("devices listen --digitizer line --port /dev/null --line-config " + quote(cfg));
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_NE(r.err.find("unit must be"), std::string::npos) << r.err;
}

}  // namespace
