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
#include "store_impl.hpp"

namespace leafdig::db {

namespace fs = std::filesystem;
using detail::Budget;
using detail::lastLimitSeconds;
using detail::lastStop;
using detail::OperationClock;
using detail::operationDeadline;
using detail::rethrow;
using detail::Stop;

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

}  // namespace leafdig::db
