// What the readers of a stored calibration (a field check, a tip calibration) do first, one way:
// the row's header copied, its record parsed as JSON of the expected format, and every refusal
// worded alike — naming the calibration, saying the file was edited or damaged, and what to do.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

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

}  // namespace leafdig::acquisition::detail
