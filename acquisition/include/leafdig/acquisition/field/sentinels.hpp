// Sentinel divots (issue 50; docs/devices.md, "Sentinel divots"): a few of a field check's divots
// taken again at the start of a capture, the jig where it lay for the check. A divot that comes
// back farther than the check's tolerance from where the check found it says the field moved since
// (metal brought near, the transmitter or the jig knocked): the check's correction no longer
// describes the field, and the capture stops before its first leaf, in words, for a new check.
// Sentinels that held are kept in the session's settings with the check they confirmed.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "leafdig/acquisition/field/field_check.hpp"

namespace leafdig::acquisition {

inline constexpr int kMinSentinels = 3, kMaxSentinels = 5;

struct SentinelDivot {
  std::string id;      // the jig's divot
  Vec3 positionMm{};   // where it was pressed now, in the digitizer's frame (before any correction)
  double movedMm = 0;  // from where the check found it
};

struct FieldSentinels {
  std::int64_t checkId = 0;
  std::string takenUtc;
  double toleranceMm = kDefaultFieldToleranceMm;  // the check's
  std::vector<SentinelDivot> divots;
  [[nodiscard]] const SentinelDivot& worst() const;  // the divot that moved most
  [[nodiscard]] bool moved() const { return worst().movedMm > toleranceMm; }
  // "4 sentinel divots of field check 3 taken again: the largest move 0.21 mm (C2), within its
  // 1.50 mm" — or, moved, what it means and what to do.
  [[nodiscard]] std::string words() const;
};

// The divots a capture takes again: `count` (3–5, at most the jig's) spread over the jig — the one
// farthest from its middle, then each the farthest from those chosen — in the jig's order, as a
// jig of their own (ids and positions kept) that a JigCapture prompts.
[[nodiscard]] model::Jig sentinelJig(const model::Jig& jig, int count);

// The presses of `sentinels` (a sentinelJig of the check's jig) against the check's own presses of
// the same divots. std::invalid_argument when a divot is not the check's or a press is missing.
[[nodiscard]] FieldSentinels compareSentinels(const FieldCalibration& check, const model::Jig& sentinels,
                                              const std::vector<JigPress>& presses, std::string takenUtc);

// As a session's settings keep them, inside its "field_calibration": {taken_utc, tolerance_mm,
// divots: [{id, position_mm, moved_mm}], max_mm, worst_point, verdict: "held"} — and read back
// checked (model::InputError naming `where` and the key; the largest move and the verdict must be
// the divots' own).
[[nodiscard]] nlohmann::json sentinelsJson(const FieldSentinels& s);
[[nodiscard]] FieldSentinels sentinelsFromJson(const nlohmann::json& doc, std::int64_t checkId,
                                               const std::string& where);

}  // namespace leafdig::acquisition
