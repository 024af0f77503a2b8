// The command line's one error map (ui/cli/failure.hpp), driven through the real binary:
// one row per family of failure, each with its exit code and its words.
#include <csignal>
#include <thread>

#include "cli_support.hpp"

namespace {

class FailureCli : public Cli {};

struct Row {
  std::string family;
  std::string args;
  int exitCode;
  std::string says;  // the message names this
  bool remedy;       // and says what to do
};

TEST_F(FailureCli, EachFamilyOfFailureHasItsExitCodeAndItsWords) {
  const std::string leaf = quote(sample("lower-leaf-n10.markers.json"));
  const fs::path bad = write("bad.markers.json", "{\"format\": \"leafdig.markers/1\", \"rows\": [");
  const fs::path other = dir_ / "other.sqlite";
  ASSERT_EQ(run("python3 -c \"import sqlite3; c=sqlite3.connect('" + other.string() +
                "'); c.execute('create table plants(x)'); c.commit()\"")
                .exitCode,
            0);
  const std::vector<Row> rows{
      {"a command line CLI11 cannot parse", "model build", 2, "markers is required", true},
      {"an unknown option", "model build " + leaf + " --no-such-option", 2, "--no-such-option", true},
      {"a bad input file (model::InputError)", "model build " + quote(bad) + " -o " + quote(dir_ / "o.glb"), 2,
       "bad.markers.json", false},
      {"a bad option value (std::invalid_argument)", "capture --db " + quote(dir_ / "c.sqlite"), 2,
       "capture needs --digitizer", false},
      {"a bad simulator (InputError from devices)", "sim nosuchdevice --markers " + leaf, 2, "unknown simulator",
       false},
      {"an unknown word (UnknownName, from the device spec)",
       "capture --digitizer wobble:/dev/ttyS0 --caliper hid --db " + quote(dir_ / "w.sqlite"), 2,
       "unknown digitizer \"wobble\": use fastrak, patriot, liberty, microscribe or line", false},
      {"a bad fault script", "sim fastrak --faults garbage=2 --markers " + leaf, 2, "--faults:", false},
      {"a file of another program (StoreError NotLeafdig)", "sessions list --db " + quote(other), 2,
       "not a leafdig one", true},
      {"no database (std::invalid_argument)", "sessions list --db " + quote(dir_ / "missing.sqlite"), 2,
       "no database at", false},
      {"a lab server that does not answer (StoreError Unreachable)",
       "sessions list --db postgresql://nobody@127.0.0.1:1/lab", 1, "127.0.0.1", true},
      {"not a server URL (StoreError Input)", "sync push --to http://lab/ --db " + quote(other), 2,
       "is not a postgresql:// URL", true},
      {"a link the simulator cannot make where it was asked (DeviceError Config)",
       "sim fastrak --seconds 1 --link " + quote(dir_ / "no-such-folder" / "pty") + " --markers " + leaf, 2,
       "cannot make the link", true},
      {"an output that cannot be written (model::IoError)",
       "model build " + leaf + " -o " + quote(dir_ / "no-such-folder" / "leaf.glb"), 1, "no-such-folder", false},
  };
  for (const Row& row : rows) {
    SCOPED_TRACE(row.family + ": leafdig " + row.args);
    const Result r = leafdig(row.args);
    EXPECT_EQ(r.exitCode, row.exitCode) << r.err;
    EXPECT_EQ(r.err.rfind("leafdig: ", 0), 0u) << "the first line says who speaks: " << r.err;
    EXPECT_NE(r.err.find(row.says), std::string::npos) << r.err;
    EXPECT_EQ(r.err.find("what to do:") != std::string::npos, row.remedy) << r.err;
    EXPECT_EQ(r.err.find("internal error"), std::string::npos) << r.err;
  }
}

TEST_F(FailureCli, AnInterruptedCaptureExits130AndASessionThatIsNotThereIsBadInput) {
  const fs::path db = dir_ / "s.sqlite";
  const fs::path out = dir_ / "capture.out";
  const fs::path err = dir_ / "capture.err";
  const pid_t pid = spawn({"capture", "--simulate", "--json", "--speed", "1", "--db", db.string(), "--markers",
                           sample("lower-leaf-n10.markers.json")},
                          out, err);
  // Interrupt once the session is committed (the first JSON line says so).
  for (int i = 0; i < 600 && slurp(out).find("\"session\"") == std::string::npos; ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  ASSERT_NE(slurp(out).find("\"session\""), std::string::npos) << slurp(err);
  ::kill(pid, SIGINT);
  const int status = reap(pid);
  ASSERT_TRUE(WIFEXITED(status)) << slurp(err);
  EXPECT_EQ(WEXITSTATUS(status), 130) << slurp(err);
  // The session is kept, open, for 'sessions resume'.
  const Result list = leafdig("sessions list --json --db " + quote(db));
  ASSERT_EQ(list.exitCode, 0) << list.err;
  EXPECT_NE(list.out.find("open"), std::string::npos) << list.out;
  // A session id that is not in the file: acquisition::SessionError, bad input.
  const Result show = leafdig("sessions show 99 --db " + quote(db));
  EXPECT_EQ(show.exitCode, 2) << show.err;
  EXPECT_NE(show.err.find("there is no session 99"), std::string::npos) << show.err;
}

}  // namespace
