// What a valid event is, without its session (docs/schema.md, "What an event may hold"): the
// station's reader applies it to every event it reads, takes in or replays, and the lab
// server's schema 10 holds the same rules in SQL (db/src/lab_schema.hpp). The cases both run
// are in tests/data/event_cases.json; what an event may name in its session (an undo of an
// item that is there, a correction of the item it carries) is the replay's
// (acquisition/session.cpp, plant_session.cpp) and the server's event_state_problem.
#pragma once

#include <optional>
#include <string>

namespace leafdig::db {

inline constexpr std::size_t kMaxPayloadBytes = 65536;     // an event's payload_json
inline constexpr std::size_t kMaxRawBytes = 262144;        // an event's raw text
inline constexpr std::size_t kMaxSettingsBytes = 4194304;  // a session's settings_json
inline constexpr double kMaxJsonMagnitude = 1e15;          // any number in a payload or settings (ns durations fit)
inline constexpr double kMaxItemCoordinateMm = 10'000.0;   // an item's position (model::kMaxCoordinateMm)
inline constexpr double kMaxItemValueMm = 100.0;           // an item's reading (model::kMaxThicknessMm)

// What is wrong with an event's payload and raw text for its kind, or nothing: sizes, a JSON
// object, every number finite and within ±kMaxJsonMagnitude, no key leafdig does not write in
// an item, a status or a correction, an item's position and value within range, and an undo,
// retake or correction that names an event (seq) and carries the (what, row, col) it names.
[[nodiscard]] std::optional<std::string> eventProblem(const std::string& kind, const std::string& payloadJson,
                                                      const std::string& raw);
// The same for a session's settings: a JSON object of at most kMaxSettingsBytes, every number
// within range.
[[nodiscard]] std::optional<std::string> settingsProblem(const std::string& settingsJson);

}  // namespace leafdig::db
