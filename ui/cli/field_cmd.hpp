// leafdig field model|check|list|show: the digitizer's magnetic field (issue 50; docs/devices.md,
// "The field" and "Checking the field").
#pragma once

#include <CLI/CLI.hpp>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>

#include "leafdig/acquisition/field/sentinels.hpp"

namespace leafdig::cli {

class CommandTable;
// Registers `field model`, `field check`, `field list` and `field show`.
void addFieldCommands(CLI::App& app, CommandTable& table);

// `capture` and `plant capture` through a field check with --sentinels N: before the session is
// made, N of the check's divots are taken again on the terminal (prompts, u undo, q or Ctrl-C
// stop; through the tip calibration the check went through) with the capture's own digitizer — or, simulated, the
// simulated FASTRAK in its field touching the jig at --jig-pose.
struct SentinelAsk {
  std::string db, station, who, fieldCalibration, digitizer, distortion, simTip;
  std::string jigPose = "200,-620,0,90";
  std::optional<int> count;  // --sentinels; not given: the station's setting, for a capture through a check
  bool simulate = false, json = false;
  double speed = 1;
  std::uint64_t seed = 1;
};
struct SentinelOutcome {
  std::optional<acquisition::FieldSentinels> sentinels;  // taken and held
  std::string fieldCalibration;  // the check they confirmed, by number: the capture applies that one
  int exitCode = 0;              // not 0: the capture does not begin (3: they moved; 1 or 130: stopped)
};
// Nothing is taken (and the outcome says go on as asked) when the count is 0 or no check applies;
// --sentinels without a check is refused (model::InputError), a setting without one is moot.
[[nodiscard]] SentinelOutcome takeSentinels(const SentinelAsk& ask);
// The ask from a capture's options (a leaf's or a plant's: the same names), its digitizer as the
// capture opens it and its simulation's speed.
template <class Options>
[[nodiscard]] SentinelAsk sentinelAskOf(const Options& o, std::string digitizer, double speed) {
  return {.db = o.db,
          .station = o.station,
          .who = o.operatorName,
          .fieldCalibration = o.fieldCalibration,
          .digitizer = std::move(digitizer),
          .distortion = o.distortion,
          .simTip = o.simTip,
          .jigPose = o.jigPose,
          .count = o.sentinels,
          .simulate = o.simulate,
          .json = o.json,
          .speed = speed,
          .seed = o.seed};
}

// docs/accuracy.md's section on captures through a bent field: the field study's leaves with its
// defaults (`leafdig synth study` appends it to the accuracy report).
[[nodiscard]] std::string fieldAccuracySection();

}  // namespace leafdig::cli
