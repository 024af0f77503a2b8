// Station files from someone else, through the command line (issue 25): a copy of a real
// station file with one statement added by sqlite3, as a technician could send it. Every
// command that opens it refuses it by name with exit code 2, promptly, and changes nothing;
// an edit of a table behind its events is found by verify and stops approval and export.
// Also: passwords in every form libpq reads never reach the terminal, and names with
// control characters are shown escaped.
#include <sqlite3.h>
#include <sys/stat.h>

#include <cmath>
#include <thread>

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

  // A plant session as a station writes it (station_sessions.hpp's events, under the shipped
  // tobacco protocol so that it replays), cut after its first `keep` events (all: -1), then
  // `extra` appended. Returns the file.
  fs::path plantFile(const std::string& name, long keep = -1, const std::vector<leafdig::db::EventInput>& extra = {}) {
    std::vector<leafdig::db::Event> events;
    {
      leafdig::db::Store s((dir_ / ("whole-" + name)).string());
      events = s.events(leafdig::test::capturePlantSession(s, "bench-a", "P-07", "tobacco-2026", "ana", false));
    }
    json settings{{"kind", "plant"}, {"engine", {{"still_mm", 0.5}}}};
    settings["protocol"] =
        json::parse(slurp(std::string(LEAFDIG_SOURCE_DIR) + "/data/protocols/tobacco.plant-protocol.json"));
    const fs::path f = dir_ / name;
    leafdig::db::Store s(f.string());
    const auto id = s.createPlantSession(s.ensurePlant(s.ensureProject("tobacco-2026"), "P-07"),
                                         s.ensureOperator("ana"), "bench-a", "standard", "sequential", settings.dump());
    const std::size_t n = keep < 0 ? events.size() : static_cast<std::size_t>(keep);
    for (std::size_t i = 0; i < n && i < events.size(); ++i) {
      leafdig::db::Event e = events[i];
      // The helper's landmarks lie on one line; around a pot's rim they make the plant's frame.
      json p = json::parse(e.payloadJson);
      if (e.kind == "accepted" && p.value("what", "") == "landmark") {
        const double a = 2.0944 * p.at("row").get<int>();
        p["position_mm"] = {100 * std::cos(a), 100 * std::sin(a), 20.0};
        e.payloadJson = p.dump();
      }
      (void)s.append(id, leafdig::db::changeOf(e));
    }
    for (const auto& e : extra) (void)s.append(id, e);
    return f;
  }

  // A leaf session as a station writes it (station_sessions.hpp) with its margin reading, so
  // that it builds and exports; complete.
  fs::path leafFile(const std::string& name) {
    const fs::path f = dir_ / name;
    leafdig::db::Store s(f.string());
    const auto id = leafdig::test::captureSession(s, "bench-a", 1, 3, "tobacco-2026", "P-07", "ana", false);
    leafdig::db::EventInput edge;
    edge.kind = "accepted";
    edge.payloadJson = R"({"what":"edge_thickness","row":null,"col":null,"value_mm":0.25})";
    edge.raw = "=HYPERLINK(\"http://x.example/\",\"open me\")\r";
    edge.projection =
        leafdig::db::changeOf(leafdig::db::Event{0, 0, "", 0, edge.kind, edge.payloadJson, edge.raw, "", ""})
            .projection;
    (void)s.append(id, edge);
    (void)s.setStatus(id, "complete", "ana", "all steps captured");
    return f;
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

// One output function for every writer (issue 47, 20): no command writes over a file it reads
// — the same file by inode, through a symlink or a second name, the station's own database
// among them — nor replaces what is not a regular file.
TEST_F(TrustCli, NoCommandWritesOverItsInputOrADevice) {
  const fs::path plant =
      write("p.plant-markers.json", slurp(std::string(LEAFDIG_SOURCE_DIR) + "/data/plants/sample.plant-markers.json"));
  const std::string before = slurp(plant);
  fs::create_symlink(plant, dir_ / "link.mtg");
  for (const std::string& args :
       {"--mtg " + quote(plant), "--csv " + quote(plant), "--mtg " + quote(dir_ / "link.mtg")}) {
    const Result r = leafdig("plant measure " + quote(plant) + " " + args);
    EXPECT_EQ(r.exitCode, 2) << args << "\n" << r.err;
    EXPECT_NE(r.err.find("a file this command reads"), std::string::npos) << args << "\n" << r.err;
  }
  EXPECT_EQ(slurp(plant), before);
  EXPECT_TRUE(fs::is_symlink(dir_ / "link.mtg"));
  // A FIFO (or a device) is never replaced by an output.
  ASSERT_EQ(::mkfifo((dir_ / "pipe.mtg").c_str(), 0600), 0);
  const Result fifo = leafdig("plant measure " + quote(plant) + " --mtg " + quote(dir_ / "pipe.mtg"));
  EXPECT_EQ(fifo.exitCode, 2) << fifo.err;
  EXPECT_NE(fifo.err.find("is not a regular file"), std::string::npos) << fifo.err;
  EXPECT_TRUE(fs::is_fifo(dir_ / "pipe.mtg"));
  // A plan built onto itself, a leaf whose markers file is named like the CARIBU export's
  // optical file beside it, two outputs of one command on one path.
  std::string planText = slurp(std::string(LEAFDIG_SOURCE_DIR) + "/data/plants/tobacco-p07.plant.json");
  for (std::size_t at; (at = planText.find("../samples/")) != std::string::npos;)
    planText.replace(at, 11, std::string(LEAFDIG_SOURCE_DIR) + "/data/samples/");
  const fs::path plan = write("p.plant.json", planText);
  const std::string planBefore = slurp(plan);
  const Result onPlan = leafdig("plant build " + quote(plan) + " -o " + quote(plan));
  EXPECT_EQ(onPlan.exitCode, 2) << onPlan.err;
  EXPECT_NE(onPlan.err.find("a file this command reads"), std::string::npos) << onPlan.err;
  EXPECT_EQ(slurp(plan), planBefore);
  const fs::path opt =
      write("leaf.opt", slurp(std::string(LEAFDIG_SOURCE_DIR) + "/data/samples/lower-leaf-n10.markers.json"));
  const std::string optBefore = slurp(opt);
  const Result onOpt = leafdig("model build " + quote(opt) + " -o " + quote(dir_ / "leaf.can"));
  EXPECT_EQ(onOpt.exitCode, 2) << onOpt.err;
  EXPECT_NE(onOpt.err.find("a file this command reads"), std::string::npos) << onOpt.err;
  EXPECT_EQ(slurp(opt), optBefore);
  const Result twice =
      leafdig("synth plant --markers " + quote(dir_ / "same.json") + " --truth " + quote(dir_ / "." / "same.json"));
  EXPECT_EQ(twice.exitCode, 2) << twice.err;
  EXPECT_NE(twice.err.find("name the same file"), std::string::npos) << twice.err;
  EXPECT_FALSE(fs::exists(dir_ / "same.json"));
  // `sessions export` into the folder of a station file named like one of its exports.
  const fs::path out = dir_ / "exports";
  fs::create_directories(out);
  fs::copy_file(leafFile("exportable.sqlite"), out / "session-1.glb");
  const std::string db = slurp(out / "session-1.glb");
  const Result e =
      leafdig("sessions export 1 --format glb --out " + quote(out) + " --db " + quote(out / "session-1.glb"));
  EXPECT_EQ(e.exitCode, 2) << e.err;
  EXPECT_NE(e.err.find("a file this command reads"), std::string::npos) << e.err;
  EXPECT_EQ(slurp(out / "session-1.glb"), db);
  // A station file that is a named pipe is refused at once, not waited on for ever.
  ASSERT_EQ(::mkfifo((dir_ / "pipe.sqlite").c_str(), 0600), 0);
  for (const std::string command : {"sessions list", "sessions verify --all", "plant surveys P-07"}) {
    const Result r =
        run("timeout -s KILL 60 " + quote(LEAFDIG_CLI) + " " + command + " --db " + quote(dir_ / "pipe.sqlite"));
    EXPECT_EQ(r.exitCode, 2) << command << "\n" << r.err;
    EXPECT_NE(r.err.find("is not a regular file"), std::string::npos) << command << "\n" << r.err;
  }
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

// A plant capture stopped early (issue 47, 17): a file holding only the first k events of a
// plant session — before any node, between nodes, a node with its leaf chosen but not taken —
// is shown and refused for export in words (exit 2, "holds no whole plant yet", the command
// that goes on with it), never a crash.
TEST_F(TrustCli, APlantCaptureStoppedEarlyIsShownAndNamedNeverACrash) {
  {
    const fs::path whole = plantFile("whole.sqlite");
    const Result r = leafdig("sessions export 1 --format mtg --out " + quote(dir_ / "whole") + " --db " + quote(whole));
    ASSERT_EQ(r.exitCode, 0) << "the uncut session must export: " << r.err;
  }
  for (const long k : {0L, 4L, 9L, 11L, 12L, 14L}) {
    const fs::path cut = plantFile("cut-" + std::to_string(k) + ".sqlite", k);
    const std::string db = " --db " + quote(cut);
    const Result show = run("timeout -s KILL 60 " + quote(LEAFDIG_CLI) + " sessions show 1" + db);
    EXPECT_EQ(show.exitCode, 0) << k << " events\n" << show.err;
    // Before the first node there is no plant; after it, the plant as far as it was taken
    // exports, or is named (a node whose leaf is chosen but not taken yet) — never a crash.
    for (const std::string format : {"mtg", "csv", "json", "glb"}) {
      const Result r = run("timeout -s KILL 60 " + quote(LEAFDIG_CLI) + " sessions export 1 --format " + format +
                           " --out " + quote(dir_ / ("out-" + std::to_string(k))) + db);
      if (k < 7 || r.exitCode != 0) {
        EXPECT_EQ(r.exitCode, 2) << k << " events, " << format << "\n" << r.err;
        EXPECT_NE(r.err.find("holds no whole plant yet"), std::string::npos) << k << " events\n" << r.err;
        EXPECT_NE(r.err.find("plant capture --resume 1"), std::string::npos) << k << " events\n" << r.err;
      }
    }
    const Result surveys = run("timeout -s KILL 60 " + quote(LEAFDIG_CLI) + " plant surveys P-07" + db);
    EXPECT_EQ(surveys.exitCode, 0) << k << " events\n" << surveys.err;
  }
}

// Text a spreadsheet would run (issue 47, 12): a reading's raw text starting with = + - @ is
// neutralised in the exported CSV (a leading apostrophe), so it reaches the curator as text.
TEST_F(TrustCli, ACsvCellThatLooksLikeAFormulaIsExportedAsText) {
  const fs::path f = leafFile("formula.sqlite");
  const Result r = leafdig("sessions export 1 --format csv --out " + quote(dir_ / "csv") + " --db " + quote(f));
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const std::string csv = slurp(dir_ / "csv" / "session-1.thickness.csv");
  ASSERT_FALSE(csv.empty());
  // Each line's cells, unquoted: none starts with = + - @ (the raw texts begin with '+').
  int neutralised = 0;
  std::istringstream lines(csv);
  for (std::string line; std::getline(lines, line);) {
    std::string cell;
    bool quoted = false;
    const auto check = [&] {
      if (!cell.empty()) {
        EXPECT_EQ(std::string("=+-@").find(cell.front()), std::string::npos) << line;
        if (cell.front() == '\'') ++neutralised;
      }
      cell.clear();
    };
    for (char c : line) {
      if (c == '"')
        quoted = !quoted;
      else if (c == ',' && !quoted)
        check();
      else
        cell += c;
    }
    check();
  }
  EXPECT_GE(neutralised, 7);  // six readings '+…', the margin's '=HYPERLINK(…)'
  EXPECT_NE(csv.find("'=HYPERLINK("), std::string::npos) << csv;
}

// A session's creation time is text from the file (issue 47, 11): `plant surveys` prints it
// escaped like every other such text, so it cannot set the curator's terminal title.
TEST_F(TrustCli, APlantSurveysDateCannotDriveTheTerminal) {
  const fs::path f = dir_ / "dates.sqlite";
  {
    leafdig::db::Store s(f.string());
    (void)leafdig::test::capturePlantSession(s, "bench-a");
  }
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(f.c_str(), &db), SQLITE_OK);
  ASSERT_EQ(sqlite3_exec(db, "UPDATE sessions SET created_utc = char(27) || ']0;pwned' || char(7) || '2026-06-12'",
                         nullptr, nullptr, nullptr),
            SQLITE_OK);
  sqlite3_close(db);
  const Result r = leafdig("plant surveys P-07 --db " + quote(f));
  EXPECT_EQ(r.out.find('\x1b'), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find('\x07'), std::string::npos) << r.out;
}

// Replay checks what every event says before it indexes anything (issue 47, 18): a leaf's
// marker at column 8 or -1, a plant's branch under a protocol that has none — written with a
// valid chain, as a station file edited by a program would be — are named by event, exit 2.
TEST_F(TrustCli, AnEventThatPointsOutsideTheLeafOrThePlantIsNamedNotFollowed) {
  const auto refused = [&](const fs::path& f, const std::string& words) {
    for (const std::string& command :
         {"sessions export 1 --out " + quote(dir_ / "x"), std::string("sessions show 1")}) {
      const Result r = run("timeout -s KILL 60 " + quote(LEAFDIG_CLI) + " " + command + " --db " + quote(f));
      EXPECT_EQ(r.exitCode, 2) << command << "\n" << r.err;
      EXPECT_NE(r.err.find(words), std::string::npos) << command << "\n" << r.err;
    }
  };
  for (const int col : {8, -1}) {
    const fs::path f = dir_ / ("col" + std::to_string(col) + ".sqlite");
    {
      leafdig::db::Store s(f.string());
      const auto id = leafdig::test::captureSession(s, "bench-a", 1, 3, "tobacco-2026", "P-07", "ana", false);
      leafdig::db::EventInput e;
      e.kind = "accepted";
      e.payloadJson = json{{"what", "marker"}, {"row", 2}, {"col", col}, {"position_mm", {1, 2, 3}}}.dump();
      (void)s.append(id, e);
      (void)s.setStatus(id, "complete", "ana", "");
    }
    refused(f, "where no marker is taken");
  }
  // A point taken "after move 3" of a transmitter that never moved.
  const fs::path framed = dir_ / "frame.sqlite";
  {
    leafdig::db::Store s(framed.string());
    const auto id = leafdig::test::captureSession(s, "bench-a", 1, 3, "tobacco-2026", "P-07", "ana", false);
    leafdig::db::EventInput e;
    e.kind = "accepted";
    e.payloadJson = json{{"what", "marker"}, {"row", 4}, {"col", 1}, {"position_mm", {1, 2, 3}}, {"frame", 3}}.dump();
    (void)s.append(id, e);
    (void)s.setStatus(id, "complete", "ana", "");
  }
  refused(framed, "names a move of the transmitter the session does not hold");
  leafdig::db::EventInput branch;
  branch.kind = "node_placed";
  branch.payloadJson = R"({"node":4,"parent":2,"relation":"+"})";
  refused(plantFile("branch.sqlite", -1, {branch}), "the plant's protocol has no branch");
}

// A session's settings that are not JSON, or hold a number beyond a double (issue 47, 3), are
// named — "settings cannot be read", exit 2 — never an internal error.
TEST_F(TrustCli, SettingsThatDoNotReadAreNamedNotAnInternalError) {
  for (const std::string& settings : {std::string("not json"), std::string(R"({"engine":{"still_mm":1e400}})"),
                                      std::string(R"({"engine":{"still_mm":1e300}})")}) {
    const fs::path f = dir_ / "settings.sqlite";
    fs::remove(f);
    {
      leafdig::db::Store s(f.string());
      const auto leaf = s.ensureLeaf(s.ensurePlant(s.ensureProject("p"), "P-1"), 1, "middle", std::nullopt);
      (void)s.createSession(leaf, s.ensureOperator("ana"), "bench-a", "standard", "sequential", settings);
    }
    for (const std::string& command :
         {std::string("sessions show 1"), "sessions export 1 --out " + quote(dir_ / "x")}) {
      const Result r = leafdig(command + " --db " + quote(f));
      EXPECT_EQ(r.exitCode, 2) << settings << ": " << command << "\n" << r.err;
      EXPECT_EQ(r.err.find("internal error"), std::string::npos) << r.err;
      EXPECT_NE(r.err.find("settings"), std::string::npos) << r.err;
    }
  }
}

// One station's session never hides another's surveys (issue 47, 10): a plant session that
// does not read (settings without a protocol, as a technician could push them) is listed as
// such, and the plant's other surveys still show.
TEST_F(TrustCli, APlantSessionThatDoesNotReadHidesNoOtherSurvey) {
  const fs::path f = plantFile("surveys.sqlite");
  {
    leafdig::db::Store s(f.string());
    (void)s.createPlantSession(s.ensurePlant(s.ensureProject("tobacco-2026"), "P-07"), s.ensureOperator("eve"),
                               "bench-b", "standard", "sequential", R"({"kind":"plant"})");
  }
  const Result r = leafdig("plant surveys P-07 --db " + quote(f));
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(r.out.find("2 survey(s)"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("3 nodes"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("does not read"), std::string::npos) << r.out;
  const json listed = json::parse(leafdig("plant surveys P-07 --json --db " + quote(f)).out);
  ASSERT_EQ(listed.at("surveys").size(), 2u);
}

// Corrections at the same time (issue 47, 19): four curators correct the same item of a plant
// at once; whichever land, each was worked out against the log it joins (a correction that
// finds the session moved on writes nothing and says so), so the session still reads.
TEST_F(TrustCli, CorrectionsAtTheSameTimeNeverBreakASession) {
  leafdig::db::EventInput done;
  done.kind = "status";
  done.payloadJson = R"({"status":"complete","who":"ana","why":"all steps captured"})";
  done.setsStatus = "complete";
  for (int round = 0; round < 3; ++round) {
    const fs::path f = plantFile("race-" + std::to_string(round) + ".sqlite", -1, {done});
    std::vector<std::thread> curators;
    std::vector<Result> results(4);
    for (int k = 0; k < 4; ++k)
      curators.emplace_back([&, k] {
        // Each its own output files (the fixture's run() shares one pair).
        const fs::path out = dir_ / ("out-" + std::to_string(k)), err = dir_ / ("err-" + std::to_string(k));
        const int status =
            std::system((quote(LEAFDIG_CLI) + " sessions correct 1 --what reading --row 2 --col 1 --value " +
                         std::to_string(10 + k) + " --who c" + std::to_string(k) + " --why race --db " + quote(f) +
                         " >" + quote(out) + " 2>" + quote(err))
                            .c_str());
        results[static_cast<std::size_t>(k)] = {WIFEXITED(status) ? WEXITSTATUS(status) : -1, slurp(out), slurp(err)};
      });
    for (auto& t : curators) t.join();
    int landed = 0;
    for (const Result& r : results) {
      if (r.exitCode == 0) {
        ++landed;
      } else {
        EXPECT_NE(r.err.find("moved on"), std::string::npos) << r.exitCode << ": " << r.err << r.out;
      }
    }
    EXPECT_GE(landed, 1);
    const Result verify = leafdig("sessions verify 1 --db " + quote(f));
    EXPECT_EQ(verify.exitCode, 0) << verify.out << verify.err;
    const Result show = leafdig("sessions show 1 --db " + quote(f));
    EXPECT_EQ(show.exitCode, 0) << show.err;
    const Result exported = leafdig("sessions export 1 --format mtg --out " +
                                    quote(dir_ / ("race" + std::to_string(round))) + " --db " + quote(f));
    EXPECT_EQ(exported.exitCode, 0) << exported.err;
  }
}

// A station file written before this leafdig (station schema 2: tests/data/legacy/) reads as
// it did — every session verifies, shows and exports — and `sessions verify` says which
// sessions were written before the station was in the chain (issue 47, 15).
TEST_F(TrustCli, AFileWrittenBeforeTheStationWasInTheChainStillReadsAndSaysSo) {
  const fs::path f = dir_ / "legacy.sqlite";
  fs::copy_file(std::string(LEAFDIG_SOURCE_DIR) + "/tests/data/legacy/station-schema2.sqlite", f);
  const Result verify = leafdig("sessions verify --all --db " + quote(f));
  ASSERT_EQ(verify.exitCode, 0) << verify.out << verify.err;
  EXPECT_NE(verify.out.find("chain OK (written before the station was in the chain"), std::string::npos) << verify.out;
  for (const auto& s : json::parse(leafdig("sessions list --json --db " + quote(f)).out)) {
    const std::string id = std::to_string(s.at("id").get<int>());
    const Result show = leafdig("sessions show " + id + " --db " + quote(f));
    EXPECT_EQ(show.exitCode, 0) << show.err;
    const Result exported =
        leafdig("sessions export " + id + " --out " + quote(dir_ / ("x" + id)) + " --db " + quote(f));
    EXPECT_EQ(exported.exitCode, 0) << exported.err;
  }
}

// A file whose chain was rewritten consistently (issue 47): what the events say must still be
// what could be — a move of the transmitter whose fit is not rigid (the landmarks taken again
// 100s of mm from where a rigid move puts them), a leaf type of 1 000 characters — named by
// replay, never taken.
TEST_F(TrustCli, AConsistentlyRewrittenFileStillCannotHoldWhatCannotBe) {
  const auto event = [](const std::string& kind, const json& payload) {
    leafdig::db::EventInput e;
    e.kind = kind;
    e.payloadJson = payload.dump();
    e.projection = leafdig::db::changeOf(leafdig::db::Event{0, 0, "", 0, e.kind, e.payloadJson, "", "", ""}).projection;
    return e;
  };
  std::vector<leafdig::db::EventInput> move{event("relocation", {{"relocation", 1}, {"step", "started"}})};
  const double far[3][3] = {{0, 0, 0}, {500, 0, 0}, {0, 900, 0}};
  for (int k = 1; k <= 3; ++k)
    move.push_back(event("accepted", {{"what", "landmark_again"},
                                      {"row", k},
                                      {"col", 1},
                                      {"position_mm", {far[k - 1][0], far[k - 1][1], far[k - 1][2]}},
                                      {"frame", 1}}));
  move.push_back(event("relocation", {{"relocation", 1}, {"step", "fitted"}, {"rms_mm", 0.3}, {"worst_mm", 0.4}}));
  const fs::path moved = plantFile("nonrigid.sqlite", 9, move);
  const std::vector<leafdig::db::EventInput> type{
      event("leaf_chosen", {{"node", 1}, {"kind", "none"}, {"state", "alive"}, {"type", std::string(1000, 't')}})};
  const fs::path typed = plantFile("type.sqlite", 8, type);
  for (const auto& [f, words] : std::vector<std::pair<fs::path, std::string>>{
           {moved, "the move's fit is not one a capture takes"}, {typed, "a leaf type is at most 64"}}) {
    const Result r = leafdig("sessions export 1 --format mtg --out " + quote(dir_ / "x") + " --db " + quote(f));
    EXPECT_EQ(r.exitCode, 2) << f << ": " << r.err;
    EXPECT_NE(r.err.find(words), std::string::npos) << f << ": " << r.err;
  }
}

// What a curator types is what is meant (issue 47, 23): column 0 is no column (it used to
// correct column 1), and a reason or a name of only spaces is none.
TEST_F(TrustCli, AColumnZeroOrABlankReasonOrNameIsRefused) {
  const fs::path f = leafFile("blank.sqlite");
  const std::string db = " --db " + quote(f);
  const std::size_t events = leafdig::db::Store(f.string()).events(1).size();
  for (const std::string& args :
       {std::string("sessions correct 1 --what marker --row 1 --col 0 --position 1,2,3 --who kim --why x"),
        std::string("sessions correct 1 --what marker --row 1 --col 1 --position 1,2,3 --who kim --why '   '"),
        std::string("sessions correct 1 --what marker --row 1 --col 1 --position 1,2,3 --who '  ' --why x"),
        std::string("sessions approve 1 --who '   '"), std::string("sessions reject 1 --who kim --why ' '")}) {
    const Result r = leafdig(args + db);
    EXPECT_EQ(r.exitCode, 2) << args << "\n" << r.err;
  }
  const Result list = leafdig("sessions list --json" + db);
  EXPECT_EQ(json::parse(list.out).at(0).at("status"), "complete");
  // Nothing was written: the session holds the events it held.
  EXPECT_EQ(leafdig::db::Store(f.string()).events(1).size(), events);
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
