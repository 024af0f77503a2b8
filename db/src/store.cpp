#include "leafdig/db/store.hpp"

#include <SQLiteCpp/SQLiteCpp.h>
#include <sqlite3.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "schema.hpp"

namespace leafdig::db {
namespace {

namespace fs = std::filesystem;

// Why the progress handler stopped a statement (SQLITE_INTERRUPT).
enum class Stop { None, Signal, TimeLimit };
thread_local Stop lastStop = Stop::None;
thread_local double lastLimitSeconds = 0;

// Maps SQLite failures to what an operator can act on.
[[noreturn]] void rethrow(const SQLite::Exception& e, const std::string& path, const std::string& doing) {
  const int code = e.getErrorCode() & 0xff;
  const std::string what = doing + " " + path + ": " + e.what();
  switch (code) {
    case SQLITE_INTERRUPT:
      if (lastStop == Stop::TimeLimit)
        throw StoreError(StoreErrorKind::Tampered,
                         doing + " " + path + ": a statement ran longer than " +
                             std::to_string(static_cast<int>(lastLimitSeconds)) + " s and was stopped",
                         "a leafdig file answers every question in well under a second; this one does not: check it "
                         "with 'leafdig sessions verify --all'; nothing was changed");
      throw StoreError(StoreErrorKind::Interrupted, doing + " " + path + ": interrupted",
                       "nothing acknowledged was lost; run the command again");
    case SQLITE_FULL:
      throw StoreError(StoreErrorKind::DiskFull, what,
                       "the disk holding " + path +
                           " is full: free some space; nothing acknowledged was lost and "
                           "capture continues when space returns");
    case SQLITE_BUSY:
    case SQLITE_LOCKED:
      throw StoreError(StoreErrorKind::Busy, what, "another program is writing to the database; try again in a moment");
    case SQLITE_NOTADB:
      throw StoreError(StoreErrorKind::NotLeafdig, what,
                       "this file is not a SQLite database; give a leafdig database path");
    case SQLITE_CORRUPT:
      throw StoreError(
          StoreErrorKind::Corrupt, what,
          "the database is damaged; it was not modified. Restore it from a backup, or give another --db path");
    case SQLITE_CONSTRAINT:
      throw StoreError(StoreErrorKind::Input, what, "the change breaks a rule of the database (see docs/schema.md)");
    default: throw StoreError(StoreErrorKind::Io, what, "check that the folder exists and is writable");
  }
}

}  // namespace

namespace {
// The progress handler's state: statements stop on a signal, or past the time limit of the
// operation that runs them (OperationClock). A Store is shared between threads (the capture
// thread appends while the window reads), and SQLite runs the handler in the thread that runs
// the statement: the deadline is that thread's, the limit the Store's.
struct Budget {
  std::atomic<double> limitSeconds{Store::kDefaultTimeLimitSeconds};
};
thread_local std::chrono::steady_clock::time_point operationDeadline = std::chrono::steady_clock::time_point::max();

// Sets the deadline of one operation of a Store (all its statements together) on this thread;
// nested operations keep the outer one's.
class OperationClock {
 public:
  explicit OperationClock(const Budget& budget) : outer_(operationDeadline) {
    if (outer_ == std::chrono::steady_clock::time_point::max())
      operationDeadline =
          std::chrono::steady_clock::now() + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                                 std::chrono::duration<double>(budget.limitSeconds.load()));
  }
  OperationClock(const OperationClock&) = delete;
  OperationClock& operator=(const OperationClock&) = delete;
  ~OperationClock() { operationDeadline = outer_; }

 private:
  std::chrono::steady_clock::time_point outer_;
};
}  // namespace

struct Store::Impl {
  std::unique_ptr<SQLite::Database> db;
  Budget budget;
  int version = kSchemaVersion;  // a reader may hold an older file, read as it is
};

std::string Store::defaultPath() {
  const char* xdg = std::getenv("XDG_DATA_HOME");
  const char* home = std::getenv("HOME");
  const fs::path base = (xdg && *xdg) ? fs::path(xdg) : fs::path(home ? home : ".") / ".local/share";
  return (base / "leafdig" / "station.sqlite").string();
}

namespace {

void refuseDamaged(const std::string& path, const std::string& problem) {
  throw StoreError(StoreErrorKind::Corrupt, path + " is damaged (" + problem + ")",
                   "restore it from a backup; the file was not modified");
}

// ---- a file from elsewhere ------------------------------------------------------------------
// A station file is input like any other: a curator opens files technicians send, and sync
// reads them. Before anything in it is read, every connection is made defensive and the
// schema is compared with ours (docs/schema.md, "Files from elsewhere").

int onProgress(void* context) {
  const auto* b = static_cast<const Budget*>(context);
  if (interruptRequested()) {
    lastStop = Stop::Signal;
    return 1;
  }
  if (std::chrono::steady_clock::now() > operationDeadline) {
    lastStop = Stop::TimeLimit;
    lastLimitSeconds = b->limitSeconds.load();
    return 1;
  }
  return 0;
}

// Defensive mode (no writes to the schema by pragmas), no functions with side effects from
// the file's own schema, no views at all, and a progress handler (signals, time limit).
void harden(SQLite::Database& db, Budget* budget) {
  sqlite3* h = db.getHandle();
  (void)sqlite3_db_config(h, SQLITE_DBCONFIG_DEFENSIVE, 1, nullptr);
  (void)sqlite3_db_config(h, SQLITE_DBCONFIG_TRUSTED_SCHEMA, 0, nullptr);
  (void)sqlite3_db_config(h, SQLITE_DBCONFIG_ENABLE_VIEW, 0, nullptr);
  // A command that only reads (or refuses) leaves the file and its -wal as it found them; a
  // connection that wrote checkpoints on close (~Store).
  (void)sqlite3_db_config(h, SQLITE_DBCONFIG_NO_CKPT_ON_CLOSE, 1, nullptr);
  sqlite3_progress_handler(h, 10000, &onProgress, budget);
}

struct SchemaEntry {
  std::string type, name, table, sql;
};

std::vector<SchemaEntry> readSchema(SQLite::Database& db) {
  std::vector<SchemaEntry> out;
  SQLite::Statement q(db, "SELECT type, name, tbl_name, coalesce(sql, '') FROM sqlite_master ORDER BY type, name");
  while (q.executeStep())
    out.push_back({q.getColumn(0).getString(), q.getColumn(1).getString(), q.getColumn(2).getString(),
                   q.getColumn(3).getString()});
  return out;
}

// Our schema at `version`: the migrations run in memory, read back as SQLite stores them.
std::vector<SchemaEntry> expectedSchema(int version) {
  SQLite::Database mem(":memory:", SQLite::OPEN_READWRITE | SQLite::OPEN_CREATE);
  for (int v = 0; v < version; ++v) mem.exec(detail::kMigrations[static_cast<std::size_t>(v)]);
  return readSchema(mem);
}

std::string quoted(const std::string& name) {
  std::string out = "'";
  for (const char c : name) {
    const auto u = static_cast<unsigned char>(c);
    if (u < 0x20 || u == 0x7f) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\x%02x", u);
      out += buf;
    } else {
      out += c;
    }
  }
  return out + "'";
}

// Every table, index, trigger and view of the file against ours: anything extra, missing or
// defined otherwise is named. (sqlite_stat1..4, written by ANALYZE, only steer query plans.)
void checkSchema(SQLite::Database& db, const std::string& path, int version) {
  const std::vector<SchemaEntry> expected = expectedSchema(version);
  const std::vector<SchemaEntry> actual = readSchema(db);
  std::vector<std::string> problems;
  for (const SchemaEntry& e : expected) {
    const auto at = std::find_if(actual.begin(), actual.end(),
                                 [&](const SchemaEntry& a) { return a.type == e.type && a.name == e.name; });
    if (at == actual.end())
      problems.push_back("the " + e.type + " " + quoted(e.name) + " is missing");
    else if (at->sql != e.sql || at->table != e.table)
      problems.push_back("the " + e.type + " " + quoted(e.name) + " is defined otherwise than leafdig defines it");
  }
  for (const SchemaEntry& a : actual) {
    const bool ours = std::any_of(expected.begin(), expected.end(),
                                  [&](const SchemaEntry& e) { return a.type == e.type && a.name == e.name; });
    if (ours || (a.type == "table" && a.name.rfind("sqlite_stat", 0) == 0)) continue;
    problems.push_back("an extra " + a.type + " " + quoted(a.name) +
                       (a.type == "trigger" || a.type == "index" ? " on " + quoted(a.table) : ""));
  }
  if (problems.empty()) return;
  std::string list;
  for (const auto& p : problems) list += (list.empty() ? "" : "; ") + p;
  throw StoreError(StoreErrorKind::Tampered, path + " holds what leafdig never writes: " + list,
                   "the file was changed by another program and is not opened: nothing in it was read, and the file "
                   "was not modified; ask for the station's own copy, or look at it with sqlite3 (.schema)");
}

// Rows that name what is not in the file: a session whose leaf or operator was deleted, a
// leaf without its plant, … (the small tables; events and projections are checked per
// session by verify).
void checkReferences(SQLite::Database& db, const std::string& path) {
  std::vector<std::string> problems;
  for (const char* table : {"plants", "leaves", "sessions", "exports"}) {
    SQLite::Statement q(db, std::string("PRAGMA foreign_key_check(") + table + ")");
    while (q.executeStep() && problems.size() < 5)
      problems.push_back(q.getColumn(0).getString() + " row " + q.getColumn(1).getString() + " names a " +
                         q.getColumn(2).getString() + " row that is not there");
  }
  if (problems.empty()) return;
  std::string list;
  for (const auto& p : problems) list += (list.empty() ? "" : "; ") + p;
  throw StoreError(StoreErrorKind::Tampered, path + " has rows that name what was removed: " + list,
                   "rows were deleted by another program; the file is not opened and was not modified: ask for the "
                   "station's own copy");
}

void checkWhatCaptureTouches(SQLite::Database& db, const std::string& path) {
  for (const char* table : {"operators", "projects", "plants", "leaves", "devices", "sessions", "exports"}) {
    const std::string check = db.execAndGet(std::string("PRAGMA quick_check(") + table + ")").getString();
    if (check != "ok") refuseDamaged(path, check);
  }
  // Reading the last entries walks each b-tree's right edge (tables and their keys).
  for (const char* last : {"SELECT session_id, seq, hash FROM events ORDER BY session_id DESC, seq DESC LIMIT 1",
                           "SELECT session_id, seq FROM markers ORDER BY session_id DESC, seq DESC LIMIT 1",
                           "SELECT x_mm FROM markers ORDER BY rowid DESC LIMIT 1",
                           "SELECT session_id, seq FROM thickness_readings ORDER BY session_id DESC, seq DESC LIMIT 1",
                           "SELECT value_mm FROM thickness_readings ORDER BY rowid DESC LIMIT 1"}) {
    SQLite::Statement q(db, last);
    while (q.executeStep()) {
      for (int i = 0; i < q.getColumnCount(); ++i) (void)q.getColumn(i).getText();
    }
  }
}

}  // namespace

std::string Store::checkPages() const {
  OperationClock clock(impl_->budget);
  try {
    std::string problems;
    SQLite::Statement q(*impl_->db, "PRAGMA quick_check");
    while (q.executeStep()) problems += (problems.empty() ? "" : "; ") + q.getColumn(0).getString();
    return problems;
  } catch (const SQLite::Exception& e) {
    return e.what();
  }
}

Store::Store(const std::string& path, bool readOnly) : impl_(std::make_unique<Impl>()), path_(path) {
  std::error_code ec;
  // A named pipe would block the open for ever, /dev/zero read as a database: only a regular
  // file (or a new name) is a station's file.
  const fs::file_status status = fs::status(path, ec);
  if (fs::exists(status) && !fs::is_regular_file(status))
    throw StoreError(StoreErrorKind::Input,
                     path + " is not a regular file (" +
                         (fs::is_directory(status) ? "a folder"
                          : fs::is_fifo(status)    ? "a named pipe"
                                                   : "a device") +
                         ")",
                     "give the path of a leafdig database, or a new file name to start one; nothing was opened");
  const auto size = fs::exists(status) ? fs::file_size(path, ec) : 0;
  const bool exists = !ec && size > 0 && size != static_cast<std::uintmax_t>(-1);
  OperationClock clock(impl_->budget);
  try {
    if (exists) {
      // Look before touching: a foreign, damaged, newer or doctored file is refused unmodified,
      // before any of its tables is read.
      // It waits for a lock as the store itself does (5 s): another connection closing the
      // file checkpoints it under a short exclusive lock, and a look that gave up at once
      // would call the file locked (seen when a capture's thread ended as the station
      // opened its file to show the result).
      SQLite::Database probe(path, SQLite::OPEN_READONLY, 5000);
      harden(probe, &impl_->budget);
      const int appId = probe.execAndGet("PRAGMA application_id").getInt();
      const int version = probe.execAndGet("PRAGMA user_version").getInt();
      const int tables = probe.execAndGet("SELECT count(*) FROM sqlite_master").getInt();
      if (appId != kApplicationId && tables > 0)
        throw StoreError(
            StoreErrorKind::NotLeafdig, path + " is a SQLite database, but not a leafdig one",
            "give the path of a leafdig database, or a new file name to start one; this file was not modified");
      if (version > kSchemaVersion)
        throw StoreError(StoreErrorKind::TooNew,
                         path + " was written by a newer leafdig (schema " + std::to_string(version) +
                             "; this program knows up to " + std::to_string(kSchemaVersion) + ")",
                         "install a newer leafdig to open it; the file was not modified");
      if (version < 0 || (version == 0 && tables > 0))
        throw StoreError(StoreErrorKind::Tampered,
                         path + " says it is leafdig schema version " + std::to_string(version) +
                             (version < 0 ? ", which no leafdig writes" : " but holds tables"),
                         "its PRAGMA user_version was changed by another program; the file was not modified: ask "
                         "for the station's own copy");
      if (tables > 0) {
        checkSchema(probe, path, version);
        checkReferences(probe, path);
      }
      // A writer must not append into a damaged file, but checking every page costs 0.6 s
      // for 10 000 leaves (docs/benchmarks.md). It checks what capture touches: the small
      // tables whole, and the right edge of the event log and of its projections, where
      // appends go. The pages of the session being captured are read, and its chain
      // verified, when the session is opened; `sessions verify` checks every page
      // (checkPages). A reader relies on SQLite's own checks as it reads.
      if (!readOnly) checkWhatCaptureTouches(probe, path);
    } else if (readOnly) {
      throw StoreError(StoreErrorKind::Io, "no database at " + path, "check the --db path");
    } else if (const fs::path dir = fs::path(path).parent_path(); !dir.empty()) {
      fs::create_directories(dir, ec);
    }
    impl_->db = std::make_unique<SQLite::Database>(
        path, readOnly ? SQLite::OPEN_READONLY : (SQLite::OPEN_READWRITE | SQLite::OPEN_CREATE), 5000);
    harden(*impl_->db, &impl_->budget);
    if (!readOnly) {
      impl_->db->exec("PRAGMA journal_mode=WAL");
      impl_->db->exec("PRAGMA synchronous=FULL");
    }
    impl_->version = impl_->db->execAndGet("PRAGMA user_version").getInt();
    if (!readOnly && impl_->version < kSchemaVersion) {
      // Migrations may make a table again (2: sessions): foreign keys are off while they run
      // and checked whole before each commits.
      impl_->db->exec("PRAGMA foreign_keys=OFF");
      for (int& version = impl_->version; version < kSchemaVersion; ++version) {
        SQLite::Transaction tx(*impl_->db, SQLite::TransactionBehavior::IMMEDIATE);
        impl_->db->exec(detail::kMigrations[static_cast<std::size_t>(version)]);
        if (SQLite::Statement fk(*impl_->db, "PRAGMA foreign_key_check"); fk.executeStep())
          throw StoreError(StoreErrorKind::Corrupt,
                           path + ": upgrading to schema " + std::to_string(version + 1) + " found a " +
                               fk.getColumn(0).getString() + " row naming a missing " + fk.getColumn(2).getString() +
                               " row",
                           "the file was not modified; ask for the station's own copy");
        impl_->db->exec("PRAGMA user_version=" + std::to_string(version + 1));
        impl_->db->exec("PRAGMA application_id=" + std::to_string(kApplicationId));
        tx.commit();
      }
    }
    impl_->db->exec("PRAGMA foreign_keys=ON");
  } catch (const SQLite::Exception& e) {
    rethrow(e, path, "cannot open");
  }
}

Store::~Store() {
  // A connection that wrote checkpoints its -wal into the file as it closes (the file alone
  // then holds everything); one that only read, or refused, leaves both as they were.
  if (impl_ && impl_->db && sqlite3_total_changes(impl_->db->getHandle()) > 0)
    (void)sqlite3_db_config(impl_->db->getHandle(), SQLITE_DBCONFIG_NO_CKPT_ON_CLOSE, 0, nullptr);
}

void Store::setTimeLimit(double seconds) {
  impl_->budget.limitSeconds = seconds;
}

int Store::schemaVersion() const {
  return impl_->db->execAndGet("PRAGMA user_version").getInt();
}

namespace {
std::int64_t upsertId(SQLite::Database& db, const std::string& select, const std::string& insert,
                      const std::vector<std::string>& args) {
  SQLite::Statement q(db, select);
  for (int i = 0; i < q.getBindParameterCount(); ++i) q.bind(i + 1, args[static_cast<std::size_t>(i)]);
  if (q.executeStep()) return q.getColumn(0).getInt64();
  SQLite::Statement ins(db, insert);
  for (std::size_t i = 0; i < args.size(); ++i) ins.bind(static_cast<int>(i + 1), args[i]);
  ins.exec();
  return db.getLastInsertRowid();
}
}  // namespace

std::int64_t Store::ensureOperator(const std::string& name, const std::string& role) {
  try {
    const auto id = upsertId(*impl_->db, "SELECT id FROM operators WHERE name=?1",
                             "INSERT INTO operators(name, role) VALUES (?1, ?2)", {name, role});
    return id;
  } catch (const SQLite::Exception& e) {
    rethrow(e, path_, "cannot record operator '" + name + "' in");
  }
}

std::int64_t Store::ensureProject(const std::string& name) {
  try {
    return upsertId(*impl_->db, "SELECT id FROM projects WHERE name=?1", "INSERT INTO projects(name) VALUES (?1)",
                    {name});
  } catch (const SQLite::Exception& e) {
    rethrow(e, path_, "cannot record project in");
  }
}

std::int64_t Store::ensurePlant(std::int64_t projectId, const std::string& name) {
  try {
    return upsertId(*impl_->db, "SELECT id FROM plants WHERE project_id=?1 AND name=?2",
                    "INSERT INTO plants(project_id, name) VALUES (?1, ?2)", {std::to_string(projectId), name});
  } catch (const SQLite::Exception& e) {
    rethrow(e, path_, "cannot record plant in");
  }
}

std::int64_t Store::ensureLeaf(std::int64_t plantId, int position, const std::string& type,
                               std::optional<double> area) {
  try {
    SQLite::Statement q(*impl_->db, "SELECT id FROM leaves WHERE plant_id=?1 AND position=?2");
    q.bind(1, plantId);
    q.bind(2, position);
    if (q.executeStep()) {
      // A leaf measured again (or typed later): what is given now is kept.
      const std::int64_t id = q.getColumn(0).getInt64();
      if (!type.empty() || area) {
        SQLite::Statement up(*impl_->db,
                             "UPDATE leaves SET type=CASE WHEN ?2 = '' THEN type ELSE ?2 END, "
                             "measured_area_mm2=COALESCE(?3, measured_area_mm2) WHERE id=?1");
        up.bind(1, id);
        up.bind(2, type);
        if (area)
          up.bind(3, *area);
        else
          up.bind(3);
        up.exec();
      }
      return id;
    }
    SQLite::Statement ins(*impl_->db,
                          "INSERT INTO leaves(plant_id, position, type, measured_area_mm2) VALUES (?1, ?2, ?3, ?4)");
    ins.bind(1, plantId);
    ins.bind(2, position);
    ins.bind(3, type);
    if (area)
      ins.bind(4, *area);
    else
      ins.bind(4);
    ins.exec();
    return impl_->db->getLastInsertRowid();
  } catch (const SQLite::Exception& e) {
    rethrow(e, path_, "cannot record leaf in");
  }
}

std::int64_t Store::ensureDevice(const std::string& kind, const std::string& port, const std::string& description) {
  try {
    return upsertId(*impl_->db, "SELECT id FROM devices WHERE kind=?1 AND port=?2",
                    "INSERT INTO devices(kind, port, description) VALUES (?1, ?2, ?3)", {kind, port, description});
  } catch (const SQLite::Exception& e) {
    rethrow(e, path_, "cannot record device in");
  }
}

std::int64_t Store::createSession(std::int64_t leafId, std::int64_t operatorId, const std::string& station,
                                  const std::string& mode, const std::string& order, const std::string& settingsJson) {
  return insertSession(leafId, 0, operatorId, station, mode, order, settingsJson);
}

std::int64_t Store::createPlantSession(std::int64_t plantId, std::int64_t operatorId, const std::string& station,
                                       const std::string& mode, const std::string& order,
                                       const std::string& settingsJson) {
  return insertSession(0, plantId, operatorId, station, mode, order, settingsJson);
}

std::int64_t Store::insertSession(std::int64_t leafId, std::int64_t plantId, std::int64_t operatorId,
                                  const std::string& station, const std::string& mode, const std::string& order,
                                  const std::string& settingsJson) {
  try {
    SQLite::Transaction tx(*impl_->db, SQLite::TransactionBehavior::IMMEDIATE);
    const std::string created = utcNow();
    // A leaf session's plant is its leaf's; a plant session has no leaf.
    SQLite::Statement ins(*impl_->db,
                          "INSERT INTO sessions(kind, plant_id, leaf_id, operator_id, station, mode, capture_order, "
                          "settings_json, created_utc, genesis_hash, head_hash, genesis_form) VALUES (CASE WHEN ?1 IS "
                          "NULL THEN 'plant' ELSE 'leaf' END, coalesce((SELECT plant_id FROM leaves WHERE id = ?1), "
                          "?8), ?1, ?2, ?3, ?4, ?5, ?6, ?7, '', '', 2)");
    if (leafId > 0)
      ins.bind(1, leafId);
    else
      ins.bind(1);
    ins.bind(2, operatorId);
    ins.bind(3, station);
    ins.bind(4, mode);
    ins.bind(5, order);
    ins.bind(6, settingsJson);
    ins.bind(7, created);
    if (plantId > 0)
      ins.bind(8, plantId);
    else
      ins.bind(8);
    ins.exec();
    const std::int64_t id = impl_->db->getLastInsertRowid();
    const std::string genesis = genesisHash(station, leafId > 0 ? "leaf" : "plant", id, created, settingsJson);
    SQLite::Statement up(*impl_->db, "UPDATE sessions SET genesis_hash=?1, head_hash=?1 WHERE id=?2");
    up.bind(1, genesis);
    up.bind(2, id);
    up.exec();
    tx.commit();
    return id;
  } catch (const SQLite::Exception& e) {
    rethrow(e, path_, "cannot create a session in");
  }
}

namespace {

struct Head {
  std::int64_t seq = 0;
  std::string hash;
};

Head headOf(SQLite::Database& db, std::int64_t session, const std::string& path) {
  SQLite::Statement head(db, "SELECT head_seq, head_hash FROM sessions WHERE id=?1");
  head.bind(1, session);
  if (!head.executeStep())
    throw StoreError(StoreErrorKind::Input, "no session " + std::to_string(session) + " in " + path,
                     "'leafdig sessions list' shows the sessions");
  return {head.getColumn(0).getInt64(), head.getColumn(1).getString()};
}

// One event row, what it changes in the projections, and the session's head, inside the
// caller's transaction.
void writeEvent(SQLite::Database& db, std::int64_t session, const Event& e, const EventInput& change) {
  SQLite::Statement ins(db,
                        "INSERT INTO events(session_id, seq, utc, mono_ns, kind, payload_json, raw, prev_hash, hash) "
                        "VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9)");
  ins.bind(1, session);
  ins.bind(2, e.seq);
  ins.bind(3, e.utc);
  ins.bind(4, e.monoNs);
  ins.bind(5, e.kind);
  ins.bind(6, e.payloadJson);
  ins.bind(7, e.raw);
  ins.bind(8, e.prevHash);
  ins.bind(9, e.hash);
  ins.exec();
  // Retracting first: a correction takes its item's old row out and puts the new one in.
  if (change.retracts) {
    for (const char* sql : {"DELETE FROM markers WHERE session_id=?1 AND seq=?2",
                            "DELETE FROM thickness_readings WHERE session_id=?1 AND seq=?2"}) {
      SQLite::Statement del(db, sql);
      del.bind(1, session);
      del.bind(2, *change.retracts);
      del.exec();
    }
  }
  if (change.projection) {
    const Projection& p = *change.projection;
    const bool marker = p.kind == Projection::Kind::Marker;
    SQLite::Statement pr(db, marker ? "INSERT INTO markers(session_id, seq, what, row, col, x_mm, y_mm, z_mm) "
                                      "VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8)"
                                    : "INSERT INTO thickness_readings(session_id, seq, what, row, col, value_mm, raw) "
                                      "VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7)");
    pr.bind(1, session);
    pr.bind(2, e.seq);
    pr.bind(3, p.what);
    if (p.row)
      pr.bind(4, *p.row);
    else
      pr.bind(4);
    if (p.col)
      pr.bind(5, *p.col);
    else
      pr.bind(5);
    if (marker) {
      pr.bind(6, p.positionMm[0]);
      pr.bind(7, p.positionMm[1]);
      pr.bind(8, p.positionMm[2]);
    } else {
      pr.bind(6, p.valueMm);
      pr.bind(7, p.raw);
    }
    pr.exec();
  }
  SQLite::Statement up(db, change.setsStatus ? "UPDATE sessions SET head_seq=?1, head_hash=?2, status=?4 WHERE id=?3"
                                             : "UPDATE sessions SET head_seq=?1, head_hash=?2 WHERE id=?3");
  up.bind(1, e.seq);
  up.bind(2, e.hash);
  up.bind(3, session);
  if (change.setsStatus) up.bind(4, *change.setsStatus);
  up.exec();
}

}  // namespace

std::int64_t Store::append(std::int64_t session, const EventInput& ev) {
  return appendAll(session, {ev});
}

std::int64_t Store::appendAll(std::int64_t session, const std::vector<EventInput>& events) {
  OperationClock clock(impl_->budget);
  try {
    SQLite::Transaction tx(*impl_->db, SQLite::TransactionBehavior::IMMEDIATE);
    Head head = headOf(*impl_->db, session, path_);
    if (!events.empty() && events.front().follows && *events.front().follows != head.seq)
      throw StoreError(StoreErrorKind::Conflict,
                       "session " + std::to_string(session) + " in " + path_ + " moved on to event " +
                           std::to_string(head.seq) + " while this change was worked out from event " +
                           std::to_string(*events.front().follows) + " (another correction at the same time?)",
                       "nothing was written; look at the session again (sessions show) and run the command again");
    for (const EventInput& ev : events) {
      Event e;
      e.session = session;
      e.seq = head.seq + 1;
      e.utc = utcNow();
      e.monoNs = ev.monoNs;
      e.kind = ev.kind;
      e.payloadJson = ev.payloadJson;
      e.raw = ev.raw;
      e.prevHash = head.hash;
      e.hash = eventHash(e.prevHash, session, e.seq, e.utc, e.monoNs, e.kind, e.payloadJson, e.raw);
      writeEvent(*impl_->db, session, e, ev);
      head = {e.seq, e.hash};
    }
    tx.commit();  // synchronous=FULL: durable when this returns
    return head.seq;
  } catch (const SQLite::Exception& e) {
    rethrow(e, path_, "cannot record an event in");
  }
}

void Store::import(std::int64_t session, const std::vector<Event>& events) {
  OperationClock clock(impl_->budget);
  try {
    SQLite::Transaction tx(*impl_->db, SQLite::TransactionBehavior::IMMEDIATE);
    Head head = headOf(*impl_->db, session, path_);
    for (const Event& e : events) {
      const auto conflict = [&](const std::string& why) {
        throw StoreError(
            StoreErrorKind::Conflict,
            "session " + std::to_string(session) + " in " + path_ + ", event " + std::to_string(e.seq) + ": " + why,
            "nothing was taken in; the station's copy and the other differ from this event on "
            "(docs/lab.md, \"Conflicts\")");
      };
      if (e.seq != head.seq + 1) conflict("it does not follow the station's last event " + std::to_string(head.seq));
      if (e.prevHash != head.hash)
        conflict("it follows another event " + std::to_string(head.seq) + " than the station's");
      if (eventHash(e.prevHash, session, e.seq, e.utc, e.monoNs, e.kind, e.payloadJson, e.raw) != e.hash)
        conflict("its content does not hash to its hash");
      writeEvent(*impl_->db, session, e, changeOf(e));
      head = {e.seq, e.hash};
    }
    tx.commit();
  } catch (const SQLite::Exception& e) {
    rethrow(e, path_, "cannot take in events into");
  }
}

std::vector<Event> Store::events(std::int64_t session, std::int64_t fromSeq) const {
  OperationClock clock(impl_->budget);
  std::vector<Event> out;
  try {
    SQLite::Statement q(*impl_->db,
                        "SELECT seq, utc, mono_ns, kind, payload_json, raw, prev_hash, hash FROM events "
                        "WHERE session_id=?1 AND seq>=?2 ORDER BY seq");
    q.bind(1, session);
    q.bind(2, fromSeq);
    while (q.executeStep()) {
      Event e;
      e.session = session;
      e.seq = q.getColumn(0).getInt64();
      e.utc = q.getColumn(1).getString();
      e.monoNs = q.getColumn(2).getInt64();
      e.kind = q.getColumn(3).getString();
      e.payloadJson = q.getColumn(4).getString();
      e.raw = q.getColumn(5).getString();
      e.prevHash = q.getColumn(6).getString();
      e.hash = q.getColumn(7).getString();
      out.push_back(std::move(e));
    }
  } catch (const SQLite::Exception& e) {
    rethrow(e, path_, "cannot read events from");
  }
  return out;
}

std::vector<MarkerRow> Store::markers(std::int64_t session) const {
  OperationClock clock(impl_->budget);
  std::vector<MarkerRow> out;
  try {
    SQLite::Statement q(*impl_->db,
                        "SELECT seq, what, row, col, x_mm, y_mm, z_mm FROM markers WHERE session_id=?1 ORDER BY seq");
    q.bind(1, session);
    while (q.executeStep()) {
      MarkerRow m;
      m.seq = q.getColumn(0).getInt64();
      m.what = q.getColumn(1).getString();
      if (!q.getColumn(2).isNull()) m.row = q.getColumn(2).getInt();
      if (!q.getColumn(3).isNull()) m.col = q.getColumn(3).getInt();
      m.positionMm = {q.getColumn(4).getDouble(), q.getColumn(5).getDouble(), q.getColumn(6).getDouble()};
      out.push_back(m);
    }
  } catch (const SQLite::Exception& e) {
    rethrow(e, path_, "cannot read markers from");
  }
  return out;
}

std::vector<ThicknessRow> Store::thickness(std::int64_t session) const {
  OperationClock clock(impl_->budget);
  std::vector<ThicknessRow> out;
  try {
    SQLite::Statement q(
        *impl_->db,
        "SELECT seq, what, row, col, value_mm, raw FROM thickness_readings WHERE session_id=?1 ORDER BY seq");
    q.bind(1, session);
    while (q.executeStep()) {
      ThicknessRow t;
      t.seq = q.getColumn(0).getInt64();
      t.what = q.getColumn(1).getString();
      if (!q.getColumn(2).isNull()) t.row = q.getColumn(2).getInt();
      if (!q.getColumn(3).isNull()) t.col = q.getColumn(3).getInt();
      t.valueMm = q.getColumn(4).getDouble();
      t.raw = q.getColumn(5).getString();
      out.push_back(t);
    }
  } catch (const SQLite::Exception& e) {
    rethrow(e, path_, "cannot read thickness readings from");
  }
  return out;
}

namespace {
// Plant sessions (schema 2) have no leaf: position 0, no type or area.
constexpr const char* kSessionSelect =
    "SELECT s.id, coalesce(s.leaf_id, 0), pr.name, pl.name, coalesce(l.position, 0), o.name, s.station, s.status, "
    "s.mode, s.capture_order, s.settings_json, s.created_utc, s.head_seq, s.head_hash, coalesce(l.type, ''), "
    "l.measured_area_mm2, s.kind, s.genesis_form FROM sessions s LEFT JOIN leaves l ON l.id = s.leaf_id "
    "JOIN plants pl ON pl.id = s.plant_id JOIN projects pr ON pr.id = pl.project_id JOIN operators o ON o.id = "
    "s.operator_id ";
// Schema 2, read as it is: every session's genesis is of form 1.
constexpr const char* kSessionSelect2 =
    "SELECT s.id, coalesce(s.leaf_id, 0), pr.name, pl.name, coalesce(l.position, 0), o.name, s.station, s.status, "
    "s.mode, s.capture_order, s.settings_json, s.created_utc, s.head_seq, s.head_hash, coalesce(l.type, ''), "
    "l.measured_area_mm2, s.kind, 1 FROM sessions s LEFT JOIN leaves l ON l.id = s.leaf_id "
    "JOIN plants pl ON pl.id = s.plant_id JOIN projects pr ON pr.id = pl.project_id JOIN operators o ON o.id = "
    "s.operator_id ";
// A file of schema 1 read as it is (a reader does not upgrade): every session is a leaf's.
constexpr const char* kSessionSelect1 =
    "SELECT s.id, s.leaf_id, pr.name, pl.name, l.position, o.name, s.station, s.status, s.mode, s.capture_order, "
    "s.settings_json, s.created_utc, s.head_seq, s.head_hash, l.type, l.measured_area_mm2, 'leaf', 1 FROM sessions s "
    "JOIN leaves l ON l.id = s.leaf_id "
    "JOIN plants pl ON pl.id = l.plant_id JOIN projects pr ON pr.id = pl.project_id JOIN operators o ON o.id = "
    "s.operator_id ";
SessionInfo readSession(SQLite::Statement& q) {
  SessionInfo s;
  s.id = q.getColumn(0).getInt64();
  s.stationSessionId = s.id;
  s.leafId = q.getColumn(1).getInt64();
  s.project = q.getColumn(2).getString();
  s.plant = q.getColumn(3).getString();
  s.leafPosition = q.getColumn(4).getInt();
  s.operatorName = q.getColumn(5).getString();
  s.station = q.getColumn(6).getString();
  s.status = q.getColumn(7).getString();
  s.mode = q.getColumn(8).getString();
  s.order = q.getColumn(9).getString();
  s.settingsJson = q.getColumn(10).getString();
  s.createdUtc = q.getColumn(11).getString();
  s.headSeq = q.getColumn(12).getInt64();
  s.headHash = q.getColumn(13).getString();
  s.leafType = q.getColumn(14).getString();
  if (!q.getColumn(15).isNull()) s.measuredAreaMm2 = q.getColumn(15).getDouble();
  s.kind = q.getColumn(16).getString();
  s.genesisForm = q.getColumn(17).getInt();
  return s;
}
const char* sessionSelect(int version) {
  return version >= 3 ? kSessionSelect : version == 2 ? kSessionSelect2 : kSessionSelect1;
}
}  // namespace

std::optional<SessionInfo> Store::session(std::int64_t id) const {
  OperationClock clock(impl_->budget);
  try {
    SQLite::Statement q(*impl_->db, std::string(sessionSelect(impl_->version)) + "WHERE s.id=?1");
    q.bind(1, id);
    if (q.executeStep()) return readSession(q);
  } catch (const SQLite::Exception& e) {
    rethrow(e, path_, "cannot read sessions from");
  }
  return std::nullopt;
}

std::vector<SessionInfo> Store::sessions() const {
  OperationClock clock(impl_->budget);
  std::vector<SessionInfo> out;
  try {
    SQLite::Statement q(*impl_->db, std::string(sessionSelect(impl_->version)) + "ORDER BY s.id");
    while (q.executeStep()) out.push_back(readSession(q));
  } catch (const SQLite::Exception& e) {
    rethrow(e, path_, "cannot read sessions from");
  }
  return out;
}

ChainReport Store::verify(std::int64_t session) const {
  OperationClock clock(impl_->budget);
  std::string genesis;
  std::int64_t headSeq = 0;
  std::string headHash, status;
  // One snapshot for the row, the events and the tables: another process committing between
  // two of these reads (a curator's correction at the same time) is not a changed file.
  std::optional<SQLite::Transaction> snapshot;
  try {
    snapshot.emplace(*impl_->db);
    SQLite::Statement q(*impl_->db, "SELECT genesis_hash, head_seq, head_hash, status FROM sessions WHERE id=?1");
    q.bind(1, session);
    if (!q.executeStep()) {
      ChainReport r;
      r.ok = false;
      r.problem = "no session " + std::to_string(session);
      return r;
    }
    genesis = q.getColumn(0).getString();
    headSeq = q.getColumn(1).getInt64();
    headHash = q.getColumn(2).getString();
    status = q.getColumn(3).getString();
  } catch (const SQLite::Exception& e) {
    rethrow(e, path_, "cannot verify");
  }
  const std::vector<Event> log = events(session);
  ChainReport r = verifyChain(session, genesis, headSeq, headHash, log);
  if (!r.ok) return r;
  // The genesis must be what the session's row says it was made of: its station, kind,
  // creation time and settings (form 2), or the last two (form 1, written before schema 3).
  if (const auto info = this->session(session)) {
    r.genesisForm = info->genesisForm;
    if (genesisOf(*info) != genesis) {
      r.ok = false;
      r.firstBadSeq = 0;
      r.problem = std::string("its ") + (info->genesisForm >= 2 ? "station, kind, " : "") +
                  "creation time or settings were changed after it was written (its genesis hash differs)";
      return r;
    }
  }
  // The tables read by other tools (and by the CSV export) must be what the events say.
  if (const auto problem = projectionProblem(log, markers(session), thickness(session), status)) {
    r.ok = false;
    r.firstBadSeq = problem->seq;
    r.problem = problem->text;
  }
  return r;
}

std::int64_t Store::recordExport(std::int64_t session, const std::string& path, const std::string& format) {
  try {
    SQLite::Statement ins(*impl_->db, "INSERT INTO exports(session_id, path, format, utc) VALUES (?1, ?2, ?3, ?4)");
    ins.bind(1, session);
    ins.bind(2, path);
    ins.bind(3, format);
    ins.bind(4, utcNow());
    ins.exec();
    return impl_->db->getLastInsertRowid();
  } catch (const SQLite::Exception& e) {
    rethrow(e, path_, "cannot record an export in");
  }
}

void Store::setMaxPages(std::int64_t pages) {
  impl_->db->exec("PRAGMA max_page_count=" + std::to_string(pages > 0 ? pages : 4294967294LL));
}

std::int64_t Store::pageCount() const {
  return impl_->db->execAndGet("PRAGMA page_count").getInt64();
}

}  // namespace leafdig::db
