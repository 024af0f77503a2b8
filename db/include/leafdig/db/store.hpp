// The SQLite store: one file per station, an append-only hash-chained event log per
// session, projections (markers, thickness readings) kept in the same transactions, and
// the entities of docs/schema.md. Plain data types at the boundary; no other leafdig module.
//
// Thread contract: a Store is one SQLite connection, used by one thread at a time. Several
// Stores (threads or processes) may open the same file: WAL lets readers and one writer
// proceed without blocking each other.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "leafdig/db/event_store.hpp"

namespace leafdig::db {

inline constexpr int kSchemaVersion = 5;  // 2: plant sessions; 3: the station in the chain; 4: field checks;
                                          // 5: tip calibrations
inline constexpr std::int32_t kApplicationId = 0x4C454146;  // "LEAF"

// A calibration of the station's digitizer, kept append-only in the station file with a hash
// chain of its own per kind (docs/schema.md, "Field checks" and "Tip calibrations"): a check of
// its field against a jig (issue 50; docs/devices.md, "Checking the field") or a tip calibration
// of its stylus (docs/devices.md, "The stylus tip"). The record is JSON the acquisition layer writes and checks
// when it reads it back.
struct CalibrationInput {
  std::string station, operatorName, deviceKind, devicePort;
  std::string verdict;  // a field check: "pass", "correctable" or "fail"; a tip: "pass" or "fail"
  std::string recordJson;
};
struct CalibrationRow {
  std::int64_t id = 0;
  std::string station, operatorName, deviceKind, devicePort, createdUtc, verdict, recordJson, prevHash, hash;
};
using FieldCheckInput = CalibrationInput;
using FieldCheckRow = CalibrationRow;
// The chain's hash of a check: each field with its length, after the previous check's hash.
[[nodiscard]] std::string fieldCheckHash(const CalibrationRow& row);
[[nodiscard]] std::string tipCalibrationHash(const CalibrationRow& row);
// A field check's record is at most this long (a jig of 1000 points with every press fits), and
// so is a tip calibration's (every sample of a pivot).
inline constexpr std::size_t kMaxFieldCheckRecordBytes = 4 << 20;

class Store final : public EventStore {
 public:
  // Opens (creating when missing) and migrates. A file that is not a leafdig database, is
  // corrupt, or was written by a newer leafdig is refused with StoreError and not modified;
  // so is a file another program changed (docs/schema.md, "Files from elsewhere"): its schema
  // is compared with ours before any table is read (an extra trigger, view, index or table,
  // or a missing or redefined one, is named: StoreError Tampered), rows that name deleted
  // rows are named, and every connection is defensive (no views, no untrusted functions, a
  // progress handler that honours requestInterrupt and a time limit). A writer checks the
  // pages capture touches (the small tables, the right edge of the event log); checkPages()
  // checks them all. A Store that wrote checkpoints the -wal into the file on close; one that
  // only read leaves the file and its -wal as they were.
  explicit Store(const std::string& path, bool readOnly = false);
  ~Store() override;

  // $XDG_DATA_HOME/leafdig/station.sqlite (or ~/.local/share/leafdig/station.sqlite).
  [[nodiscard]] static std::string defaultPath();
  [[nodiscard]] const std::string& path() const { return path_; }
  [[nodiscard]] std::string describe() const override { return path_; }
  [[nodiscard]] int schemaVersion() const;

  std::int64_t ensureOperator(const std::string& name, const std::string& role = "technician") override;
  std::int64_t ensureProject(const std::string& name);
  std::int64_t ensurePlant(std::int64_t projectId, const std::string& name);
  // A type or area given for an existing leaf replaces the stored one.
  std::int64_t ensureLeaf(std::int64_t plantId, int position, const std::string& type = {},
                          std::optional<double> measuredAreaMm2 = {});
  std::int64_t ensureDevice(const std::string& kind, const std::string& port, const std::string& description = {});
  std::int64_t createSession(std::int64_t leafId, std::int64_t operatorId, const std::string& station,
                             const std::string& mode, const std::string& order, const std::string& settingsJson);
  // A session that captures a whole plant where it stands (docs/plants.md): no leaf; `mode` and
  // `order` are its full leaves' leaf protocol.
  std::int64_t createPlantSession(std::int64_t plantId, std::int64_t operatorId, const std::string& station,
                                  const std::string& mode, const std::string& order, const std::string& settingsJson);

  // Appends one event (and its projection change) in one transaction; returns its seq once
  // it is durable. Throws StoreError (DiskFull, Busy, Io): nothing was written then.
  std::int64_t append(std::int64_t session, const EventInput& event) override;
  std::int64_t appendAll(std::int64_t session, const std::vector<EventInput>& events) override;
  // Takes in events written elsewhere (the lab server's copy of this session: a curator's
  // decision), exactly as they are — seq, time, hashes — each checked to follow the
  // session's head and to hash to what it says; what each changes (changeOf) is applied.
  // All or nothing, in one transaction. Throws StoreError(Conflict) naming the session and
  // event when one does not follow, (Input) when one does not parse.
  void import(std::int64_t session, const std::vector<Event>& events);

  [[nodiscard]] std::vector<Event> events(std::int64_t session, std::int64_t fromSeq = 1) const override;
  [[nodiscard]] std::vector<MarkerRow> markers(std::int64_t session) const override;
  [[nodiscard]] std::vector<ThicknessRow> thickness(std::int64_t session) const override;
  [[nodiscard]] std::optional<SessionInfo> session(std::int64_t id) const override;
  [[nodiscard]] std::vector<SessionInfo> sessions() const override;
  // The chain (verifyChain), then the markers and thickness_readings tables and the
  // session's status against what the verified events give (projectionProblem).
  [[nodiscard]] ChainReport verify(std::int64_t session) const override;
  // Checks every page of the file (SQLite's quick_check): "ok", or what is damaged. Opening
  // for writing checks only what capture touches; this is the full check.
  [[nodiscard]] std::string checkPages() const;
  std::int64_t recordExport(std::int64_t session, const std::string& path, const std::string& format) override;
  // Appends a field check (its device recorded as ensureDevice does, its operator as
  // ensureOperator) after the newest, chained to it; returns its id. StoreError(Input) for a
  // verdict or record that is not one (not JSON, too long).
  std::int64_t addFieldCheck(const FieldCheckInput& check);
  // Every field check, oldest first, each verified against the chain: StoreError(Tampered) naming
  // the first one whose hash is not what its contents and the one before give (a file edited
  // with sqlite3). A file from before field checks (schema 3, opened to read) has none.
  [[nodiscard]] std::vector<FieldCheckRow> fieldChecks() const;
  // The same for the stylus' tip calibrations (verdict "pass" or "fail"); a file from before them
  // (schema 4, opened to read) has none.
  std::int64_t addTipCalibration(const CalibrationInput& calibration);
  [[nodiscard]] std::vector<CalibrationRow> tipCalibrations() const;
  // No statement of one operation (opening, a read, a verify) runs longer than this: past it,
  // the operation stops with StoreError(Tampered) instead of never returning. Default 60 s.
  static constexpr double kDefaultTimeLimitSeconds = 60;
  void setTimeLimit(double seconds);
  // Caps the file at `pages` database pages (a quota; SQLite reports "full" beyond it, as
  // for a full disk). 0 restores SQLite's default.
  void setMaxPages(std::int64_t pages);
  [[nodiscard]] std::int64_t pageCount() const;

 private:
  std::int64_t insertSession(std::int64_t leafId, std::int64_t plantId, std::int64_t operatorId,
                             const std::string& station, const std::string& mode, const std::string& order,
                             const std::string& settingsJson);

 public:
  struct CalibrationKind;  // a kind of calibration's table and words (calibrations.cpp)

 private:
  std::int64_t addCalibration(const CalibrationKind& kind, const CalibrationInput& in);
  [[nodiscard]] std::vector<CalibrationRow> calibrations(const CalibrationKind& kind) const;

  struct Impl;
  std::unique_ptr<Impl> impl_;
  std::string path_;
};

}  // namespace leafdig::db
