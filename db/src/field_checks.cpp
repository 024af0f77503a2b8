// The station's field checks (store.hpp, FieldCheckInput): appended with their chain, read back
// verified. What a record holds is the acquisition layer's (acquisition/field/field_check.hpp).
#include <SQLiteCpp/SQLiteCpp.h>

#include <nlohmann/json.hpp>

#include "leafdig/db/store.hpp"
#include "store_impl.hpp"

namespace leafdig::db {

using detail::OperationClock;
using detail::rethrow;

namespace {

constexpr const char* kFirstPrev = "0000000000000000000000000000000000000000000000000000000000000000";

constexpr const char* kSelect =
    "SELECT c.id, c.station, o.name, d.kind, d.port, c.created_utc, c.verdict, c.record_json, c.prev_hash, c.hash "
    "FROM field_checks c JOIN operators o ON o.id = c.operator_id JOIN devices d ON d.id = c.device_id ";

FieldCheckRow rowOf(SQLite::Statement& q) {
  FieldCheckRow r;
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

}  // namespace

std::string fieldCheckHash(const FieldCheckRow& r) {
  const auto field = [](const std::string& v) { return std::to_string(v.size()) + ":" + v + "\n"; };
  return sha256Hex("leafdig field check/1\n" + field(r.prevHash) + field(std::to_string(r.id)) + field(r.station) +
                   field(r.operatorName) + field(r.deviceKind) + field(r.devicePort) + field(r.createdUtc) +
                   field(r.verdict) + field(r.recordJson));
}

std::int64_t Store::addFieldCheck(const FieldCheckInput& in) {
  if (in.verdict != "pass" && in.verdict != "correctable" && in.verdict != "fail")
    throw StoreError(StoreErrorKind::Input,
                     "a field check's verdict is pass, correctable or fail, not '" + in.verdict.substr(0, 40) + "'",
                     "this is a bug in the program that wrote it; nothing was written");
  if (in.recordJson.size() > kMaxFieldCheckRecordBytes || !nlohmann::json::accept(in.recordJson))
    throw StoreError(StoreErrorKind::Input, "a field check's record is not JSON of at most 4 MiB",
                     "this is a bug in the program that wrote it; nothing was written");
  try {
    const OperationClock clock(impl_->budget);
    SQLite::Transaction tx(*impl_->db, SQLite::TransactionBehavior::IMMEDIATE);
    FieldCheckRow r;
    r.station = in.station;
    r.operatorName = in.operatorName;
    r.deviceKind = in.deviceKind;
    r.devicePort = in.devicePort;
    r.createdUtc = utcNow();
    r.verdict = in.verdict;
    r.recordJson = in.recordJson;
    const std::int64_t operatorId = ensureOperator(in.operatorName);
    const std::int64_t deviceId = ensureDevice(in.deviceKind, in.devicePort);
    SQLite::Statement last(*impl_->db, "SELECT id, hash FROM field_checks ORDER BY id DESC LIMIT 1");
    r.prevHash = kFirstPrev;
    r.id = 1;
    if (last.executeStep()) {
      r.id = last.getColumn(0).getInt64() + 1;
      r.prevHash = last.getColumn(1).getString();
    }
    r.hash = fieldCheckHash(r);
    SQLite::Statement ins(*impl_->db,
                          "INSERT INTO field_checks(id, station, operator_id, device_id, created_utc, verdict, "
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
    rethrow(e, path_, "cannot record a field check in");
  }
}

std::vector<FieldCheckRow> Store::fieldChecks() const {
  std::vector<FieldCheckRow> out;
  if (impl_->version < 4) return out;
  try {
    const OperationClock clock(impl_->budget);
    SQLite::Statement q(*impl_->db, std::string(kSelect) + "ORDER BY c.id");
    std::string prev = kFirstPrev;
    while (q.executeStep()) {
      FieldCheckRow r = rowOf(q);
      const std::string why = r.prevHash != prev            ? "does not follow the check before it"
                              : fieldCheckHash(r) != r.hash ? "is not what its contents hash to"
                                                            : "";
      if (!why.empty())
        throw StoreError(StoreErrorKind::Tampered,
                         path_ + ": field check " + std::to_string(r.id) + " " + why + ": the file was edited",
                         "no check of this file can be trusted; run 'leafdig field check' again on a file that "
                         "verifies");
      prev = r.hash;
      out.push_back(std::move(r));
    }
  } catch (const SQLite::Exception& e) {
    rethrow(e, path_, "cannot read the field checks of");
  }
  return out;
}

}  // namespace leafdig::db
