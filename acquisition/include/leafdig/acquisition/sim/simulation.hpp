// The simulated station: emulators on pseudo-terminals
// driven by an operator hand and a caliper, plus a virtual operator that reads the
// station's prompts and captures a known leaf the way a technician does, mistakes included
// (a double press, a point out of order, a wrong point undone with the stylus, a caliper
// reading that bounced to zero). Shipped, not test-only: `leafdig capture --simulate` and
// `leafdig demo` run on it.
#pragma once

#include <Eigen/Geometry>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <memory>
#include <mutex>
#include <random>
#include <string>
#include <thread>

#include "leafdig/acquisition/live/leaf_loop.hpp"
#include "leafdig/devices/sim/field_distortion.hpp"
#include "leafdig/devices/sim/sim.hpp"
#include "leafdig/model/leaf/markers.hpp"

namespace leafdig::acquisition {

struct SimulationOptions {
  double speed = 1.0;  // time scale of the operator and the devices
  std::uint64_t seed = 1;
  std::string digitizerFaults;  // FaultPlan spec for the digitizer (e.g. "unplug=0.002:0.5")
  std::string caliperFaults;
  bool mistakes = true;
  double stylusNoiseMm = 0.3;    // Gaussian noise per axis of the stylus tip at rest
  std::string linkDir = "/tmp";  // where the stable symlinks to the ptys go
  // After this many accepted points the virtual technician moves the transmitter to a new
  // random pose (seeded) and takes the landmarks again — a plant's, or a leaf's three board
  // points (0: never).
  int relocateSourceAfter = 0;
  // A reference receiver on the pot (FASTRAK receiver 2): the stylus is read in its frame
  // (docs/devices.md, "A reference receiver"). With it, the pot turns by potTurnDeg about the
  // vertical through potCentreMm, smoothly, as the technician goes up the plant (aimPot).
  bool referenceReceiver = false;
  double potTurnDeg = 0;
  Vec3 potCentreMm{};
  // The transmitter's field bent as by metal nearby (issue 50): every receiver reports through
  // it, in the transmitter's frame (none: a clean field).
  std::shared_ptr<const devices::sim::FieldDistortion> distortion;
  // The simulated stylus' sensor is this far from its tip, in the sensor's frame (issue 50; 0:
  // the stylus reports its tip, as a FASTRAK stylus does with its factory offset applied). A
  // tip calibration (leafdig field tip) finds it; a capture without one is bent by it
  // (devices::sim::StylusSensor: the hand tilts the stylus towards where it presses).
  Vec3 stylusTipMm{0, 0, 0};
  // The tip the capture applies (its session's tip calibration): what the station shows of a
  // press, which the virtual technician judges by, is the sensor moved by it (0: none applied).
  Vec3 tipAppliedMm{0, 0, 0};
};

class TransmitterMotion;
class PotTurn;

// Where a virtual technician moves the transmitter (SimulatedRig::moveTransmitter's pose): up
// to 150 mm aside, 40 mm up or down, 40° about the vertical and 6° of tilt, drawn from `rng`.
[[nodiscard]] Eigen::Isometry3d randomTransmitterMove(std::mt19937_64& rng);

// A FASTRAK and a Sylvac caliper on pseudo-terminals, moved by an OperatorHand.
class SimulatedRig {
 public:
  SimulatedRig(const SimulationOptions& options);
  ~SimulatedRig();
  [[nodiscard]] std::string digitizerSpec() const;  // "fastrak:<pty symlink>[,reference=2]"
  [[nodiscard]] std::string caliperSpec() const;    // "sylvac:<pty symlink>"
  // The simulated FASTRAK's record rate (120 Hz times the speed, at most 960 Hz).
  [[nodiscard]] double digitizerRateHz() const { return digitizerRateHz_; }
  devices::sim::OperatorHand& hand() { return *hand_; }
  devices::sim::VirtualCaliper& caliper() { return *caliper_; }
  devices::sim::Emulator& digitizerEmulator() { return *digitizer_; }
  devices::sim::Emulator& caliperEmulator() { return *gauge_; }
  // The transmitter moved: from now on the digitizer reports every point of the first
  // transmitter position's frame as `fromFirst` maps it (thread-safe).
  void moveTransmitter(const Eigen::Isometry3d& fromFirst);
  // The pot (with the plant and the reference receiver on it) turns towards `deg` about the
  // vertical, at most 3° a second of the simulation's time (no reference receiver: nothing).
  void aimPot(double deg);
  // Where the station sees a point of the simulated leaf or plant (as the file gives it, on the
  // pot before it turns): itself, or with a reference receiver that point in the receiver's
  // frame — fixed, however the pot turns. fromStation is the inverse (where to press).
  [[nodiscard]] Vec3 toStation(const Vec3& truthMm) const;
  // Where the station sees a point the hand touches at `truthMm` (as toStation), through the
  // bent field when there is one (SimulationOptions::distortion), and moved by the stylus' sensor
  // offset the capture does not take away (stylusTipMm less tipAppliedMm): what a technician sees
  // on the screen and judges a press by — nobody can tell a field's bend from the leaf.
  [[nodiscard]] Vec3 seen(const Vec3& truthMm) const;
  [[nodiscard]] Vec3 fromStation(const Vec3& stationMm) const;

 private:
  std::shared_ptr<devices::sim::OperatorHand> hand_;
  std::shared_ptr<TransmitterMotion> transmitter_, referenceTransmitter_;
  std::shared_ptr<PotTurn> pot_;
  bool reference_ = false;
  std::shared_ptr<const devices::sim::FieldDistortion> distortion_;
  std::shared_ptr<const devices::sim::StylusSensor> sensor_;  // a stylus whose sensor is off its tip
  Vec3 tipAppliedMm_{};
  Eigen::Isometry3d receiver_ = Eigen::Isometry3d::Identity();  // the reference receiver before the pot turns
  std::shared_ptr<devices::sim::VirtualCaliper> caliper_;
  std::unique_ptr<devices::sim::Emulator> digitizer_, gauge_;
  double digitizerRateHz_ = 120.0;
};

// How a virtual technician waits for the station's answer before acting again: until the hand
// is still, its release has had 10 ms to reach the station and the station's state has moved
// on — or, when no answer comes (a press the digitizer lost), for as long as a person would: at
// least 2.5 s of the simulation's time and four times the slowest answer seen so far, so a slow
// station (a loaded PC, a sanitizer) is waited for instead of answered twice — a second
// caliper reading would land on the next step, be undone, and so on.
class AnswerWait {
 public:
  using Clock = std::chrono::steady_clock;
  explicit AnswerWait(double speed) : base_(2.5 / speed + 0.4) {}
  // True when it is time to act; `version` is the station's state now. The caller acts then.
  [[nodiscard]] bool due(std::uint64_t version, bool handIdle);

 private:
  std::chrono::duration<double> base_, slowestAnswer_{0};
  std::uint64_t versionAtAction_ = ~0ULL;
  bool awaiting_ = false, idle_ = false;
  Clock::time_point idleSince_{};
};

class VirtualOperator {
 public:
  struct Stats {
    int gestures = 0, doubleTaps = 0, outOfOrder = 0, wrongPointsUndone = 0, bounces = 0, endRows = 0;
  };
  VirtualOperator(SimulatedRig& rig, model::MarkerSet leaf, const SimulationOptions& options);
  ~VirtualOperator();
  // How the technician says what a stylus cannot: move the transmitter, undo a move found
  // half-done after a restart (set before start()).
  void setCommands(std::function<void(const Command&)> send) { send_ = std::move(send); }
  // A restarted simulation whose session already fitted a move: the rig was put back where
  // the transmitter was; the technician does not move it again.
  void transmitterMovedBefore() { moved_ = true; }
  void observe(const Snapshot& s);  // the station's latest state (any thread)
  void start();
  void stop();
  [[nodiscard]] Stats stats() const;

 private:
  void run();
  void act(const Snapshot& s);
  void press(const Vec3& at, double pressS, double settleS = 0.45, double travelS = 0.6);
  void measure(double mm);
  bool relocate(const Snapshot& s);  // true when it acted
  [[nodiscard]] bool wrongPoint(const Item& i) const;
  [[nodiscard]] Vec3 truth(What w, int row, int col) const;
  [[nodiscard]] double truthThickness(What w, int row, int col) const;

  SimulatedRig& rig_;
  model::MarkerSet leaf_;
  SimulationOptions options_;
  std::mt19937_64 rng_;
  mutable std::mutex mutex_;
  std::condition_variable cv_;
  std::optional<Snapshot> latest_;
  std::uint64_t actedOn_ = 0;
  std::thread thread_;
  std::atomic<bool> stop_{false};
  Stats stats_;
  int stylusAccepted_ = 0, thicknessSteps_ = 0;
  bool didDoubleTap_ = false, didOutOfOrder_ = false, didWrongPoint_ = false, didBounce_ = false;
  std::function<void(const Command&)> send_;
  bool moved_ = false;  // the transmitter was moved in this session (by this run or before it)
  bool started_ = false, resumedInMove_ = false;  // the first state seen was a move half-done
  int movedFor_ = 0;                              // the move the rig was moved for (0: none)
};

}  // namespace leafdig::acquisition
