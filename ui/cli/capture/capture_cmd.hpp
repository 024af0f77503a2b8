// leafdig capture, leafdig sessions resume, leafdig demo (the other `sessions` commands: sessions_cmd).
#pragma once

#include <CLI/CLI.hpp>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace leafdig::cli {

struct CaptureOptions {
  std::string db;       // a station's SQLite file
  std::string station;  // --station: this station's id (default: settings file, else host name)
  bool json = false;
  // capture
  std::string project = "default", plant = "plant-1", digitizer, caliper, mode = "standard", order = "sequential",
              operatorName = "technician";
  int leafPosition = 1;
  std::string leafType;
  std::string serration;               // the leaf's declared margin teeth ("" : not declared)
  std::optional<double> toothDepthMm;  // their depth
  bool board = false;
  bool referenceReceiver = false;               // receiver 2 on the leaf's board: the digitizer spec's ",reference=2"
  double potTurnDeg = 0;                        // simulation: the board turns by this under the reference receiver
  std::optional<double> relocationToleranceMm;  // --relocation-tolerance: a new session's
  int relocateSourceAfter = 0;                  // simulation: the transmitter moves after this many points (0: never)
  // simulation
  bool simulate = false, noMistakes = false;
  std::string markers, faults, caliperFaults;
  std::string synth;                            // a synthetic leaf (synth_cmd.hpp: parseSynthSpec)
  std::optional<double> stylusNoiseMm;          // the simulated stylus's noise per axis
  std::string distortion;                       // the simulated field's leafdig.field-distortion/1 file (issue 50)
  std::string fieldCalibration;                 // --field-calibration ID|latest|none (issue 50)
  std::string tipCalibration;                   // --tip-calibration ID|latest|none (issue 50)
  std::string simTip;                           // --sim-tip x,y,z: the simulated stylus' sensor offset
  std::optional<double> fieldCheckMaxAgeHours;  // --field-check-max-age-hours (capture_console.hpp)
  std::optional<int> sentinels;                 // --sentinels N (capture_console.hpp)
  std::string jigPose = "200,-620,0,90";        // simulation: where the jig lies for the sentinels
  std::uint64_t seed = 1;
  std::optional<double> speed;  // not given: 1 for a new capture, a resumed one's own, 8 for the demo
  double giveUpAfterS = 180;    // a simulated technician that gets nowhere this long is stopped
  // sessions resume
  std::int64_t id = 0;
  // demo
  std::string out, samples;
  int synthLeaves = 2;
};

class CommandTable;
// Registers `capture`, `demo` and `sessions` (sessions_cmd.hpp) with `sessions resume`.
void addCaptureCommands(CLI::App& app, CommandTable& table);

}  // namespace leafdig::cli
