// The station's calibrations (store.hpp, CalibrationInput): field checks and tip calibrations,
// each kind in its own append-only table with its own chain, appended and read back verified by
// one piece of code. What a record holds is the acquisition layer's (acquisition/field/).
#include <SQLiteCpp/SQLiteCpp.h>

#include <nlohmann/json.hpp>

#include "leafdig/db/store.hpp"
#include "store_impl.hpp"

namespace leafdig::db {

using detail::OperationClock;
using detail::rethrow;

namespace {

constexpr const char* kFirstPrev = "0000000000000000000000000000000000000000000000000000000000000000";

}  // namespace

// One kind of calibration: its table, the schema that made it, the tag its hash begins with and
// the words of its refusals.
struct Store::CalibrationKind {
  const char* table;
  int since;             // the schema version that made the table
  const char* tag;       // "leafdig field check/1"
  const char* name;      // "field check"
  const char* verdicts;  // "pass, correctable or fail" (for the refusal)
  bool (*verdictOk)(const std::string&);
  const char* again;  // what to do when the chain does not verify
};

namespace {

using Kind = Store::CalibrationKind;

constexpr Kind kFieldChecks{"field_checks",
                            4,
                            "leafdig field check/1",
                            "field check",
                            "pass, correctable or fail",
                            [](const std::string& v) { return v == "pass" || v == "correctable" || v == "fail"; },
                            "run 'leafdig field check' again on a file that verifies"};
constexpr Kind kTipCalibrations{"tip_calibrations",
                                5,
                                "leafdig tip calibration/1",
                                "tip calibration",
                                "pass or fail",
                                [](const std::string& v) { return v == "pass" || v == "fail"; },
                                "run 'leafdig field tip' again on a file that verifies"};

CalibrationRow rowOf(SQLite::Statement& q) {
  CalibrationRow r;
  r.id = q.getColumn(0).getInt64();
  r.station = q.getColumn(1).getString();
  r.operatorName = q.getColumn(2).getString();
  r.deviceKind = q.getColumn(3).getString();
  r.devicePort = q.getColumn(4).getString();
  r.createdUtc = q.getColumn(5).getString();
  r.verdict = q.getColumn(6).getString();
  r.recordJson = q.getColumn(7).getString();
  r.prevHash = q.getColumn(8).getString();
  r.hash = q.getColumn(9).getString();
  return r;
}

std::string chainHash(const Kind& k, const CalibrationRow& r) {
  const auto field = [](const std::string& v) { return std::to_string(v.size()) + ":" + v + "\n"; };
  return sha256Hex(std::string(k.tag) + "\n" + field(r.prevHash) + field(std::to_string(r.id)) + field(r.station) +
                   field(r.operatorName) + field(r.deviceKind) + field(r.devicePort) + field(r.createdUtc) +
                   field(r.verdict) + field(r.recordJson));
}

}  // namespace

std::string fieldCheckHash(const CalibrationRow& r) {
  return chainHash(kFieldChecks, r);
}

std::string tipCalibrationHash(const CalibrationRow& r) {
  return chainHash(kTipCalibrations, r);
}

std::int64_t Store::addCalibration(const CalibrationKind& k, const CalibrationInput& in) {
  if (!k.verdictOk(in.verdict))
    throw StoreError(
        StoreErrorKind::Input,
        std::string("a ") + k.name + "'s verdict is " + k.verdicts + ", not '" + in.verdict.substr(0, 40) + "'",
        "this is a bug in the program that wrote it; nothing was written");
  if (in.recordJson.size() > kMaxFieldCheckRecordBytes || !nlohmann::json::accept(in.recordJson))
    throw StoreError(StoreErrorKind::Input, std::string("a ") + k.name + "'s record is not JSON of at most 4 MiB",
                     "this is a bug in the program that wrote it; nothing was written");
  try {
    const OperationClock clock(impl_->budget);
    SQLite::Transaction tx(*impl_->db, SQLite::TransactionBehavior::IMMEDIATE);
    CalibrationRow r;
    r.station = in.station;
    r.operatorName = in.operatorName;
    r.deviceKind = in.deviceKind;
    r.devicePort = in.devicePort;
    r.createdUtc = utcNow();
    r.verdict = in.verdict;
    r.recordJson = in.recordJson;
    const std::int64_t operatorId = ensureOperator(in.operatorName);
    const std::int64_t deviceId = ensureDevice(in.deviceKind, in.devicePort);
    SQLite::Statement last(*impl_->db, std::string("SELECT id, hash FROM ") + k.table + " ORDER BY id DESC LIMIT 1");
    r.prevHash = kFirstPrev;
    r.id = 1;
    if (last.executeStep()) {
      r.id = last.getColumn(0).getInt64() + 1;
      r.prevHash = last.getColumn(1).getString();
    }
    r.hash = chainHash(k, r);
    SQLite::Statement ins(*impl_->db, std::string("INSERT INTO ") + k.table +
                                          "(id, station, operator_id, device_id, created_utc, verdict, "
                                          "record_json, prev_hash, hash) VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9)");
    ins.bind(1, r.id);
    ins.bind(2, r.station);
    ins.bind(3, operatorId);
    ins.bind(4, deviceId);
    ins.bind(5, r.createdUtc);
    ins.bind(6, r.verdict);
    ins.bind(7, r.recordJson);
    ins.bind(8, r.prevHash);
    ins.bind(9, r.hash);
    ins.exec();
    tx.commit();
    return r.id;
  } catch (const SQLite::Exception& e) {
    rethrow(e, path_, std::string("cannot record a ") + k.name + " in");
  }
}

std::vector<CalibrationRow> Store::calibrations(const CalibrationKind& k) const {
  std::vector<CalibrationRow> out;
  if (impl_->version < k.since) return out;
  try {
    const OperationClock clock(impl_->budget);
    SQLite::Statement q(*impl_->db,
                        std::string("SELECT c.id, c.station, o.name, d.kind, d.port, c.created_utc, c.verdict, "
                                    "c.record_json, c.prev_hash, c.hash FROM ") +
                            k.table +
                            " c JOIN operators o ON o.id = c.operator_id JOIN devices d ON d.id = c.device_id "
                            "ORDER BY c.id");
    std::string prev = kFirstPrev;
    while (q.executeStep()) {
      CalibrationRow r = rowOf(q);
      const std::string why = r.prevHash != prev          ? std::string("does not follow the ") + k.name + " before it"
                              : chainHash(k, r) != r.hash ? std::string("is not what its contents hash to")
                                                          : std::string();
      if (!why.empty())
        throw StoreError(StoreErrorKind::Tampered,
                         path_ + ": " + k.name + " " + std::to_string(r.id) + " " + why + ": the file was edited",
                         std::string("no ") + k.name + " of this file can be trusted; " + k.again);
      prev = r.hash;
      out.push_back(std::move(r));
    }
  } catch (const SQLite::Exception& e) {
    rethrow(e, path_, std::string("cannot read the ") + k.name + "s of");
  }
  return out;
}

std::int64_t Store::addFieldCheck(const CalibrationInput& check) {
  return addCalibration(kFieldChecks, check);
}
std::vector<CalibrationRow> Store::fieldChecks() const {
  return calibrations(kFieldChecks);
}
std::int64_t Store::addTipCalibration(const CalibrationInput& calibration) {
  return addCalibration(kTipCalibrations, calibration);
}
std::vector<CalibrationRow> Store::tipCalibrations() const {
  return calibrations(kTipCalibrations);
}

}  // namespace leafdig::db
