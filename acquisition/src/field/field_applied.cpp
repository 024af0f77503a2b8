#include "leafdig/acquisition/field/field_applied.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <stdexcept>

#include "field/numbers.hpp"
#include "field/stored_record.hpp"
#include "leafdig/model/errors.hpp"

namespace leafdig::acquisition {

namespace {
using nlohmann::json;
}

Vec3 FieldApplied::apply(const Vec3& p) const {
  const Eigen::Vector3d c = correction.apply({p[0], p[1], p[2]});
  return {c.x(), c.y(), c.z()};
}

std::string FieldApplied::words() const {
  char b[64];
  std::snprintf(b, sizeof b, "%.2f mm RMS", holdoutRmsMm);
  return "field check " + std::to_string(id) + " of " + createdUtc + ": " + correction.name() + ", " + b +
         " on divots it did not see";
}

std::string FieldApplied::moveRefusal() const {
  return "the transmitter stays where field check " + std::to_string(id) +
         " found the field: its correction holds only there, and moved it would bend good points. Finish "
         "without moving it, or end this capture and check the field at the new place (leafdig field check), "
         "or capture with --field-calibration none";
}

std::optional<ResolvedFieldCheck> resolveFieldCheck(const db::Store& store, const std::string& which) {
  if (which.empty() || which == "none") return std::nullopt;
  std::int64_t id = 0;
  if (which != "latest") id = detail::calibrationNumber(which, "--field-calibration", "check", "leafdig field list");
  // The rows read once (their chain verified), every check trusted as every reader trusts one.
  const std::vector<db::FieldCheckRow> rows = store.fieldChecks();
  const db::FieldCheckRow* row = nullptr;
  std::optional<FieldCalibration> chosen;
  for (const db::FieldCheckRow& r : rows) {
    FieldCalibration c = readFieldCheck(r);
    if (id == 0 || r.id == id) {
      row = &r;
      chosen = std::move(c);
    }
  }
  if (!chosen)
    throw std::invalid_argument(
        id == 0 ? "no field check in " + store.path() +
                      ": run 'leafdig field check' first, or capture with --field-calibration none"
                : "no field check " + std::to_string(id) + " in " + store.path() + ": 'leafdig field list' shows them");
  if (chosen->result.verdict == "fail")
    throw std::invalid_argument("field check " + std::to_string(chosen->id) +
                                " failed: the field is beyond correcting (move the metal away, check again), or "
                                "capture with --field-calibration none");
  FieldApplied f;
  f.id = chosen->id;
  f.hash = row->hash;
  f.createdUtc = chosen->createdUtc;
  f.verdict = chosen->result.verdict;
  f.holdoutRmsMm = chosen->result.correction.holdoutRmsMm;
  f.holdoutMaxMm = chosen->result.correction.holdoutMaxMm;
  f.correction = chosen->result.correction.correction;
  return ResolvedFieldCheck{std::move(*chosen), std::move(f)};
}

std::optional<FieldApplied> resolveFieldCalibration(const db::Store& store, const std::string& which) {
  auto resolved = resolveFieldCheck(store, which);
  if (!resolved) return std::nullopt;
  return std::move(resolved->applied);
}

void attachSentinels(std::optional<FieldApplied>& applied, const std::optional<FieldSentinels>& sentinels) {
  if (!sentinels) return;
  if (!applied || applied->id != sentinels->checkId)
    throw std::invalid_argument("the sentinel divots confirm field check " + std::to_string(sentinels->checkId) +
                                ", and this capture applies " +
                                (applied ? "field check " + std::to_string(applied->id) : std::string("none")) +
                                ": take them again through the check the capture applies");
  if (sentinels->moved()) throw std::invalid_argument(sentinels->words());
  applied->sentinels = sentinels;
}

json fieldAppliedJson(const FieldApplied& f) {
  json j = {{"id", f.id},
            {"hash", f.hash},
            {"created_utc", f.createdUtc},
            {"verdict", f.verdict},
            {"holdout_rms_mm", f.holdoutRmsMm},
            {"holdout_max_mm", f.holdoutMaxMm},
            {"correction", json::parse(model::encodeCorrection(f.correction))}};
  if (f.sentinels) j["sentinels"] = sentinelsJson(*f.sentinels);
  return j;
}

std::optional<FieldApplied> fieldAppliedFromSettings(const std::string& settingsJson, const std::string& source) {
  const detail::SettingsEntry e(settingsJson, source, "field_calibration");
  if (!e.present()) return std::nullopt;
  FieldApplied f;
  f.id = e.id("a check's number");
  f.hash = e.text("hash", 100);
  f.createdUtc = e.text("created_utc", 100);
  f.verdict = e.text("verdict", 100);
  if (f.verdict != "pass" && f.verdict != "correctable") e.fail("verdict is not pass or correctable");
  f.holdoutRmsMm = e.millimetres("holdout_rms_mm", 100);
  f.holdoutMaxMm = e.millimetres("holdout_max_mm", 100);
  if (!e.doc().contains("correction")) e.fail("the correction is missing");
  f.correction = model::parseCorrection(e.doc()["correction"].dump(), e.where() + ".correction");
  if (e.doc().contains("sentinels")) {
    f.sentinels = sentinelsFromJson(e.doc()["sentinels"], f.id, e.where() + ".sentinels");
    // A session begins only when its sentinels held.
    if (f.sentinels->moved()) e.fail("sentinels: they moved, and a session does not begin through a moved field");
  }
  return f;
}

std::string fieldBanner(const db::Store& store, const std::optional<FieldApplied>& applied, double maxAgeHours) {
  const auto age = [](const std::string& utc) {
    char b[32];
    std::snprintf(b, sizeof b, "%.0f h", fieldCheckAgeHours(utc));
    return std::string(b);
  };
  if (applied) {
    std::string words = "field: corrected by " + applied->words();
    if (fieldCheckAgeHours(applied->createdUtc) > maxAgeHours)
      words += "; the check is " + age(applied->createdUtc) + " old: check the field again (leafdig field check)";
    return words;
  }
  std::vector<FieldCalibration> checks;
  try {
    checks = fieldCalibrations(store);
  } catch (const std::exception& e) {
    return std::string("field: not corrected; the file's field checks do not verify (") + e.what() + ")";
  }
  if (checks.empty() || fieldCheckAgeHours(checks.back().createdUtc) > maxAgeHours) {
    if (maxAgeHours == kFieldCheckMaxAgeHours)
      return "field: not corrected, and no check of the field today (leafdig field check)";
    char within[48];
    std::snprintf(within, sizeof within, "%.0f h", maxAgeHours);
    return std::string("field: not corrected, and no check of the field in the last ") + within +
           " (leafdig field check)";
  }
  return "field: not corrected (check " + std::to_string(checks.back().id) + ", " + checks.back().result.verdict +
         ", is " + age(checks.back().createdUtc) + " old: --field-calibration latest applies it)";
}

double fieldCheckAgeHours(const std::string& createdUtc) {
  std::tm tm{};
  int ms = 0;
  if (std::sscanf(createdUtc.c_str(), "%4d-%2d-%2dT%2d:%2d:%2d.%3dZ", &tm.tm_year, &tm.tm_mon, &tm.tm_mday, &tm.tm_hour,
                  &tm.tm_min, &tm.tm_sec, &ms) < 6)
    return 0;
  tm.tm_year -= 1900;
  tm.tm_mon -= 1;
  const std::time_t made = timegm(&tm);
  const std::time_t now = std::time(nullptr);
  return std::difftime(now, made) / 3600.0;
}

}  // namespace leafdig::acquisition
