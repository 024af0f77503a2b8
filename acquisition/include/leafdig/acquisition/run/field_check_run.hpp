// A field check from start to its stored record (field_check.hpp): the digitizer — a real one on
// its port, or the simulated FASTRAK in a bent field (SimulationOptions::distortion) with a
// virtual technician touching a jig placed at `jigPose` — delivers into a queue; the caller's
// thread feeds a JigCapture and, once every divot is taken, fits, verdicts and stores the check.
//
// Thread contract: construct, run() on one thread; undo() and stop() from any thread. The
// listener's callbacks run on run()'s thread (onStatus on the driver's).
#pragma once

#include <Eigen/Geometry>
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "leafdig/acquisition/field/field_check.hpp"
#include "leafdig/acquisition/field/sentinels.hpp"
#include "leafdig/acquisition/live/input_queue.hpp"
#include "leafdig/acquisition/sim/simulation.hpp"

namespace leafdig::acquisition {

struct FieldCheckRequest {
  std::string db;       // the station file; empty: the station's default
  std::string station;  // empty: thisStation()
  std::string who;      // the technician
  model::Jig jig;
  double toleranceMm = kDefaultFieldToleranceMm;
  std::string digitizer;  // "fastrak:/dev/ttyUSB0"; ignored when simulated
  bool simulated = false;
  SimulationOptions simulation;
  // Where the simulated jig lies in the transmitter's frame (its own frame's origin and turn).
  Eigen::Isometry3d jigPose = Eigen::Isometry3d::Identity();
  // The stylus' tip calibration the divots are touched through (tip_calibration.hpp): "" or
  // "latest" (the digitizer's newest that passed, if any), "none", or a calibration's number.
  // The check keeps which applied.
  std::string tipCalibration;
};

struct FieldCheckListener {
  std::function<void(const std::string&)> onPrompt;  // the divot to touch next
  std::function<void(const JigCapture::Decision&)> onDecision;
  std::function<void(const devices::DeviceStatus&)> onStatus;
};

// The jig's pose in a simulation from "x,y,z,yaw_deg" (mm, degrees about the vertical):
// std::invalid_argument in words otherwise (each within ±2000 mm, yaw within ±360°).
[[nodiscard]] Eigen::Isometry3d parseJigPose(const std::string& text);

class FieldCheckRun {
 public:
  // Opens the store (db::StoreError) and checks the request (std::invalid_argument: a digitizer
  // spec that does not parse, no technician named). Nothing runs yet.
  FieldCheckRun(FieldCheckRequest request, FieldCheckListener listener);
  FieldCheckRun(const FieldCheckRun&) = delete;
  FieldCheckRun& operator=(const FieldCheckRun&) = delete;
  ~FieldCheckRun();

  void undo();  // takes the last divot back (as a long press)
  void stop();  // run() returns soon, nothing stored
  // Until every divot is taken (then the check is fitted, stored and returned) or stop().
  std::optional<FieldCalibration> run();
  // Sentinel divots before a capture (sentinels.hpp): the request's jig is sentinelJig(check.jig,
  // n); until every one is taken (then they are compared with the check's presses and returned —
  // nothing is stored: a session keeps them) or stop(). The divots are touched through the tip
  // calibration the check's were (the request's own is not used), so like is compared with like.
  std::optional<FieldSentinels> runSentinels(const FieldCalibration& check);
  [[nodiscard]] const db::Store& store() const { return *store_; }

 private:
  enum class FieldCommand { Undo };
  bool takeDivots();  // true when every divot of the request's jig is taken
  class Technician;

  FieldCheckRequest request_;
  FieldCheckListener listener_;
  std::unique_ptr<db::Store> store_;
  InputQueue<FieldCommand> inputs_;
  JigCapture capture_;
  std::unique_ptr<SimulatedRig> rig_;
  std::unique_ptr<Technician> technician_;
  std::unique_ptr<devices::Driver> digitizer_;
  std::string spec_;  // the digitizer as opened (a simulation's pseudo-terminal)
  std::optional<TipApplied> tip_;
};

}  // namespace leafdig::acquisition
