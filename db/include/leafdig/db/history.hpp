// A session's review history (issue 49): every curator's decision, reopening and correction in the order
// they were written, with who, when, why and — for a correction — the item and its value
// before and after. One projection of the events, the same for a station's file and the lab
// server; `sessions show` and `sessions list --json`, Python's `Store.history` and the exports
// all show this one.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "leafdig/db/event_store.hpp"

namespace leafdig::db {

struct ReviewEntry {
  std::int64_t seq = 0;
  std::string utc;
  std::string action;  // "approved", "rejected" (decisions), "reopened" or "corrected"
  std::string who, why;
  std::string reopens;  // a reopening's: the decision it reopened (approved, rejected)
  // A correction's item (its `what` as the events name it: "marker", "node3.marker",
  // "landmark", …) and its value before and after: a position or a reading.
  std::string what;
  std::optional<int> row, col;
  std::optional<std::array<double, 3>> fromMm, toMm;
  std::optional<double> fromValueMm, toValueMm;
  // How far a corrected point moved, in mm (in the frame it was digitized in).
  [[nodiscard]] std::optional<double> movedMm() const;
};

// The decisions and corrections among `events` (a session's, in order). Events that do not
// read as one (they were checked when read: none should) are left out.
[[nodiscard]] std::vector<ReviewEntry> reviewHistory(const std::vector<Event>& events);
// As JSON (what `sessions show --json`, `sessions list --json` and Python give): an entry is
// {"seq", "utc", "action", "who", "why"}, a reopening's also {"reopens"}, a correction's also {"what", "row", "col",
// "from", "to"} (each {"position_mm": [x, y, z]} or {"value_mm": v}) and, for a point, "moved_mm".
[[nodiscard]] std::string reviewEntryJson(const ReviewEntry& entry);
[[nodiscard]] std::string reviewHistoryJson(const std::vector<ReviewEntry>& history);
// The decision that stands at the end of a history (approved or rejected), or none: none when a
// reopening came after the last one.
[[nodiscard]] std::optional<ReviewEntry> lastDecision(const std::vector<ReviewEntry>& history);

}  // namespace leafdig::db
