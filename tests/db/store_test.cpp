// The SQLite store through its public interface, and the file through SQLite's own API
// (as a person with the sqlite3 tool would tamper with it).
#include "leafdig/db/store.hpp"

#include <gtest/gtest.h>
#include <sqlite3.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "../../db/src/schema.hpp"  // white box: a file of schema 1, as the last release wrote it
#include "../support/small_file_system.hpp"

namespace fs = std::filesystem;
using leafdig::db::EventInput;
using leafdig::db::Projection;
using leafdig::db::Store;
using leafdig::db::StoreError;
using leafdig::db::StoreErrorKind;

namespace {

class StoreTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("leafdig-db-" + std::to_string(::getpid()) + "-" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    path_ = (dir_ / "station.sqlite").string();
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::int64_t newSession(Store& s) {
    const auto op = s.ensureOperator("ana");
    const auto leaf = s.ensureLeaf(s.ensurePlant(s.ensureProject("tobacco-2026"), "P07"), 5, "middle");
    return s.createSession(leaf, op, "bench-1", "standard", "sequential", R"({"still_mm":0.5})");
  }
  // An accepted marker as capture writes it: the payload says what the projection holds.
  static EventInput marker(int row, int col, double x) {
    EventInput e;
    e.kind = "accepted";
    e.payloadJson =
        nlohmann::json{{"what", "marker"}, {"row", row}, {"col", col}, {"position_mm", {x, 2.0, 3.0}}}.dump();
    e.raw = "01   1.00   2.00   3.00\\r\\n";
    e.monoNs = 123456789;
    e.projection = Projection{Projection::Kind::Marker, row, col, "marker", {x, 2, 3}, 0, ""};
    return e;
  }
  static void sql(const std::string& path, const std::string& statement, bool expectOk = true) {
    sqlite3* db = nullptr;
    ASSERT_EQ(sqlite3_open(path.c_str(), &db), SQLITE_OK);
    char* err = nullptr;
    const int rc = sqlite3_exec(db, statement.c_str(), nullptr, nullptr, &err);
    if (expectOk)
      EXPECT_EQ(rc, SQLITE_OK) << (err ? err : "");
    else
      EXPECT_NE(rc, SQLITE_OK);
    sqlite3_free(err);
    sqlite3_close(db);
  }
  static std::string bytes(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
  }
  void expectRefusedUnchanged(StoreErrorKind kind, const std::string& messagePart) {
    const std::string before = bytes(path_);
    try {
      Store s(path_);
      FAIL() << "opened";
    } catch (const StoreError& e) {
      EXPECT_EQ(e.kind(), kind) << e.what();
      EXPECT_NE(std::string(e.what()).find(messagePart), std::string::npos) << e.what();
      EXPECT_NE(e.remedy().find("not modified"), std::string::npos) << e.remedy();
    }
    // (a read-only look at a WAL file may leave -shm/-wal beside it; the file itself is intact)
    EXPECT_EQ(leafdig::db::sha256Hex(bytes(path_)), leafdig::db::sha256Hex(before));
  }

  fs::path dir_;
  std::string path_;
};

TEST_F(StoreTest, CreatesAVersionedWalDatabase) {
  {
    Store s(path_);
    EXPECT_EQ(s.schemaVersion(), leafdig::db::kSchemaVersion);
  }
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(path_.c_str(), &db), SQLITE_OK);
  sqlite3_stmt* st = nullptr;
  sqlite3_prepare_v2(db, "PRAGMA journal_mode", -1, &st, nullptr);
  ASSERT_EQ(sqlite3_step(st), SQLITE_ROW);
  EXPECT_STREQ(reinterpret_cast<const char*>(sqlite3_column_text(st, 0)), "wal");
  sqlite3_finalize(st);
  sqlite3_prepare_v2(db, "PRAGMA application_id", -1, &st, nullptr);
  ASSERT_EQ(sqlite3_step(st), SQLITE_ROW);
  EXPECT_EQ(sqlite3_column_int(st, 0), leafdig::db::kApplicationId);
  sqlite3_finalize(st);
  sqlite3_close(db);
  Store again(path_);  // reopening migrates nothing and works
  EXPECT_EQ(again.schemaVersion(), leafdig::db::kSchemaVersion);
}

TEST_F(StoreTest, AFileOfSchemaOneIsReadAsItIsAndUpgradedWhenWrittenKeepingEverySessionAndItsChain) {
  // A station file as the last release wrote it: schema 1, one leaf session with its genesis.
  const std::string created = "2026-06-01T09:00:00.000Z", settings = R"({"still_mm":0.5})";
  const std::string genesis = leafdig::db::genesisHash(1, created, settings);
  sql(path_, std::string(leafdig::db::detail::kMigrations[0]) +
                 "PRAGMA user_version=1; PRAGMA application_id=" + std::to_string(leafdig::db::kApplicationId) + ";" +
                 "INSERT INTO operators VALUES (1, 'ana', 'technician'); INSERT INTO projects VALUES (1, 'tobacco');"
                 "INSERT INTO plants VALUES (1, 1, 'P07'); INSERT INTO leaves VALUES (1, 1, 5, 'middle', NULL);"
                 "INSERT INTO sessions(id, leaf_id, operator_id, station, mode, capture_order, settings_json, "
                 "created_utc, genesis_hash, head_hash) VALUES (1, 1, 1, 'bench-1', 'standard', 'sequential', '" +
                 settings + "', '" + created + "', '" + genesis + "', '" + genesis + "');");
  const std::string before = bytes(path_);
  {
    const Store reader(path_, true);  // a reader does not upgrade: the file stays as it was
    EXPECT_EQ(reader.schemaVersion(), 1);
    ASSERT_EQ(reader.sessions().size(), 1U);
    EXPECT_EQ(reader.sessions()[0].kind, "leaf");
    EXPECT_EQ(reader.sessions()[0].leafPosition, 5);
  }
  EXPECT_EQ(leafdig::db::sha256Hex(bytes(path_)), leafdig::db::sha256Hex(before));
  {
    Store s(path_);
    EXPECT_EQ(s.schemaVersion(), leafdig::db::kSchemaVersion);
    EXPECT_EQ(s.session(1)->genesisForm, 1);  // written before the station was in the chain
    const auto info = s.session(1);
    ASSERT_TRUE(info);
    EXPECT_EQ(info->kind, "leaf");
    EXPECT_EQ(info->plant, "P07");
    EXPECT_EQ(info->leafPosition, 5);
    EXPECT_EQ(info->leafType, "middle");
    EXPECT_EQ(info->headHash, genesis);
    EXPECT_TRUE(s.verify(1).ok) << s.verify(1).problem;
    EXPECT_EQ(s.append(1, marker(1, 1, 10.0)), 1);
    EXPECT_TRUE(s.verify(1).ok);
  }
  // The upgraded file is exactly what this leafdig writes: opened again without a word.
  const Store again(path_);
  EXPECT_EQ(again.sessions().size(), 1U);
}

TEST_F(StoreTest, APlantSessionHasAPlantAndNoLeafAndItsOwnChain) {
  Store s(path_);
  const auto leafSession = newSession(s);
  const auto plant = s.ensurePlant(s.ensureProject("tobacco-2026"), "P07");
  const auto id = s.createPlantSession(plant, s.ensureOperator("ana"), "bench-1", "standard", "sequential", "{}");
  const auto info = s.session(id);
  ASSERT_TRUE(info);
  EXPECT_EQ(info->kind, "plant");
  EXPECT_EQ(info->plant, "P07");
  EXPECT_EQ(info->project, "tobacco-2026");
  EXPECT_EQ(info->leafPosition, 0);
  EXPECT_EQ(info->leafId, 0);
  EXPECT_EQ(s.session(leafSession)->kind, "leaf");
  EXPECT_EQ(s.sessions().size(), 2U);
  EXPECT_EQ(s.append(id, marker(1, 1, 4.0)), 1);
  EXPECT_TRUE(s.verify(id).ok);
  // Plain SQL cannot make a leaf session without a leaf, nor a plant session with one.
  sql(path_, "UPDATE sessions SET leaf_id = NULL WHERE id = " + std::to_string(leafSession), false);
  sql(path_, "UPDATE sessions SET kind = 'leaf' WHERE id = " + std::to_string(id), false);
  sql(path_, "UPDATE sessions SET kind = 'bush' WHERE id = " + std::to_string(id), false);
}

TEST_F(StoreTest, AppendsEventsWithProjectionsAndUndo) {
  Store s(path_);
  const auto id = newSession(s);
  EXPECT_EQ(s.append(id, marker(1, 1, 10)), 1);
  EXPECT_EQ(s.append(id, marker(1, 2, 20)), 2);
  EventInput t;
  t.kind = "accepted";
  t.payloadJson = R"({"what":"midrib_thickness","row":1,"col":4,"value_mm":1.25})";
  t.raw = "+001.250\\r";
  t.projection = Projection{Projection::Kind::Thickness, 1, 4, "midrib_thickness", {}, 1.25, "+001.250\\r"};
  EXPECT_EQ(s.append(id, t), 3);
  EventInput undo;
  undo.kind = "undone";
  undo.payloadJson = R"({"what":"marker","row":1,"col":2,"seq":2})";
  undo.retracts = 2;
  EXPECT_EQ(s.append(id, undo), 4);
  const auto m = s.markers(id);
  ASSERT_EQ(m.size(), 1u);
  EXPECT_EQ(*m[0].col, 1);
  EXPECT_DOUBLE_EQ(m[0].positionMm[0], 10);
  const auto th = s.thickness(id);
  ASSERT_EQ(th.size(), 1u);
  EXPECT_DOUBLE_EQ(th[0].valueMm, 1.25);
  EXPECT_EQ(th[0].raw, "+001.250\\r");
  EXPECT_EQ(s.events(id).size(), 4u);
  const auto info = s.session(id);
  ASSERT_TRUE(info);
  EXPECT_EQ(info->headSeq, 4);
  EXPECT_EQ(info->plant, "P07");
  EXPECT_EQ(info->leafPosition, 5);
  EXPECT_TRUE(s.verify(id).ok);
  s.setStatus(id, "complete", "ana", "all rows done");
  EXPECT_EQ(s.session(id)->status, "complete");
  EXPECT_TRUE(s.verify(id).ok);
  EXPECT_THROW(s.setStatus(id, "finished", "ana", ""), StoreError);
  // Every status of the public table is one the schema's CHECK takes (the table and the
  // released schema cannot drift apart unseen).
  for (const char* status : leafdig::db::kSessionStatuses) {
    s.setStatus(id, status, "ana", "the table's word");
    EXPECT_EQ(s.session(id)->status, status);
  }
  EXPECT_TRUE(s.verify(id).ok);
}

TEST_F(StoreTest, EventsCannotBeEditedAndTamperingIsFound) {
  std::int64_t id = 0;
  {
    Store s(path_);
    id = newSession(s);
    for (int i = 1; i <= 5; ++i) s.append(id, marker(1, i, i));
  }
  sql(path_, "UPDATE events SET payload_json='{}' WHERE seq=3", false);  // the trigger refuses
  sql(path_, "DELETE FROM events WHERE seq=5", false);
  // Someone drops the trigger, edits event 3 and puts the trigger back as it was.
  sql(path_, "DROP TRIGGER events_no_update; UPDATE events SET raw='01 9.99' WHERE session_id=" + std::to_string(id) +
                 " AND seq=3; CREATE TRIGGER events_no_update BEFORE UPDATE ON events\n"
                 "  BEGIN SELECT RAISE(ABORT, 'events are append-only: record a correction event instead'); END");
  {
    Store s(path_);
    const auto r = s.verify(id);
    EXPECT_FALSE(r.ok);
    EXPECT_EQ(*r.firstBadSeq, 3);
    EXPECT_NE(r.problem.find("changed"), std::string::npos);
  }
  // Without the trigger the file is not opened at all: the missing trigger is named.
  sql(path_, "DROP TRIGGER events_no_update");
  expectRefusedUnchanged(StoreErrorKind::Tampered, "the trigger 'events_no_update' is missing");
}

TEST_F(StoreTest, FieldChecksAreChainedAndAnEditedOneIsNamed) {
  {
    Store s(path_);
    EXPECT_TRUE(s.fieldChecks().empty());
    EXPECT_EQ(s.addFieldCheck({"bench-1", "ana", "fastrak", "/dev/ttyUSB0", "pass", R"({"rms_mm": 0.4})"}), 1);
    EXPECT_EQ(s.addFieldCheck({"bench-1", "ben", "fastrak", "/dev/ttyUSB0", "fail", R"({"rms_mm": 3.1})"}), 2);
    EXPECT_THROW(s.addFieldCheck({"bench-1", "ana", "fastrak", "/dev/ttyUSB0", "great", "{}"}), StoreError);
    EXPECT_THROW(s.addFieldCheck({"bench-1", "ana", "fastrak", "/dev/ttyUSB0", "pass", "{rms"}), StoreError);
    const auto checks = s.fieldChecks();
    ASSERT_EQ(checks.size(), 2U);
    EXPECT_EQ(checks[1].prevHash, checks[0].hash);
    EXPECT_EQ(checks[1].operatorName, "ben");
    EXPECT_EQ(checks[0].verdict, "pass");
    EXPECT_EQ(checks[1].recordJson, R"({"rms_mm": 3.1})");
  }
  sql(path_, "UPDATE field_checks SET verdict='pass' WHERE id=2", false);  // the trigger refuses
  sql(path_, "DELETE FROM field_checks WHERE id=1", false);
  // Someone drops the trigger, turns the failed check into a pass and puts the trigger back.
  sql(path_,
      "DROP TRIGGER field_checks_no_update; UPDATE field_checks SET verdict='pass', record_json='{\"rms_mm\": 0.3}' "
      "WHERE id=2; CREATE TRIGGER field_checks_no_update BEFORE UPDATE ON field_checks\n"
      "  BEGIN SELECT RAISE(ABORT, 'field checks are append-only: run a new check'); END");
  Store s(path_);
  try {
    (void)s.fieldChecks();
    ADD_FAILURE() << "an edited field check was read";
  } catch (const StoreError& e) {
    EXPECT_EQ(e.kind(), StoreErrorKind::Tampered);
    EXPECT_NE(std::string(e.what()).find("field check 2 is not what its contents hash to"), std::string::npos)
        << e.what();
  }
}

TEST_F(StoreTest, TipCalibrationsHaveAChainOfTheirOwnAndAnEditedOneIsNamed) {
  {
    Store s(path_);
    EXPECT_TRUE(s.tipCalibrations().empty());
    EXPECT_EQ(s.addFieldCheck({"bench-1", "ana", "fastrak", "/dev/ttyUSB0", "pass", R"({"rms_mm": 0.4})"}), 1);
    EXPECT_EQ(s.addTipCalibration({"bench-1", "ana", "fastrak", "/dev/ttyUSB0", "pass", R"({"rms_mm": 0.4})"}), 1);
    EXPECT_EQ(s.addTipCalibration({"bench-1", "ben", "fastrak", "/dev/ttyUSB0", "fail", R"({"rms_mm": 2.5})"}), 2);
    // A tip is passed or failed: no correction makes it good.
    EXPECT_THROW(s.addTipCalibration({"bench-1", "ana", "fastrak", "/dev/ttyUSB0", "correctable", "{}"}), StoreError);
    const auto tips = s.tipCalibrations();
    ASSERT_EQ(tips.size(), 2U);
    EXPECT_EQ(tips[1].prevHash, tips[0].hash);
    // Its own chain: the same fields hash otherwise than a field check's.
    EXPECT_NE(tips[0].hash, s.fieldChecks()[0].hash);
    EXPECT_EQ(leafdig::db::tipCalibrationHash(tips[0]), tips[0].hash);
  }
  sql(path_, "UPDATE tip_calibrations SET verdict='pass' WHERE id=2", false);  // the trigger refuses
  sql(path_, "DELETE FROM tip_calibrations WHERE id=1", false);
  sql(path_,
      "DROP TRIGGER tip_calibrations_no_update; UPDATE tip_calibrations SET verdict='pass' WHERE id=2; "
      "CREATE TRIGGER tip_calibrations_no_update BEFORE UPDATE ON tip_calibrations\n"
      "  BEGIN SELECT RAISE(ABORT, 'tip calibrations are append-only: calibrate again'); END");
  Store s(path_);
  EXPECT_EQ(s.fieldChecks().size(), 1U);  // the field checks' chain is not the tips'
  try {
    (void)s.tipCalibrations();
    ADD_FAILURE() << "an edited tip calibration was read";
  } catch (const StoreError& e) {
    EXPECT_EQ(e.kind(), StoreErrorKind::Tampered);
    EXPECT_NE(std::string(e.what()).find("tip calibration 2 is not what its contents hash to"), std::string::npos)
        << e.what();
  }
}

TEST_F(StoreTest, TruncationIsFound) {
  std::int64_t id = 0;
  {
    Store s(path_);
    id = newSession(s);
    for (int i = 1; i <= 5; ++i) s.append(id, marker(1, i, i));
  }
  sql(path_,
      "DROP TRIGGER events_no_delete; DELETE FROM markers WHERE seq=5; DELETE FROM events WHERE seq=5; "
      "CREATE TRIGGER events_no_delete BEFORE DELETE ON events\n"
      "  BEGIN SELECT RAISE(ABORT, 'events are append-only: record a correction event instead'); END");
  Store s(path_);
  const auto r = s.verify(id);
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.problem.find("removed"), std::string::npos) << r.problem;
}

TEST_F(StoreTest, AForeignDatabaseIsRefusedUnmodified) {
  sql(path_, "CREATE TABLE birds(name TEXT); INSERT INTO birds VALUES ('wren');");
  expectRefusedUnchanged(StoreErrorKind::NotLeafdig, "not a leafdig one");
}

TEST_F(StoreTest, ATextFileIsRefusedUnmodified) {
  std::ofstream(path_) << "leaf,x,y,z\n1,2,3,4\n";
  try {
    Store s(path_);
    FAIL();
  } catch (const StoreError& e) {
    EXPECT_EQ(e.kind(), StoreErrorKind::NotLeafdig) << e.what();
  }
  EXPECT_EQ(bytes(path_), "leaf,x,y,z\n1,2,3,4\n");
}

TEST_F(StoreTest, ANewerSchemaIsRefusedUnmodified) {
  { Store s(path_); }
  sql(path_, "PRAGMA user_version=7");
  expectRefusedUnchanged(StoreErrorKind::TooNew, "newer leafdig (schema 7");
}

TEST_F(StoreTest, ADamagedFileIsRefusedUnmodified) {
  {
    Store s(path_);
    const auto id = newSession(s);
    for (int i = 1; i <= 300; ++i) s.append(id, marker(1 + i / 7, 1 + i % 7, i));
  }
  sql(path_, "PRAGMA wal_checkpoint(TRUNCATE); PRAGMA journal_mode=DELETE");
  std::string b = bytes(path_);
  ASSERT_GT(b.size(), 4096u * 6);
  for (std::size_t page = 1; page < 6; ++page)  // b-tree page headers of pages 2..6
    for (std::size_t i = 0; i < 24; ++i) b[4096 * page + i] = static_cast<char>(0x5a);
  std::ofstream(path_, std::ios::binary | std::ios::trunc) << b;
  const std::string before = leafdig::db::sha256Hex(bytes(path_));
  try {
    Store s(path_);
    FAIL() << "opened a damaged file";
  } catch (const StoreError& e) {
    EXPECT_TRUE(e.kind() == StoreErrorKind::Corrupt || e.kind() == StoreErrorKind::NotLeafdig) << e.what();
    EXPECT_NE(e.remedy().find("not modified"), std::string::npos) << e.remedy();
  }
  EXPECT_EQ(leafdig::db::sha256Hex(bytes(path_)), before);
}

// Opening for capture checks the pages capture touches — not every page (0.6 s for 10 000
// leaves) — so a damaged page where the next event would go is found before any append.
TEST_F(StoreTest, ADamagedPageWhereAppendsGoIsFoundWhenOpeningForCapture) {
  {
    Store s(path_);
    const auto id = newSession(s);
    for (int i = 1; i <= 400; ++i) s.append(id, marker(1 + i / 7, 1 + i % 7, i));
  }
  sql(path_, "PRAGMA wal_checkpoint(TRUNCATE); PRAGMA journal_mode=DELETE");
  // The leaf page holding the newest event: the right edge of the event log's b-tree.
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(path_.c_str(), &db), SQLITE_OK);
  sqlite3_stmt* st = nullptr;
  ASSERT_EQ(sqlite3_prepare_v2(db,
                               "SELECT pageno, (SELECT count(*) FROM dbstat WHERE name='events') FROM dbstat "
                               "WHERE name='events' AND pagetype='leaf' ORDER BY path DESC LIMIT 1",
                               -1, &st, nullptr),
            SQLITE_OK);
  ASSERT_EQ(sqlite3_step(st), SQLITE_ROW);
  const auto page = static_cast<std::size_t>(sqlite3_column_int(st, 0));
  ASSERT_GT(sqlite3_column_int(st, 1), 3) << "the event log should span several pages";
  sqlite3_finalize(st);
  sqlite3_close(db);
  std::string b = bytes(path_);
  for (std::size_t i = 0; i < 24; ++i) b[4096 * (page - 1) + i] = static_cast<char>(0x5a);
  std::ofstream(path_, std::ios::binary | std::ios::trunc) << b;
  expectRefusedUnchanged(StoreErrorKind::Corrupt, "malformed");
  // A reader opens it (review tools read what they need), and the full check names it.
  Store reader(path_, true);
  EXPECT_NE(reader.checkPages(), "ok");
}

TEST_F(StoreTest, TheFullPageCheckPassesOnAnIntactFile) {
  Store s(path_);
  const auto id = newSession(s);
  for (int i = 1; i <= 50; ++i) s.append(id, marker(1 + i / 7, 1 + i % 7, i));
  EXPECT_EQ(s.checkPages(), "ok");
}

TEST_F(StoreTest, AFullDiskLosesNothingAndCaptureContinuesAfterwards) {
  Store s(path_);
  const auto id = newSession(s);
  s.append(id, marker(1, 1, 1));
  s.setMaxPages(s.pageCount());
  std::int64_t last = 1;
  bool full = false;
  for (int i = 2; i < 5000 && !full; ++i) {
    try {
      last = s.append(id, marker(1 + i / 7, 1 + i % 7, i));
    } catch (const StoreError& e) {
      EXPECT_EQ(e.kind(), StoreErrorKind::DiskFull);
      EXPECT_NE(e.remedy().find("free some space"), std::string::npos);
      full = true;
    }
  }
  ASSERT_TRUE(full);
  EXPECT_EQ(s.session(id)->headSeq, last);
  EXPECT_EQ(static_cast<std::int64_t>(s.events(id).size()), last);
  s.setMaxPages(0);
  EXPECT_EQ(s.append(id, marker(9, 9, 9)), last + 1);
  EXPECT_TRUE(s.verify(id).ok);
}

// The same through a file system that is really full (a 1 MB tmpfs filled to the last byte,
// when the tests run as root); otherwise through the page quota, and the output says so.
TEST_F(StoreTest, AReallyFullFileSystemLosesNothingAndAppendsGoOnOnceSpaceIsFreed) {
  leafdig::test::SmallFileSystem disk(dir_ / "small", 1 << 20);
  const std::string path = (disk.dir() / "station.sqlite").string();
  Store s(path);
  const auto id = newSession(s);
  std::int64_t last = s.append(id, marker(1, 1, 1));
  if (disk.mounted()) {
    std::printf("disk full: a real file system (1 MB tmpfs filled until ENOSPC)\n");
    ASSERT_EQ(disk.fill(), ENOSPC);
  } else {
    std::printf("disk full: the page-limit path (not root, so no tmpfs could be mounted)\n");
    s.setMaxPages(s.pageCount());
  }
  bool full = false;
  for (int i = 2; i < 20000 && !full; ++i) {
    try {
      last = s.append(id, marker(1 + i / 7, 1 + i % 7, i));
    } catch (const StoreError& e) {
      EXPECT_EQ(e.kind(), StoreErrorKind::DiskFull) << e.what();
      EXPECT_NE(e.remedy().find("free some space"), std::string::npos) << e.remedy();
      full = true;
    }
  }
  ASSERT_TRUE(full);
  // Everything acknowledged is there, nothing half-written; the file still verifies.
  EXPECT_EQ(s.session(id)->headSeq, last);
  EXPECT_EQ(static_cast<std::int64_t>(s.events(id).size()), last);
  EXPECT_TRUE(s.verify(id).ok);
  if (disk.mounted())
    disk.release();
  else
    s.setMaxPages(0);
  EXPECT_EQ(s.append(id, marker(99, 1, 1)), last + 1);
  EXPECT_TRUE(s.verify(id).ok);
  // Another connection (the next run of the station) opens the file and sees it all.
  Store reopened(path);
  EXPECT_EQ(reopened.session(id)->headSeq, last + 1);
}

TEST_F(StoreTest, AReaderAndAWriterDoNotBlockEachOther) {
  Store writer(path_);
  const auto id = newSession(writer);
  for (int i = 1; i <= 3; ++i) writer.append(id, marker(1, i, i));
  Store reader(path_, true);
  const auto before = reader.events(id);
  // Hold a read transaction open through SQLite directly, as a curator's tool would.
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open_v2(path_.c_str(), &db, SQLITE_OPEN_READONLY, nullptr), SQLITE_OK);
  sqlite3_stmt* st = nullptr;
  ASSERT_EQ(sqlite3_prepare_v2(db, "SELECT seq FROM events ORDER BY seq", -1, &st, nullptr), SQLITE_OK);
  ASSERT_EQ(sqlite3_step(st), SQLITE_ROW);  // read transaction open
  // The append commits while the reader's transaction stays open: without WAL it would wait
  // the busy timeout out and fail (the reader does not let go until after it), whatever the
  // machine's speed (issue 26: no test asserts on the machine's speed).
  EXPECT_EQ(writer.append(id, marker(1, 4, 4)), 4);
  sqlite3_finalize(st);
  sqlite3_close(db);
  EXPECT_EQ(before.size(), 3u);
  EXPECT_EQ(reader.events(id).size(), 4u);
}

TEST_F(StoreTest, StatusEventsKeepWhoAndWhyExactly) {
  Store s(path_);
  const auto id = newSession(s);
  const std::string who = "Sean \"Ó\" Neil\\lab";
  const std::string why = "row 3 midrib\nretaken: \"jaws slipped\"";
  const auto seq = s.setStatus(id, "rejected", who, why);
  const auto payload = nlohmann::json::parse(s.events(id).at(static_cast<std::size_t>(seq - 1)).payloadJson);
  EXPECT_EQ(payload["status"], "rejected");
  EXPECT_EQ(payload["who"], who);
  EXPECT_EQ(payload["why"], why);
}

TEST_F(StoreTest, DevicesAndExportsAreRecorded) {
  Store s(path_);
  const auto id = newSession(s);
  const auto fastrak = s.ensureDevice("fastrak", "/dev/ttyUSB0", "Polhemus FASTRAK");
  EXPECT_EQ(s.ensureDevice("fastrak", "/dev/ttyUSB0"), fastrak);  // the same device once
  EXPECT_NE(s.ensureDevice("sylvac", "/dev/ttyUSB1"), fastrak);
  EXPECT_GE(s.recordExport(id, "/tmp/leaf.glb", "glb"), 1);
  try {
    (void)s.recordExport(id + 99, "/tmp/x.glb", "glb");
    FAIL() << "an export of a session that does not exist was recorded";
  } catch (const StoreError& e) {
    EXPECT_EQ(e.kind(), StoreErrorKind::Input) << e.what();
  }
}

TEST_F(StoreTest, DefaultPathFollowsXdg) {
  ::setenv("XDG_DATA_HOME", dir_.c_str(), 1);
  EXPECT_EQ(Store::defaultPath(), (dir_ / "leafdig" / "station.sqlite").string());
  ::unsetenv("XDG_DATA_HOME");
}

// ---- files from someone else (issue 25): each a copy of a real file with one statement added --

class CraftedFile : public StoreTest {
 protected:
  // A station file with one session of 12 markers, a reading and a status, closed.
  std::int64_t capture() {
    Store s(path_);
    const auto id = newSession(s);
    for (int i = 1; i <= 12; ++i) s.append(id, marker(1 + (i - 1) / 6, 1 + (i - 1) % 6, i));
    s.setStatus(id, "complete", "ana", "all steps captured");
    return id;
  }
  // Opening, read-only and for writing, is refused, named, before anything is read; the
  // file is not changed.
  void expectRefusedBothWays(const std::string& messagePart) {
    expectRefusedUnchanged(StoreErrorKind::Tampered, messagePart);
    try {
      Store reader(path_, true);
      FAIL() << "a reader opened it";
    } catch (const StoreError& e) {
      EXPECT_EQ(e.kind(), StoreErrorKind::Tampered) << e.what();
      EXPECT_NE(std::string(e.what()).find(messagePart), std::string::npos) << e.what();
    }
  }
  static std::string scalar(const std::string& path, const std::string& query) {
    sqlite3* db = nullptr;
    EXPECT_EQ(sqlite3_open_v2(path.c_str(), &db, SQLITE_OPEN_READONLY, nullptr), SQLITE_OK);
    sqlite3_stmt* st = nullptr;
    std::string out;
    if (sqlite3_prepare_v2(db, query.c_str(), -1, &st, nullptr) == SQLITE_OK && sqlite3_step(st) == SQLITE_ROW &&
        sqlite3_column_text(st, 0))
      out = reinterpret_cast<const char*>(sqlite3_column_text(st, 0));
    sqlite3_finalize(st);
    sqlite3_close(db);
    return out;
  }
};

TEST_F(CraftedFile, ATriggerThatRewritesMarkersIsRefusedByNameAndNeverFires) {
  const auto id = capture();
  sql(path_,
      "CREATE TRIGGER evil AFTER INSERT ON events BEGIN UPDATE markers SET x_mm = x_mm + 100 WHERE session_id = "
      "NEW.session_id; INSERT INTO operators(name, role) VALUES ('pwned-' || NEW.seq, 'curator'); END;");
  expectRefusedBothWays("an extra trigger 'evil' on 'events'");
  EXPECT_EQ(scalar(path_, "SELECT count(*) FROM operators WHERE name LIKE 'pwned-%'"), "0");
  EXPECT_EQ(scalar(path_, "SELECT x_mm FROM markers WHERE session_id = " + std::to_string(id) + " AND seq = 1"), "1.0");
}

TEST_F(CraftedFile, AViewInPlaceOfATableIsRefusedByNameBeforeItIsRead) {
  (void)capture();
  sql(path_,
      "ALTER TABLE markers RENAME TO markers_real; CREATE VIEW markers AS SELECT session_id, seq, what, row, col, "
      "x_mm + 50 AS x_mm, y_mm, z_mm FROM markers_real;");
  expectRefusedBothWays("the table 'markers' is missing");
  expectRefusedBothWays("an extra view 'markers'");
}

TEST_F(CraftedFile, AnEndlessViewIsRefusedInsteadOfRun) {
  (void)capture();
  // A `sessions` view over a recursive CTE that never ends: reading it would never return.
  sql(path_,
      "ALTER TABLE sessions RENAME TO sessions_real; CREATE VIEW sessions AS WITH RECURSIVE n(i) AS (SELECT 1 UNION "
      "ALL SELECT i + 1 FROM n) SELECT s.* FROM sessions_real s, n;");
  expectRefusedBothWays("an extra view 'sessions'");
}

TEST_F(CraftedFile, AChangedTableOrAnExtraIndexOrTableIsRefusedAndAnalyzeIsNot) {
  (void)capture();
  sql(path_, "ANALYZE");  // sqlite_stat1 only steers query plans
  { Store s(path_, true); }
  sql(path_, "CREATE INDEX markers_by_x ON markers(x_mm)");
  expectRefusedBothWays("an extra index 'markers_by_x' on 'markers'");
  sql(path_, "DROP INDEX markers_by_x; ALTER TABLE markers ADD COLUMN note TEXT");
  expectRefusedBothWays("the table 'markers' is defined otherwise");
}

TEST_F(CraftedFile, ASchemaVersionOfMinusOneOrZeroIsRefusedNotMigrated) {
  (void)capture();
  sql(path_, "PRAGMA user_version = -1");
  expectRefusedBothWays("schema version -1, which no leafdig writes");
  sql(path_, "PRAGMA user_version = 0");
  expectRefusedBothWays("schema version 0 but holds tables");
}

TEST_F(CraftedFile, ASessionWhoseLeafWasDeletedIsNamed) {
  (void)capture();
  sql(path_, "PRAGMA foreign_keys = OFF; DELETE FROM leaves;");
  expectRefusedBothWays("sessions row 1 names a leaves row that is not there");
}

TEST_F(CraftedFile, AProjectionEditedBehindTheEventsIsFoundByVerifyNamingTheItem) {
  const auto id = capture();
  sql(path_, "UPDATE markers SET x_mm = x_mm + 100 WHERE seq = 8");
  {
    Store s(path_, true);
    const auto r = s.verify(id);
    EXPECT_FALSE(r.ok);
    EXPECT_EQ(r.firstBadSeq, 8);
    EXPECT_NE(r.problem.find("the markers table has marker row 2 col 2 of event 8 as (108.000, 2.000, 3.000) mm, "
                             "but its event says marker row 2 col 2 (8.000, 2.000, 3.000) mm"),
              std::string::npos)
        << r.problem;
  }
  sql(path_, "UPDATE markers SET x_mm = x_mm - 100 WHERE seq = 8; DELETE FROM markers WHERE seq = 3");
  EXPECT_NE(Store(path_, true).verify(id).problem.find("lacks marker row 1 col 3 of event 3"), std::string::npos);
  sql(path_, "INSERT INTO markers VALUES (" + std::to_string(id) +
                 ", 3, 'marker', 1, 3, 3.0, 2.0, 3.0); UPDATE sessions SET status = 'approved'");
  EXPECT_NE(
      Store(path_, true).verify(id).problem.find("the session's status is 'approved' but its events say 'complete'"),
      std::string::npos);
}

// A -wal beside the file is part of it (SQLite's rule; after a crash it holds the last
// acknowledged events): what it holds is checked as the file is, and a command that refuses
// changes neither the file nor its -wal.
TEST_F(CraftedFile, WhatAWalHoldsIsCheckedAndARefusalLeavesFileAndWalUnchanged) {
  const auto id = capture();
  {
    sqlite3* db = nullptr;
    ASSERT_EQ(sqlite3_open(path_.c_str(), &db), SQLITE_OK);
    ASSERT_EQ(sqlite3_db_config(db, SQLITE_DBCONFIG_NO_CKPT_ON_CLOSE, 1, nullptr), SQLITE_OK);
    ASSERT_EQ(sqlite3_exec(db, "PRAGMA wal_autocheckpoint=0; UPDATE markers SET y_mm = 77 WHERE seq = 5", nullptr,
                           nullptr, nullptr),
              SQLITE_OK);
    sqlite3_close(db);
  }
  const std::string wal = path_ + "-wal";
  ASSERT_TRUE(fs::exists(wal) && fs::file_size(wal) > 0);
  const std::string file = bytes(path_), walBytes = bytes(wal);
  {
    Store s(path_);  // opened for writing, as `sessions approve` does
    const auto r = s.verify(id);
    EXPECT_FALSE(r.ok);
    EXPECT_EQ(r.firstBadSeq, 5);
  }
  EXPECT_EQ(bytes(path_), file) << "a refusing command checkpointed the -wal into the file";
  EXPECT_EQ(bytes(wal), walBytes);
}

TEST_F(CraftedFile, NoOperationRunsPastItsTimeLimitAndASignalStopsAStatement) {
  std::int64_t id = 0;
  {
    Store s(path_);
    id = newSession(s);
    for (int i = 1; i <= 3000; ++i) s.append(id, marker(1 + i / 7, 1 + i % 7, i));
  }
  Store s(path_, true);
  s.setTimeLimit(1e-9);
  try {
    (void)s.events(id);
    FAIL() << "the operation was not stopped at its time limit";
  } catch (const StoreError& e) {
    EXPECT_EQ(e.kind(), StoreErrorKind::Tampered) << e.what();
    EXPECT_NE(std::string(e.what()).find("ran longer than"), std::string::npos) << e.what();
  }
  s.setTimeLimit(Store::kDefaultTimeLimitSeconds);
  EXPECT_EQ(s.events(id).size(), 3000u);
  leafdig::db::requestInterrupt();
  try {
    (void)s.verify(id);
    FAIL() << "a requested interrupt did not stop the statement";
  } catch (const StoreError& e) {
    EXPECT_EQ(e.kind(), StoreErrorKind::Interrupted) << e.what();
  }
  leafdig::db::clearInterrupt();
  EXPECT_TRUE(s.verify(id).ok);
}

TEST(Sha256, KnownVector) {
  EXPECT_EQ(leafdig::db::sha256Hex("abc"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
}

}  // namespace
