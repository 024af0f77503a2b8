// The console the capture commands share — a leaf's (`capture`, `sessions resume`, `demo`), a
// plant's (`plant capture`) and `sessions` that shows what they captured: the words for an
// item and a step, where a station's file is by default, the simulated technician's give-up
// watch, and the relocation tolerance's check.
#pragma once

#include <chrono>
#include <cstdint>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "leafdig/acquisition/protocol/engine.hpp"
#include "leafdig/devices/sim/field_distortion.hpp"

namespace leafdig::cli {

// --db as given, or the station's default file.
[[nodiscard]] std::string stationDbPath(const std::string& db);
// A 1-based row or column, or null where none applies.
[[nodiscard]] nlohmann::json nullable(int v);
// A step as the JSON-lines contract says it: what, row, col, prompt.
[[nodiscard]] nlohmann::json stepJson(const acquisition::Step& s, const std::string& prompt);
// An item in words: "row 3 point 2 (1.0, 2.0, 3.0) mm [flag]", "row 2 midrib_thickness 0.412 mm".
[[nodiscard]] std::string describe(const acquisition::Item& i);

// --distortion FILE of a simulated capture (issue 50): the field, read and checked; none when
// no file is given. A bad file is refused in words (exit 2) before anything is captured.
inline constexpr const char* kDistortionHelp =
    "Simulation: the digitizer's field bent as by metal nearby, from a leafdig.field-distortion/1 file "
    "(data/fields/steel-bench.field.json; docs/devices.md, \"The field\")";
[[nodiscard]] std::shared_ptr<const devices::sim::FieldDistortion> distortionOf(const std::string& path);
// --field-calibration of a new capture (issue 50; docs/devices.md, "Captures through a checked field").
inline constexpr const char* kFieldCalibrationHelp =
    "The field check whose correction every stylus sample goes through: a check's number (leafdig field list), "
    "latest, or none (default)";
// --field-check-max-age-hours: how old a check may be before the banner says the field was not
// checked today — the flag, else the station's settings file (`[field] max_check_age_hours`,
// the station's dialog writes it), else 24 h. A value that is not a number of hours from 1 to
// 8760 is refused in words, naming where it came from.
inline constexpr const char* kFieldCheckMaxAgeHelp =
    "How old a field check may be before the banner asks for a new one, hours (default: the station's settings "
    "file, [field] max_check_age_hours, else 24)";
[[nodiscard]] double fieldCheckMaxAge(const std::optional<double>& flag);
// --sentinels N: how many of the check's divots a capture through a field check takes again
// before its first leaf (acquisition/field/sentinels.hpp) — the flag, else the station's settings
// file (`[field] sentinels`), else 0 (none). 0 or 3 to 5; anything else is refused in words.
inline constexpr const char* kSentinelsHelp =
    "Sentinel divots: take this many of the field check's divots again before the first leaf, the jig where it "
    "lay for the check; a divot moved beyond the check's tolerance stops the capture (0: none, or 3 to 5; "
    "default: the station's settings file, [field] sentinels, else 0)";
[[nodiscard]] int sentinelCount(const std::optional<int>& flag);
// --sim-tip x,y,z of a simulated digitizer (issue 50): its stylus' sensor that far from its tip,
// in the sensor's frame (mm, each within 500); "" is none (the stylus reports its tip).
inline constexpr const char* kSimTipHelp =
    "Simulation: the stylus' sensor is this far from its tip, x,y,z mm in the sensor's frame (default: none, the "
    "stylus reports its tip; docs/devices.md, \"The stylus tip\")";
[[nodiscard]] devices::Vec3 simTipOf(const std::string& text);
// Three numbers "x,y,z" in mm, each within limitMm: model::InputError naming `option` otherwise.
[[nodiscard]] devices::Vec3 vec3Option(const std::string& text, const std::string& option, double limitMm,
                                       const char* example);
// --tip-calibration of a new capture: the stylus' tip calibration every sample goes through.
inline constexpr const char* kTipCalibrationHelp =
    "The tip calibration of the digitizer's stylus every sample goes through: a calibration's number (leafdig "
    "field tips), latest (default: the newest that passed for this digitizer, if any) or none";

// How far a simulated capture got, for --give-up-after: anything the station took (but a device
// message) is progress, a refusal is not, and a pause is no lack of it. Thread-safe: the
// capture's thread tells it, a watcher asks it.
class GiveUpWatch {
 public:
  explicit GiveUpWatch(double seconds);
  void progressed();
  void refused(const std::string& reason);
  void at(const std::string& prompt, bool paused);  // the station's state now
  // The words to print once the technician got nowhere for the limit; empty before.
  [[nodiscard]] std::string overdue(const std::string& capture, std::int64_t id, const std::string& db) const;

 private:
  double seconds_;
  mutable std::mutex mutex_;
  std::chrono::steady_clock::time_point lastProgress_;
  std::string where_, lastRefusal_;
  int refusedSince_ = 0;
  bool paused_ = false;
};

// --relocation-tolerance (leaf and plant capture): 0.1–10 mm, given when a capture begins (a
// resumed one keeps its session's). Throws std::invalid_argument in words.
void checkRelocationTolerance(const std::optional<double>& mm, bool resuming);

}  // namespace leafdig::cli
