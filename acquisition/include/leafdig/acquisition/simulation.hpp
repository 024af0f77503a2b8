// Device wiring for a capture, and the simulated station: emulators on pseudo-terminals
// driven by an operator hand and a caliper, plus a virtual operator that reads the
// station's prompts and captures a known leaf the way a technician does, mistakes included
// (a double press, a point out of order, a wrong point undone with the stylus, a caliper
// reading that bounced to zero). Shipped, not test-only: `leafdig capture --simulate` and
// `leafdig demo` run on it.
#pragma once

#include <atomic>
#include <condition_variable>
#include <memory>
#include <mutex>
#include <random>
#include <string>
#include <thread>

#include "leafdig/acquisition/capture_loop.hpp"
#include "leafdig/devices/links.hpp"
#include "leafdig/devices/sim.hpp"
#include "leafdig/model/markers.hpp"

namespace leafdig::acquisition {

// "fastrak:/dev/ttyUSB0" (also patriot, liberty, microscribe). Throws std::invalid_argument
// naming the accepted form.
[[nodiscard]] devices::DigitizerConfig parseDigitizerSpec(const std::string& spec);
// "sylvac:/dev/ttyUSB1", "mitutoyo:PORT", "uwave:PORT", "hid:0fe7:4001", "hid:/dev/hidraw3",
// "usbitn" or "usbitn:VID:PID".
[[nodiscard]] devices::CaliperConfig parseCaliperSpec(const std::string& spec);

// The two drivers of a capture, delivering into a loop.
// Thread contract: construct, start, stop, connect and disconnect from one owner thread;
// statuses() from any thread.
class DeviceSet {
 public:
  enum class Role { Digitizer, Caliper };
  DeviceSet(const std::string& digitizerSpec, const std::string& caliperSpec, CaptureLoop& loop);
  ~DeviceSet();
  void start();
  void stop();
  // The operator takes a device off line (to swap a cable, lend the caliper) and back: the
  // capture records both as device events and keeps its step.
  void disconnect(Role role);
  void connect(Role role);
  [[nodiscard]] bool connected(Role role) const;
  // Each driver's status now: state, rate, last-sample age, message and remedy.
  [[nodiscard]] devices::DeviceStatus status(Role role) const;
  [[nodiscard]] const std::string& spec(Role role) const;

 private:
  [[nodiscard]] devices::Driver& driver(Role role) const;
  CaptureLoop& loop_;
  std::string digitizerSpec_, caliperSpec_;
  std::unique_ptr<devices::Driver> digitizer_, caliper_;
  std::atomic<bool> digitizerOn_{false}, caliperOn_{false};
};

struct SimulationOptions {
  double speed = 1.0;          // time scale of the operator and the devices
  std::uint64_t seed = 1;
  std::string digitizerFaults; // FaultPlan spec for the digitizer (e.g. "unplug=0.002:0.5")
  std::string caliperFaults;
  bool mistakes = true;
  std::string linkDir = "/tmp";  // where the stable symlinks to the ptys go
};

// A FASTRAK and a Sylvac caliper on pseudo-terminals, moved by an OperatorHand.
class SimulatedRig {
 public:
  SimulatedRig(const SimulationOptions& options);
  ~SimulatedRig();
  [[nodiscard]] std::string digitizerSpec() const;  // "fastrak:<pty symlink>"
  [[nodiscard]] std::string caliperSpec() const;    // "sylvac:<pty symlink>"
  devices::sim::OperatorHand& hand() { return *hand_; }
  devices::sim::VirtualCaliper& caliper() { return *caliper_; }
  devices::sim::Emulator& digitizerEmulator() { return *digitizer_; }
  devices::sim::Emulator& caliperEmulator() { return *gauge_; }

 private:
  std::shared_ptr<devices::sim::OperatorHand> hand_;
  std::shared_ptr<devices::sim::VirtualCaliper> caliper_;
  std::unique_ptr<devices::sim::Emulator> digitizer_, gauge_;
};

class VirtualOperator {
 public:
  struct Stats {
    int gestures = 0, doubleTaps = 0, outOfOrder = 0, wrongPointsUndone = 0, bounces = 0, endRows = 0;
  };
  VirtualOperator(SimulatedRig& rig, model::MarkerSet leaf, SimulationOptions options);
  ~VirtualOperator();
  void observe(const Snapshot& s);  // the station's latest state (any thread)
  void start();
  void stop();
  [[nodiscard]] Stats stats() const;

 private:
  void run();
  void act(const Snapshot& s);
  void press(const Vec3& at, double pressS, double settleS = 0.45, double travelS = 0.6);
  void measure(double mm);
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
};

}  // namespace leafdig::acquisition
