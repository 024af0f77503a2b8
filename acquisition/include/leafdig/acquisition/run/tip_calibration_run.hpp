// A tip (pivot) calibration from start to its stored record (field/tip_calibration.hpp): the
// digitizer — a real one on its port, or the simulated FASTRAK whose stylus carries its sensor
// away from its tip (SimulationOptions::stylusTipMm), with a virtual technician pivoting it in a
// divot — delivers into a queue; the caller's thread keeps every sample taken while the button is
// held and, at the release, fits, verdicts and stores the calibration. A pivot that cannot give a
// tip (too short, hardly tilted, the tip slipped) is refused in words and the technician pivots
// again.
//
// Thread contract: construct, run() on one thread; stop() from any thread. The listener's
// callbacks run on run()'s thread (onStatus on the driver's).
#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "leafdig/acquisition/field/tip_calibration.hpp"
#include "leafdig/acquisition/live/input_queue.hpp"
#include "leafdig/acquisition/sim/simulation.hpp"

namespace leafdig::acquisition {

struct TipCalibrationRequest {
  std::string db;       // the station file; empty: the station's default
  std::string station;  // empty: thisStation()
  std::string who;      // the technician
  double toleranceMm = kDefaultTipToleranceMm;
  std::string digitizer;  // "fastrak:/dev/ttyUSB0" (no tip= option: the sensor as it reports); ignored when simulated
  bool simulated = false;
  SimulationOptions simulation;
  Vec3 divotMm{250.0, 0.0, -50.0};  // a simulation: where the divot is, in the transmitter's frame
  double pivotDeg = 40.0;           // a simulation: how far the technician tilts the stylus
  double pivotSeconds = 6.0;        // and for how long (of the simulation's time)
};

struct TipCalibrationListener {
  std::function<void(const std::string&)> onPrompt;   // what to do now
  std::function<void(const std::string&)> onRefused;  // a pivot that gave no tip, in words
  std::function<void(const devices::DeviceStatus&)> onStatus;
};

class TipCalibrationRun {
 public:
  // Opens the store (db::StoreError) and checks the request (std::invalid_argument: a digitizer
  // spec that does not parse or carries a tip already, no technician named, a tolerance out of
  // range). Nothing runs yet.
  TipCalibrationRun(TipCalibrationRequest request, TipCalibrationListener listener);
  TipCalibrationRun(const TipCalibrationRun&) = delete;
  TipCalibrationRun& operator=(const TipCalibrationRun&) = delete;
  ~TipCalibrationRun();

  void stop();  // run() returns soon, nothing stored
  // Until a pivot gives a tip (then it is verdicted, stored and returned) or stop().
  std::optional<TipCalibration> run();

 private:
  class Technician;

  TipCalibrationRequest request_;
  TipCalibrationListener listener_;
  std::unique_ptr<db::Store> store_;
  InputQueue<int> inputs_;
  std::unique_ptr<SimulatedRig> rig_;
  std::unique_ptr<Technician> technician_;
  std::unique_ptr<devices::Driver> digitizer_;
};

}  // namespace leafdig::acquisition
