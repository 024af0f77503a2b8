// What a capture applies of a field check (issue 50; docs/devices.md, "Captures through a checked
// field"): `--field-calibration ID|latest|none` names a check of the station file; the session
// keeps the check's id, chain hash, verdict, held-out error and the correction itself in its
// settings (covered by its genesis hash, and carried to the lab server with it), so a session
// reads the same wherever it goes. Every stylus sample is corrected before the engine sees it;
// the digitizer's raw record stays in the event; the area interval and a plant's node tolerance
// widen by the held-out error.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "leafdig/acquisition/field/field_check.hpp"
#include "leafdig/acquisition/field/sentinels.hpp"

namespace leafdig::acquisition {

struct FieldApplied {
  std::int64_t id = 0;  // the check
  std::string hash, createdUtc, verdict;
  double holdoutRmsMm = 0, holdoutMaxMm = 0;
  model::FieldCorrection correction;
  // The check's divots taken again at the session's start, when they were (sentinels.hpp): they
  // held, or the session would not have begun.
  std::optional<FieldSentinels> sentinels;
  [[nodiscard]] Vec3 apply(const Vec3& p) const;
  // "field check 3 of 2026-11-29T05:25Z: polynomial-2, 0.42 mm RMS on divots it did not see"
  [[nodiscard]] std::string words() const;
  // Why a capture through this check takes no move of the transmitter: the correction is the
  // field the jig found around the transmitter where it stood; moved, the metal is elsewhere in
  // its frame and the correction would bend good points. The leaf's and the plant's sessions
  // refuse the move with these words (a `rejected` event), before the engine hears of it.
  [[nodiscard]] std::string moveRefusal() const;
};

// A check is trusted for captures this long after it was made; an older one is named in the
// capture's banner (the check of the day). A setting: the station's `field/max_check_age_hours`,
// the CLI's `--field-check-max-age-hours` (from 1 h to a year).
inline constexpr double kFieldCheckMaxAgeHours = 24.0;
inline constexpr double kFieldCheckMaxAgeLimitHours = 8760.0;

// "none" or "": nothing; "latest": the newest check; a number: that check. Refused in words
// (std::invalid_argument): no check in the file, no check of that number, a check that failed
// (the field is beyond correcting: move the metal, check again). A check that does not read
// (model::InputError) or a chain that does not verify (db::StoreError) is refused as such.
[[nodiscard]] std::optional<FieldApplied> resolveFieldCalibration(const db::Store& store, const std::string& which);
// The same, with the check itself as read (its jig and presses: what sentinel divots are taken
// against), from the one reading of the file.
struct ResolvedFieldCheck {
  FieldCalibration check;
  FieldApplied applied;
};
[[nodiscard]] std::optional<ResolvedFieldCheck> resolveFieldCheck(const db::Store& store, const std::string& which);

// Sentinels taken before a new session, kept with the check the session applies: refused
// (std::invalid_argument, in words) when they are another check's, when the session applies none,
// or when they moved. Nothing to do without sentinels.
void attachSentinels(std::optional<FieldApplied>& applied, const std::optional<FieldSentinels>& sentinels);

// As a session's settings keep it ("field_calibration": {id, hash, created_utc, verdict,
// holdout_rms_mm, holdout_max_mm, correction, and sentinels when they were taken}) and read back, checked
// (model::InputError naming `source` and the key).
[[nodiscard]] nlohmann::json fieldAppliedJson(const FieldApplied& f);
[[nodiscard]] std::optional<FieldApplied> fieldAppliedFromSettings(const std::string& settingsJson,
                                                                   const std::string& source);

// What a capture's banner says of its field, in words: corrected by which check (and when it is
// older than `maxAgeHours`, so); or not corrected, and whether the file holds a check younger than
// that; or that the file's checks do not verify.
[[nodiscard]] std::string fieldBanner(const db::Store& store, const std::optional<FieldApplied>& applied,
                                      double maxAgeHours = kFieldCheckMaxAgeHours);

// Hours since a check was made (UTC ISO 8601 with milliseconds, as the store writes it); 0 for a
// time that does not read.
[[nodiscard]] double fieldCheckAgeHours(const std::string& createdUtc);

}  // namespace leafdig::acquisition
