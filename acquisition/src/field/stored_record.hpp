// What the readers of a stored calibration (a field check, a tip calibration) do first, one way:
// the row's header copied, its record parsed as JSON of the expected format, and every refusal
// worded alike — naming the calibration, saying the file was edited or damaged, and what to do.
// Likewise for the calibration a session's settings keep (SettingsEntry).
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>

#include "leafdig/db/store.hpp"
#include "leafdig/model/errors.hpp"

namespace leafdig::acquisition::detail {

class StoredRecord {
 public:
  // `name`: "field check"; `format`: the record's "format"; `again`: what to do ("run a new check").
  StoredRecord(const db::CalibrationRow& row, const std::string& name, const char* format, std::string again)
      : source_(name + " " + std::to_string(row.id)), again_(std::move(again)) {
    try {
      doc_ = nlohmann::json::parse(row.recordJson);
    } catch (const nlohmann::json::exception&) {
      fail("its record is not JSON");
    }
    if (!doc_.is_object() || doc_.value("format", "") != format) fail("its record is not a leafdig " + name);
  }
  [[noreturn]] void fail(const std::string& what) const {
    throw model::InputError(source_ + ": " + what + "; the station file was edited or damaged: " + again_);
  }
  [[nodiscard]] const nlohmann::json& doc() const { return doc_; }
  [[nodiscard]] const std::string& source() const { return source_; }

 private:
  std::string source_, again_;
  nlohmann::json doc_;
};

// The row's own fields into a calibration read from it (FieldCalibration, TipCalibration).
template <class Calibration>
void copyHeader(const db::CalibrationRow& row, Calibration& c) {
  c.id = row.id;
  c.station = row.station;
  c.operatorName = row.operatorName;
  c.device = row.deviceKind + ":" + row.devicePort;
  c.createdUtc = row.createdUtc;
  c.verdict = row.verdict;
}

// The calibration a session's settings keep under `key` ("field_calibration",
// "tip_calibration"): the settings parsed, the entry picked (none when the settings do not name
// one), and its refusals (model::InputError) worded alike: "SOURCE: KEY: what".
class SettingsEntry {
 public:
  SettingsEntry(const std::string& settingsJson, const std::string& source, const char* key)
      : SettingsEntry(parsed(settingsJson, source), source, key) {}
  // The same in a document already parsed (a stored check's record keeps its tip this way).
  SettingsEntry(const nlohmann::json& doc, const std::string& source, const char* key) : where_(source + ": " + key) {
    if (!doc.is_object() || !doc.contains(key)) return;
    entry_ = doc[key];
    if (!entry_.is_object()) fail("is not an object");
  }
  [[nodiscard]] bool present() const { return !entry_.is_null(); }
  [[nodiscard]] const nlohmann::json& doc() const { return entry_; }
  [[nodiscard]] const std::string& where() const { return where_; }
  [[noreturn]] void fail(const std::string& what) const { throw model::InputError(where_ + ": " + what); }
  // "id", a positive whole number; `whose` says what of ("a check's number").
  [[nodiscard]] std::int64_t id(const std::string& whose) const {
    if (!entry_.value("id", nlohmann::json()).is_number_integer() || entry_["id"].get<std::int64_t>() < 1)
      fail("id is not " + whose);
    return entry_["id"].get<std::int64_t>();
  }
  [[nodiscard]] std::string text(const char* key, std::size_t most) const {
    if (!entry_.value(key, nlohmann::json()).is_string() || entry_[key].get_ref<const std::string&>().size() > most)
      fail(std::string(key) + " is not text of at most " + std::to_string(most) + " characters");
    return entry_[key].get<std::string>();
  }
  [[nodiscard]] double millimetres(const char* key, double most) const {
    if (!entry_.value(key, nlohmann::json()).is_number() ||
        !(entry_[key].get<double>() >= 0 && entry_[key].get<double>() <= most))
      fail(std::string(key) + " is not a number of millimetres from 0 to " + std::to_string(static_cast<int>(most)));
    return entry_[key].get<double>();
  }

 private:
  static nlohmann::json parsed(const std::string& settingsJson, const std::string& source) {
    try {
      return nlohmann::json::parse(settingsJson);
    } catch (const nlohmann::json::exception&) {
      throw model::InputError(source + ": its settings are not JSON");
    }
  }

  std::string where_;
  nlohmann::json entry_;
};

}  // namespace leafdig::acquisition::detail
