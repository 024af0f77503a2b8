// CaptureRun: the one capture lifecycle the command line and the station drive. Simulated
// devices over real ptys, a real store; also run under ThreadSanitizer.
#include "leafdig/acquisition/run/capture_run.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <functional>
#include <stdexcept>
#include <thread>

#include "leafdig/model/leaf/markers_json.hpp"

namespace acq = leafdig::acquisition;
namespace fs = std::filesystem;

namespace {

const std::string kSamples = std::string(LEAFDIG_SOURCE_DIR) + "/data/samples/";

fs::path freshDir(const std::string& tag) {
  const fs::path dir = fs::temp_directory_path() / ("leafdig-run-" + tag + "-" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

acq::RunRequest simulatedRequest(const fs::path& dir, const std::string& leafFile, std::uint64_t seed) {
  acq::RunRequest r;
  r.db = (dir / "s.sqlite").string();
  r.setup.project = "p";
  r.setup.plant = "pl";
  r.setup.simulated = true;
  r.simulation.speed = 10;
  r.simulation.seed = seed;
  r.simulation.mistakes = false;
  r.simulation.linkDir = dir.string();
  r.leafFile = leafFile;
  r.preview = acq::PreviewDetail::None;
  return r;
}

bool waitFor(const std::function<bool()>& ok, int seconds) {
  for (int i = 0; i < seconds * 50 && !ok(); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(20));
  return ok();
}

// Every stored marker lies within `tolMm` of the same marker of `leaf`.
int markersOffTheLeaf(const leafdig::db::Store& store, std::int64_t id, const leafdig::model::MarkerSet& leaf,
                      double tolMm) {
  int off = 0;
  for (const auto& m : store.markers(id)) {
    if (m.what != "marker") continue;
    const auto& truth =
        leaf.rows.at(static_cast<std::size_t>(*m.row - 1)).pointsMm.at(static_cast<std::size_t>(*m.col - 1));
    const double dx = m.positionMm[0] - truth.x(), dy = m.positionMm[1] - truth.y(), dz = m.positionMm[2] - truth.z();
    off += std::sqrt(dx * dx + dy * dy + dz * dz) > tolMm;
  }
  return off;
}

}  // namespace

TEST(CaptureRun, StoppingAnUnfinishedCaptureRecordsAPauseAndAResumedSimulationDigitizesTheSameLeaf) {
  const fs::path dir = freshDir("resume");
  // Not the default sample: a resumed run that fell back to the default leaf would put
  // another leaf's markers into this session.
  const std::string leafFile = kSamples + "upper-small-leaf-n17.markers.json";
  const auto leaf = leafdig::model::readMarkersFile(leafFile);
  std::int64_t id = 0;
  {
    std::atomic<int> accepted{0};
    std::atomic<bool> paused{false};
    acq::RunObserver observer;
    observer.onFeedback = [&](const acq::Feedback& f) {
      accepted += f.kind == acq::Feedback::Kind::Accepted;
      paused = paused || f.kind == acq::Feedback::Kind::Paused;
    };
    acq::CaptureRun run(simulatedRequest(dir, leafFile, 3), observer);
    id = run.sessionId();
    EXPECT_TRUE(run.simulated());
    run.start();
    ASSERT_TRUE(waitFor([&] { return accepted >= 12; }, 120));
    const acq::Snapshot last = run.shutdown("end of the shift");
    EXPECT_FALSE(last.complete);
    EXPECT_TRUE(last.paused);
    EXPECT_TRUE(paused);  // the observer was told, like any other feedback
  }
  leafdig::db::Store store((dir / "s.sqlite").string());
  const auto events = store.events(id);
  ASSERT_FALSE(events.empty());
  EXPECT_EQ(events.back().kind, "paused");
  EXPECT_NE(events.back().payloadJson.find("end of the shift"), std::string::npos);
  EXPECT_EQ(store.session(id)->status, "open");

  // Resumed without naming the leaf: it goes on with the leaf the session recorded.
  acq::RunRequest again = simulatedRequest(dir, "", 5);
  again.resume = id;
  again.setup.simulated = false;  // the session, not the request, says it is simulated
  std::atomic<bool> complete{false};
  acq::RunObserver observer;
  observer.onFeedback = [&](const acq::Feedback& f) { complete = complete || f.kind == acq::Feedback::Kind::Complete; };
  acq::CaptureRun run(again, observer);
  EXPECT_TRUE(run.simulated());
  EXPECT_DOUBLE_EQ(run.timeScale(), 10.0);  // the recorded time scale
  run.start();
  ASSERT_TRUE(waitFor([&] { return run.finished(); }, 240));
  const acq::Snapshot last = run.shutdown("not used: the leaf is complete");
  EXPECT_TRUE(last.complete) << last.prompt;
  EXPECT_TRUE(complete);
  EXPECT_EQ(store.session(id)->status, "complete");
  int markers = 0;
  for (const auto& m : store.markers(id)) markers += m.what == "marker";
  EXPECT_EQ(markers, static_cast<int>(leaf.rows.size()) * 7);
  EXPECT_EQ(markersOffTheLeaf(store, id, leaf, 3.0), 0);
  // A completed run records no pause when it is shut down.
  EXPECT_NE(store.events(id).back().kind, "paused");
  EXPECT_TRUE(store.verify(id).ok);
  fs::remove_all(dir);
}

TEST(CaptureRun, AResumedSimulationRefusesAnotherLeafAndARealSessionRefusesSimulation) {
  const fs::path dir = freshDir("refuse");
  std::int64_t simulated = 0;
  {
    acq::CaptureRun run(simulatedRequest(dir, kSamples + "upper-small-leaf-n17.markers.json", 1), {});
    simulated = run.sessionId();
  }
  acq::RunRequest other = simulatedRequest(dir, kSamples + "lower-leaf-n10.markers.json", 1);
  other.resume = simulated;
  try {
    acq::CaptureRun run(other, {});
    FAIL() << "resumed with another leaf";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("another leaf"), std::string::npos) << e.what();
  }

  acq::RunRequest real;
  real.db = (dir / "s.sqlite").string();
  real.setup.project = "p";
  real.setup.plant = "pl";
  real.setup.digitizer = "fastrak:/dev/leafdig-no-such-port";
  real.setup.caliper = "sylvac:/dev/leafdig-no-such-port";
  std::int64_t realId = 0;
  {
    acq::CaptureRun run(real, {});  // devices are opened on start(), not here
    realId = run.sessionId();
    EXPECT_FALSE(run.simulated());
  }
  acq::RunRequest simulate = simulatedRequest(dir, "", 1);
  simulate.resume = realId;
  try {
    acq::CaptureRun run(simulate, {});
    FAIL() << "a session captured with real devices was resumed with simulated ones";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("real devices"), std::string::npos) << e.what();
  }
  // Never started: shutting down wrote nothing.
  leafdig::db::Store store((dir / "s.sqlite").string());
  EXPECT_TRUE(store.events(simulated).empty());
  EXPECT_TRUE(store.events(realId).empty());
  fs::remove_all(dir);
}

TEST(CaptureRun, ABadDeviceSpecIsRefusedBeforeTheStoreIsTouched) {
  const fs::path dir = freshDir("spec");
  acq::RunRequest r;
  r.db = (dir / "s.sqlite").string();
  r.setup.digitizer = "fastrack:/dev/ttyUSB0";  // a typo
  r.setup.caliper = "sylvac:/dev/ttyUSB1";
  EXPECT_THROW(acq::CaptureRun(r, {}), std::invalid_argument);
  r.setup.digitizer = "fastrak:/dev/ttyUSB0";
  r.setup.caliper = "";
  EXPECT_THROW(acq::CaptureRun(r, {}), std::invalid_argument);
  r.setup.simulated = true;
  r.leafFile = (dir / "missing.markers.json").string();
  EXPECT_ANY_THROW(acq::CaptureRun(r, {}));
  EXPECT_FALSE(fs::exists(dir / "s.sqlite"));
  fs::remove_all(dir);
}
