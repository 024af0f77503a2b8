// One capture from start to shutdown, the same for every front end: opens the store,
// creates or reopens the session (replaying it), wires the devices — real ones from their
// specs, or the simulated rig and the virtual technician — to a capture loop on its own
// thread, takes commands, and on shutdown records a pause when the session is neither
// complete nor abandoned, so the next run resumes at the exact step. `leafdig capture`,
// `leafdig sessions resume`, `leafdig demo` and the station drive it and observe it.
//
// Thread contract: construct, start(), wait() and shutdown() on one owner thread;
// command(), setPedal(), pedal(), requestStop(), finished(), latestStylus() and devices() from any
// thread. The observer's callbacks run on the capture thread (and, for the pause recorded
// at shutdown, on the owner thread) and must not block for long.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <thread>

#include "leafdig/acquisition/field/field_applied.hpp"
#include "leafdig/acquisition/live/device_set.hpp"
#include "leafdig/acquisition/live/leaf_loop.hpp"
#include "leafdig/acquisition/session/session.hpp"
#include "leafdig/acquisition/sim/simulation.hpp"

namespace leafdig::acquisition {

// A simulation's speed (1 = real time): from a tenth of real time to fifty times it. Throws
// std::invalid_argument in words otherwise (the leaf's and the plant's captures, the station).
inline constexpr double kMinSimulationSpeed = 0.1, kMaxSimulationSpeed = 50.0;
void checkSimulationSpeed(double speed);
// A turn of the simulated pot or board (--pot-turn, -360…360°) under the reference receiver it
// carries: only in a simulation with the reference receiver (without one, a turning pot moves
// the plant under the stylus). `carrier` is what turns ("pot", "board"). Throws
// std::invalid_argument in words (the leaf's and the plant's captures, the station).
void checkPotTurn(double degrees, bool simulated, bool referenceReceiver, const std::string& carrier);

struct RunRequest {
  std::string db;           // SQLite file; empty: the station's default file
  std::int64_t resume = 0;  // an open session to continue; 0: a new one from `setup`
  SessionSetup setup;       // a new session: what, who, how, which devices (or simulated)
  // Resuming with real devices: ports that replace the recorded ones (a cable moved).
  std::string digitizer, caliper;
  // Simulation (setup.simulated for a new session; a resumed session that was simulated is
  // simulated again). `simulation.speed` is the time scale of a new session; a resumed one
  // keeps its recorded time scale unless `speed` is given.
  SimulationOptions simulation;
  std::optional<double> speed;
  // The leaf the virtual technician digitizes (a leafdig.markers/1 file). A new session
  // records it; a resumed session goes on with the leaf it recorded, and a different file
  // here is refused. Empty: the recorded leaf, else the default sample.
  std::string leafFile;
  // Or the leaf itself (a synthetic leaf made for this run); at most one of the two.
  std::optional<model::MarkerSet> leaf;
  // What snapshots carry of the live preview: a view draws meshes (built off the capture
  // thread), a terminal prints from the model, scripts need none.
  PreviewDetail preview = PreviewDetail::Meshes;
  // A new session's field check (field_applied.hpp): "" or "none", "latest", or a check's number.
  std::string fieldCalibration;
  // Sentinel divots of that check taken again just before (field/sentinels.hpp): kept with it in
  // the session's settings. They must be the applied check's and must have held.
  std::optional<FieldSentinels> sentinels;
  // A new session's tip calibration (tip_calibration.hpp): "" or "latest" (the newest that passed
  // for its digitizer, if any), "none", or a calibration's number. A resumed session keeps its own.
  std::string tipCalibration;
};

struct RunObserver {
  std::function<void(const Feedback&)> onFeedback;  // after the event is committed
  std::function<void(const Snapshot&)> onSnapshot;  // after every committed change
};

class CaptureRun {
 public:
  // Validates the request before anything is written (device specs, the leaf file, speed:
  // std::invalid_argument or model::InputError), opens the store (db::StoreError), creates
  // or reopens the session (SessionError when it is not open). Nothing runs yet.
  CaptureRun(RunRequest request, RunObserver observer);
  CaptureRun(const CaptureRun&) = delete;
  CaptureRun& operator=(const CaptureRun&) = delete;
  ~CaptureRun();  // shutdown("capture stopped")

  // Starts the devices (and the virtual technician) and the capture thread. A session that
  // was paused is resumed: the operator starting a run means to capture.
  void start();
  void command(const Command& c) { loop_->command(c); }
  // A held foot pedal (or key) is the stylus button.
  void setPedal(bool down) { loop_->setPedal(down); }
  [[nodiscard]] bool pedal() const { return loop_->pedal(); }
  // Asks the capture thread to end soon (Ctrl-C, a window closing). Any thread.
  void requestStop() { loop_->stop(); }
  // Blocks until the capture thread ends: complete, abandoned, a quit command or requestStop().
  void wait();
  [[nodiscard]] bool finished() const { return finished_; }
  // Ends the run: stops the capture thread, the virtual technician and the devices; when the
  // session is neither ended nor paused, records a pause saying `why` (delivered to the
  // observer like any feedback). Idempotent. Returns the session's last state.
  Snapshot shutdown(const std::string& why);

  [[nodiscard]] std::int64_t sessionId() const { return id_; }
  [[nodiscard]] const SessionSetup& setup() const { return setup_; }
  [[nodiscard]] const std::string& dbPath() const { return store_->path(); }
  [[nodiscard]] bool simulated() const { return rig_ != nullptr; }
  [[nodiscard]] double timeScale() const { return timeScale_; }
  [[nodiscard]] DeviceSet& devices() { return *devices_; }
  [[nodiscard]] std::optional<devices::StylusSample> latestStylus() const { return loop_->latestStylus(); }
  // The virtual technician's tally (zeros for real devices).
  [[nodiscard]] VirtualOperator::Stats operatorStats() const;

 private:
  void prepareSimulation(const RunRequest& request);

  RunObserver observer_;
  std::unique_ptr<db::Store> store_;
  std::int64_t id_ = 0;
  SessionSetup setup_;
  double timeScale_ = 1.0;
  PreviewDetail preview_ = PreviewDetail::Meshes;
  std::unique_ptr<CaptureSession> session_;
  std::unique_ptr<LeafCaptureLoop> loop_;
  std::unique_ptr<SimulatedRig> rig_;
  std::unique_ptr<VirtualOperator> operator_;
  std::unique_ptr<DeviceSet> devices_;
  std::thread thread_;
  std::atomic<bool> finished_{false};
  bool started_ = false, shutDown_ = false;
  std::optional<Snapshot> last_;
};

}  // namespace leafdig::acquisition
