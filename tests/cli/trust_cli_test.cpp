// Station files from someone else, through the command line (issue 25): a copy of a real
// station file with one statement added by sqlite3, as a technician could send it. Every
// command that opens it refuses it by name with exit code 2, promptly, and changes nothing;
// an edit of a table behind its events is found by verify and stops approval and export.
// Also: passwords in every form libpq reads never reach the terminal, and names with
// control characters are shown escaped.
#include <sqlite3.h>

#include "../support/station_sessions.hpp"
#include "cli_support.hpp"

namespace {

class TrustCli : public Cli {
 protected:
  void SetUp() override {
    Cli::SetUp();
    original_ = dir_ / "station.sqlite";
    leafdig::db::Store s(original_.string());
    for (int leaf = 1; leaf <= 2; ++leaf) (void)leafdig::test::captureSession(s, "bench-a", leaf, 3);
  }
  // A copy of the station file with `statement` run on it by SQLite itself.
  fs::path crafted(const std::string& name, const std::string& statement) {
    const fs::path p = dir_ / name;
    fs::copy_file(original_, p, fs::copy_options::overwrite_existing);
    sqlite3* db = nullptr;
    EXPECT_EQ(sqlite3_open(p.c_str(), &db), SQLITE_OK);
    char* err = nullptr;
    EXPECT_EQ(sqlite3_exec(db, statement.c_str(), nullptr, nullptr, &err), SQLITE_OK) << (err ? err : "");
    sqlite3_free(err);
    sqlite3_close(db);
    return p;
  }
  static std::string scalar(const fs::path& file, const std::string& query) {
    sqlite3* db = nullptr;
    EXPECT_EQ(sqlite3_open_v2(file.c_str(), &db, SQLITE_OPEN_READONLY, nullptr), SQLITE_OK);
    sqlite3_stmt* st = nullptr;
    std::string out;
    if (sqlite3_prepare_v2(db, query.c_str(), -1, &st, nullptr) == SQLITE_OK && sqlite3_step(st) == SQLITE_ROW &&
        sqlite3_column_text(st, 0))
      out = reinterpret_cast<const char*>(sqlite3_column_text(st, 0));
    sqlite3_finalize(st);
    sqlite3_close(db);
    return out;
  }
  // Every command that opens a station file, on `file`: exit 2 naming `words`, within a
  // minute (a hang is a failure, not a timeout of the suite), the file unchanged.
  void expectEveryCommandRefuses(const fs::path& file, const std::string& words) {
    const std::string before = slurp(file);
    const std::string db = " --db " + quote(file);
    for (const std::string& command :
         {"sessions list" + db, "sessions show 1" + db, "sessions verify --all" + db,
          "sessions export 1 --out " + quote(dir_ / "out") + db, "sessions approve 2 --who cur" + db,
          "sessions correct 1 --what tip --position 1,2,3 --who cur --why x" + db,
          "sync push --to postgresql://nobody@127.0.0.1:1/x" + db,
          "sessions resume 1 --simulate" + db + " </dev/null"}) {
      const Result r = run("timeout -s KILL 60 " + quote(LEAFDIG_CLI) + " " + command);
      EXPECT_EQ(r.exitCode, 2) << command << "\n" << r.err;
      EXPECT_NE(r.err.find(words), std::string::npos) << command << "\n" << r.err;
      EXPECT_NE(r.err.find("not modified"), std::string::npos) << command << "\n" << r.err;
    }
    EXPECT_EQ(slurp(file), before) << "the file was changed";
    EXPECT_FALSE(fs::exists(dir_ / "out" / "session-1.glb"));
  }

  fs::path original_;
};

TEST_F(TrustCli, ATriggerAddedToTheFileIsNamedAndNeverFires) {
  const fs::path f = crafted(
      "trigger.sqlite",
      "CREATE TRIGGER evil AFTER INSERT ON events BEGIN UPDATE markers SET x_mm = x_mm + 100 WHERE session_id = "
      "NEW.session_id; INSERT INTO operators(name, role) VALUES ('pwned-' || NEW.seq, 'curator'); END;");
  const std::string x = scalar(f, "SELECT group_concat(x_mm) FROM markers WHERE session_id = 2");
  expectEveryCommandRefuses(f, "an extra trigger 'evil' on 'events'");
  EXPECT_EQ(scalar(f, "SELECT count(*) FROM operators WHERE name LIKE 'pwned-%'"), "0");
  EXPECT_EQ(scalar(f, "SELECT group_concat(x_mm) FROM markers WHERE session_id = 2"), x);
}

TEST_F(TrustCli, AViewThatShiftsMarkersIsNamed) {
  expectEveryCommandRefuses(
      crafted("view.sqlite",
              "ALTER TABLE markers RENAME TO markers_real; CREATE VIEW markers AS SELECT "
              "session_id, seq, what, row, col, x_mm + 50 AS x_mm, y_mm, z_mm FROM markers_real;"),
      "an extra view 'markers'");
}

TEST_F(TrustCli, AnEndlessViewHangsNothing) {
  expectEveryCommandRefuses(
      crafted("endless.sqlite",
              "ALTER TABLE sessions RENAME TO sessions_real; CREATE VIEW sessions AS WITH RECURSIVE n(i) AS (SELECT 1 "
              "UNION ALL SELECT i + 1 FROM n) SELECT s.* FROM sessions_real s, n;"),
      "an extra view 'sessions'");
  expectEveryCommandRefuses(
      crafted("endless-markers.sqlite",
              "ALTER TABLE markers RENAME TO m2; CREATE VIEW markers AS WITH RECURSIVE n(i) AS (SELECT 1 UNION ALL "
              "SELECT i + 1 FROM n) SELECT m.* FROM m2 m, n;"),
      "the table 'markers' is missing");
}

TEST_F(TrustCli, ASchemaVersionOfMinusOneOrZeroIsRefusedNotMigrated) {
  expectEveryCommandRefuses(crafted("minus.sqlite", "PRAGMA user_version = -1"), "schema version -1");
  expectEveryCommandRefuses(crafted("zero.sqlite", "PRAGMA user_version = 0"), "schema version 0 but holds tables");
}

TEST_F(TrustCli, DroppedAppendOnlyTriggersAndDeletedLeavesAreNamed) {
  expectEveryCommandRefuses(crafted("dropped.sqlite", "DROP TRIGGER events_no_update"),
                            "the trigger 'events_no_update' is missing");
  expectEveryCommandRefuses(crafted("orphans.sqlite", "PRAGMA foreign_keys = OFF; DELETE FROM leaves"),
                            "names a leaves row that is not there");
}

TEST_F(TrustCli, AMarkerMovedBehindItsEventIsFoundAndStopsApprovalAndExport) {
  const fs::path f = crafted("moved.sqlite",
                             "UPDATE markers SET x_mm = x_mm + 100 WHERE session_id = 2 AND row = 2 "
                             "AND col = 3");
  const std::string seq = scalar(f, "SELECT seq FROM markers WHERE session_id = 2 AND row = 2 AND col = 3");
  const Result verify = leafdig("sessions verify --all --db " + quote(f));
  EXPECT_EQ(verify.exitCode, 1) << verify.out << verify.err;
  EXPECT_NE(verify.out.find("session 1: "), std::string::npos);
  EXPECT_NE(verify.out.find("session 2: "), std::string::npos);
  EXPECT_NE(verify.out.find("CHAIN BROKEN at event " + seq + ": the markers table has marker row 2 col 3 of event " +
                            seq + " as (130.000"),
            std::string::npos)
      << verify.out;
  EXPECT_NE(verify.out.find("the file was changed after leafdig wrote it"), std::string::npos) << verify.out;
  // `show` says so, and shows the position the events hold.
  const json shown = json::parse(leafdig("sessions show 2 --json --db " + quote(f)).out);
  EXPECT_EQ(shown.at("chain_ok"), false);
  for (const auto& m : shown.at("markers"))
    if (m.at("row") == 2 && m.at("col") == 3) {
      EXPECT_DOUBLE_EQ(m.at("position_mm")[0].get<double>(), 30.0);
    }
  const std::string before = slurp(f);
  const Result approve = leafdig("sessions approve 2 --who cur --db " + quote(f));
  EXPECT_EQ(approve.exitCode, 2);
  EXPECT_NE(approve.err.find("fails 'sessions verify'"), std::string::npos) << approve.err;
  const Result exported = leafdig("sessions export 2 --out " + quote(dir_ / "out") + " --db " + quote(f));
  EXPECT_EQ(exported.exitCode, 2) << exported.err;
  EXPECT_FALSE(fs::exists(dir_ / "out" / "session-2.glb"));
  EXPECT_EQ(slurp(f), before);
  // The untouched session of the same file is still reviewed as usual.
  EXPECT_EQ(leafdig("sessions approve 1 --who cur --db " + quote(f)).exitCode, 0);
}

// A -wal beside the file is part of it (SQLite's rule): its content is checked like the
// file's, and a refusal leaves both as they were.
TEST_F(TrustCli, WhatAWalHoldsIsCheckedAndARefusalLeavesFileAndWalAsTheyWere) {
  const fs::path f = dir_ / "wal.sqlite";
  fs::copy_file(original_, f);
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(f.c_str(), &db), SQLITE_OK);
  ASSERT_EQ(sqlite3_db_config(db, SQLITE_DBCONFIG_NO_CKPT_ON_CLOSE, 1, nullptr), SQLITE_OK);
  ASSERT_EQ(sqlite3_exec(db,
                         "PRAGMA journal_mode=WAL; PRAGMA wal_autocheckpoint=0; UPDATE sessions SET status = "
                         "'approved' WHERE id = 2",
                         nullptr, nullptr, nullptr),
            SQLITE_OK);
  sqlite3_close(db);
  const fs::path wal = f.string() + "-wal";
  ASSERT_TRUE(fs::exists(wal));
  const std::string file = slurp(f), walBytes = slurp(wal);
  const Result verify = leafdig("sessions verify 2 --db " + quote(f));
  EXPECT_EQ(verify.exitCode, 1);
  EXPECT_NE(verify.out.find("the session's status is 'approved' but its events say 'complete'"), std::string::npos)
      << verify.out;
  const Result approve = leafdig("sessions reject 2 --who cur --why x --db " + quote(f));
  EXPECT_EQ(approve.exitCode, 2) << approve.err;
  EXPECT_EQ(slurp(f), file);
  EXPECT_EQ(slurp(wal), walBytes);
}

TEST_F(TrustCli, ModelBuildRefusesToWriteOverItsOwnInput) {
  const fs::path in = write("leaf.markers.json", slurp(sample("lower-leaf-n10.markers.json")));
  const std::string before = slurp(in);
  for (const std::string& args :
       {"--model-json " + quote(in), "-o " + quote(dir_ / "." / "leaf.markers.json"),
        "--model-json " + quote(dir_ / "m.json") + " -o " + quote(dir_ / "a.glb") + " -o " + quote(dir_ / "a.glb")}) {
    const Result r = leafdig("model build " + quote(in) + " " + args);
    EXPECT_EQ(r.exitCode, 2) << args << r.err;
    EXPECT_NE(r.err.find("is the same file as"), std::string::npos) << r.err;
  }
  EXPECT_EQ(slurp(in), before);
  EXPECT_FALSE(fs::exists(dir_ / "a.glb"));
  EXPECT_FALSE(fs::exists(dir_ / "m.json"));
}

TEST_F(TrustCli, APasswordIsNeverPrintedHoweverItIsWritten) {
  for (const std::string& url :
       {std::string("postgresql://tech@127.0.0.1:1/leafdig?pass%77ord=SECRET"),
        std::string("postgresql://tech@127.0.0.1:1/leafdig?sslpassword=SECRET&sslmode=disable"),
        std::string("host=127.0.0.1 port=1 user=tech password = SECRET dbname=leafdig"),
        std::string("postgresql://tech:SE%zzCRET@127.0.0.1:1/leafdig"),
        std::string("postgresql://tech:SECRET@127.0.0.1:1/leafdig?bogus=1")}) {
    for (const std::string& command : {"sync push --db " + quote(original_) + " --to " + quote(url),
                                       "sessions list --db " + quote(url), "server init --url " + quote(url)}) {
      const Result r = leafdig(command);
      EXPECT_NE(r.exitCode, 0) << command;
      EXPECT_EQ((r.out + r.err).find("CRET"), std::string::npos) << command << "\n" << r.out << r.err;
      EXPECT_FALSE(r.err.empty());
    }
  }
}

TEST_F(TrustCli, NamesWithControlCharactersArePrintedEscaped) {
  const fs::path f = crafted("names.sqlite",
                             "UPDATE plants SET name = 'P' || char(27) || ']0;pwned' || char(7) || char(27) || '[2J'; "
                             "UPDATE operators SET name = 'ana' || char(13) || char(0x202e) || 'evil'");
  const Result list = leafdig("sessions list --db " + quote(f));
  ASSERT_EQ(list.exitCode, 0) << list.err;
  EXPECT_EQ(list.out.find('\x1b'), std::string::npos) << list.out;
  EXPECT_EQ(list.out.find('\r'), std::string::npos) << list.out;
  EXPECT_EQ(list.out.find("\xe2\x80\xae"), std::string::npos) << list.out;
  EXPECT_NE(list.out.find("P\\x1b]0;pwned\\x07\\x1b[2J"), std::string::npos) << list.out;
  EXPECT_NE(list.out.find("ana\\r\\u{202e}evil"), std::string::npos) << list.out;
  const Result show = leafdig("sessions show 1 --db " + quote(f));
  EXPECT_EQ(show.out.find('\x1b'), std::string::npos) << show.out;
  // JSON keeps the name exactly (the JSON writer escapes it).
  const json listed = json::parse(leafdig("sessions list --json --db " + quote(f)).out);
  EXPECT_EQ(listed[0].at("plant"), "P\x1b]0;pwned\x07\x1b[2J");
}

}  // namespace
