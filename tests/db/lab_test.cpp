// The lab server against a real PostgreSQL cluster started for these tests (initdb +
// pg_ctl in a temporary directory, tests/support/pg_cluster.hpp): schema and roles, push and
// pull, the server's own checks of every chain, each role's refusals, hostile text, four
// stations at once beside a curator, and a connection cut in the middle of a transaction.
// The server is read back with libpq directly (test::Sql), not through leafdig's code.
#include "leafdig/db/lab.hpp"

#include <gtest/gtest.h>
#include <sqlite3.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <thread>
#include <tuple>

#include "../../db/src/lab_schema.hpp"
#include "../support/cutting_proxy.hpp"
#include "../support/pg_cluster_environment.hpp"
#include "../support/station_sessions.hpp"
#include "leafdig/acquisition/review/review.hpp"
#include "leafdig/db/event_rules.hpp"
#include "leafdig/db/history.hpp"
#include "leafdig/db/store.hpp"

namespace fs = std::filesystem;
namespace db = leafdig::db;
using leafdig::test::capturePlantSession;
using leafdig::test::captureSession;
using leafdig::test::PgCluster;
using leafdig::test::Sql;

namespace {

const auto* const kEnvironment = ::testing::AddGlobalTestEnvironment(new leafdig::test::PgClusterEnvironment);
PgCluster& clusterOf() {
  return leafdig::test::PgClusterEnvironment::cluster();
}

class Lab : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("leafdig-lab-" + std::to_string(::getpid()) + "-" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    database_ = clusterOf().createDatabase();
    admin_ = clusterOf().adminUrl(database_);
    (void)db::initServer(admin_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  // A login of the given role (a unique name per test), and its URL.
  std::string login(db::LabRole role, const std::string& station = "") {
    const std::string name = std::string(db::toString(role)) + "_" + database_ + "_" + std::to_string(++logins_);
    const std::string password = "pw \"" + name + "\" 's";
    (void)db::addUser(admin_, name, role, station, password);
    return clusterOf().url(name, password, database_);
  }
  std::string file(const std::string& name) const { return (dir_ / name).string(); }

  // Every event of every session on the server, by (station, station session id), as text.
  std::map<std::pair<std::string, std::int64_t>, std::vector<std::vector<std::string>>> serverEvents() {
    Sql sql(admin_);
    std::map<std::pair<std::string, std::int64_t>, std::vector<std::vector<std::string>>> out;
    for (auto& r :
         sql.rows("SELECT s.station, s.station_session_id, e.seq, e.utc, e.mono_ns, e.kind, e.payload_json, e.raw, "
                  "e.prev_hash, e.hash FROM leafdig.events e JOIN leafdig.sessions s ON s.id = e.session_id "
                  "ORDER BY s.station, s.station_session_id, e.seq"))
      out[{r[0], std::stoll(r[1])}].push_back(std::vector<std::string>(r.begin() + 2, r.end()));
    return out;
  }
  // The same from a station's file.
  static std::map<std::pair<std::string, std::int64_t>, std::vector<std::vector<std::string>>> fileEvents(
      const db::Store& s) {
    std::map<std::pair<std::string, std::int64_t>, std::vector<std::vector<std::string>>> out;
    for (const auto& info : s.sessions())
      for (const auto& e : s.events(info.id))
        out[{info.station, info.id}].push_back(
            {std::to_string(e.seq), e.utc, std::to_string(e.monoNs), e.kind, e.payloadJson, e.raw, e.prevHash, e.hash});
    return out;
  }

  // A session pushed by its station's technician: its server id and its id at the station.
  struct Pushed {
    std::string serverId;
    std::int64_t stationId = 0;
  };
  Pushed pushOne(db::Store& station, const std::string& stationName, const std::string& tech, bool complete = true) {
    const auto id = captureSession(station, stationName, static_cast<int>(station.sessions().size()) + 1, 2,
                                   "tobacco-2026", "P-07", "ana", complete);
    EXPECT_TRUE(db::push(station, tech).problems.empty());
    return {Sql(admin_).value("SELECT id FROM leafdig.sessions WHERE station = $1 AND station_session_id = $2",
                              {stationName, std::to_string(id)}),
            id};
  }
  // "carla (LOGIN)": how leafdig signs a review written through the curator login at `url`
  // (lab schema 11: a review names the login that writes it).
  static std::string carlaAt(const std::string& url) { return "carla (" + Sql(url).value("SELECT session_user") + ")"; }
  // Appends one event to a server session through plain SQL as the login of `sql`, chained
  // exactly right (the server's own head and hash): "" when the server takes it, else its words.
  std::string appendBySql(Sql&& sql, const Pushed& s, const std::string& station, const std::string& kind,
                          const std::string& payload) {
    Sql admin(admin_);
    const auto head = admin.rows("SELECT head_seq, head_hash FROM leafdig.sessions WHERE id = $1", {s.serverId});
    const std::int64_t seq = std::stoll(head[0][0]) + 1;
    const std::string utc = "2026-11-25T10:00:00.000Z";
    const std::string hash = db::eventHash(head[0][1], s.stationId, seq, utc, 7, kind, payload, "");
    return sql.error(
        "INSERT INTO leafdig.events(session_id, station, seq, utc, mono_ns, kind, payload_json, raw, prev_hash, hash) "
        "VALUES ($1, $2, $3, $4, 7, $5, $6, '', $7, $8)",
        {s.serverId, station, std::to_string(seq), utc, kind, payload, head[0][1], hash});
  }
  std::string appendBySql(Sql& sql, const Pushed& s, const std::string& station, const std::string& kind,
                          const std::string& payload) {
    return appendBySql(std::move(sql), s, station, kind, payload);
  }
  std::string statusOf(const Pushed& s) {
    return Sql(admin_).value("SELECT status FROM leafdig.sessions WHERE id = $1", {s.serverId});
  }

  fs::path dir_;
  std::string database_, admin_;
  int logins_ = 0;
};

TEST(LabUrl, PasswordsAreRedactedInEveryForm) {
  EXPECT_EQ(db::redactUrl("postgresql://tech:s3cret@lab.example:5432/leafdig"),
            "postgresql://tech:***@lab.example:5432/leafdig");
  EXPECT_EQ(db::redactUrl("postgres://tech@lab/leafdig?sslmode=verify-full&password=s3cret&connect_timeout=5"),
            "postgres://tech:***@lab/leafdig?connect_timeout=5&sslmode=verify-full");
  EXPECT_EQ(db::redactUrl("host=lab user=tech password='a b' dbname=leafdig"),
            "user=tech password=*** dbname=leafdig host=lab");
  EXPECT_EQ(db::redactUrl("postgresql://lab/leafdig"), "postgresql://lab/leafdig");
  EXPECT_TRUE(db::isServerUrl("postgresql://lab/x"));
  EXPECT_FALSE(db::isServerUrl("/home/ana/station.sqlite"));
  EXPECT_EQ(db::redactUrl("/home/ana/station.sqlite"), "/home/ana/station.sqlite");
  // Every way of writing a password that libpq reads (issue 25): a %-escaped key, the TLS
  // key's password, spaces around '=', and a URL libpq cannot read at all.
  for (const std::string& url : {std::string("postgresql://tech@lab/leafdig?pass%77ord=SECRET"),
                                 std::string("postgresql://tech@lab/leafdig?sslpassword=SECRET&sslmode=require"),
                                 std::string("host=lab user=tech password = SECRET dbname=leafdig"),
                                 std::string("postgresql://tech:SE%zzCRET@lab/leafdig"),
                                 std::string("postgresql://tech:SE%2FCRET@lab/x"), std::string("password = 'SECRET")}) {
    const std::string shown = db::redactUrl(url);
    EXPECT_EQ(shown.find("SECRET"), std::string::npos) << url << " -> " << shown;
    EXPECT_EQ(shown.find("CRET"), std::string::npos) << url << " -> " << shown;
  }
}

// Every released migration stays as it was released (db/migrations/lab/, embedded at build
// time): a lab server upgraded by one leafdig and another must hold the same schema. A new
// version is a new file, and its hash goes here when it is released.
TEST(LabMigrations, EveryReleasedMigrationIsUnchanged) {
  const std::vector<std::string> released{
      "6732c03006cf76eeef446962de4c72462b9744e596e747a9146c5e45aacbfa13",  // 0001
      "8ecc4126b26bcdea5050aaaea3717d3ea46f3375c2a1bf7aaa274de56e6344eb",  // 0002
      "b86b59cb0e04ffccc1a3347a4845e30625738111bdc2737460b20831068235db",  // 0003
      "92bf22dc341920c87dfe488dcf303d5d2bdc84196c2c6f49317f6ef0aff6cc0c",  // 0004
      "d0016ff24b30843276ecfbd7d4bcf48ea8d8c00cd437dd5a3e91c875496d39ee",  // 0005
      "51f3af3dc06479d64c8ddf9100615fc1297f9ec014f8b6f359ca13988ac34f47",  // 0006
      "ac32df003fa1d414bed3515b9ff0656e888b450c9c86404ae139c50f1641dec1",  // 0007
      "0786312ab8763a21144a2b93bcd4671359c5dcebef05ffad89ecbd7c992fba2c",  // 0008
      "b934f01484b148b2ec6c320f671659304fcf8bedc35216d3d02bc14b660fc0d7",  // 0009
      "ae225bd13bad4804c897e4430538e49163ed29f1eac68a23bd5971f38e09aba3",  // 0010
      "37a101574c88b9e474dc1ecc36aacadb7c472b4db1d9a24285046226b9ea4129",  // 0011
      "5d8b9c86e5207bf4978f0513dfbcef68bf8252fd5e129cdd5d3524bddd675bcb",  // 0012
  };
  ASSERT_EQ(db::detail::kLabMigrations.size(), static_cast<std::size_t>(db::kLabSchemaVersion));
  ASSERT_GE(db::detail::kLabMigrations.size(), released.size());
  for (std::size_t v = 0; v < released.size(); ++v)
    EXPECT_EQ(db::sha256Hex(db::detail::kLabMigrations[v]), released[v])
        << "migration " << v + 1 << " was edited after it was released: undo the edit and add the next file";
  // The files in the source tree are the ones embedded, numbered without a gap.
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(fs::path(LEAFDIG_SOURCE_DIR) / "db/migrations/lab"))
    files.push_back(e.path());
  std::sort(files.begin(), files.end());
  ASSERT_EQ(files.size(), db::detail::kLabMigrations.size());
  for (std::size_t v = 0; v < files.size(); ++v) {
    char number[24];  // room for any size_t: GCC 12 -Wformat-truncation counts 20 digits
    std::snprintf(number, sizeof number, "%04zu_", v + 1);
    EXPECT_EQ(files[v].filename().string().rfind(number, 0), 0u) << files[v];
    std::ifstream in(files[v], std::ios::binary);
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    EXPECT_EQ(text, db::detail::kLabMigrations[v]) << files[v];
  }
}

TEST(LabText, StationIdsAndUtf8AreChecked) {
  EXPECT_NO_THROW(db::checkStationId("greenhouse-2.lab_A"));
  for (const std::string& bad : std::vector<std::string>{"", "-x", "a b", "a'b", std::string(65, 'a'), "\xc3\xa9"})
    EXPECT_THROW(db::checkStationId(bad), db::StoreError) << bad;
  EXPECT_FALSE(db::badTextByte("Blattstiel \xc3\xa9 \xe2\x80\x94 \xf0\x9f\x8c\xbf"));
  EXPECT_EQ(db::badTextByte("ok\xff"), 2u);
  EXPECT_EQ(db::badTextByte(std::string("nul\0x", 5)), 3u);
  EXPECT_EQ(db::badTextByte("\xc0\xaf"), 0u);      // overlong '/'
  EXPECT_EQ(db::badTextByte("\xed\xa0\x80"), 0u);  // a surrogate
  EXPECT_EQ(db::badTextByte("cut \xe2\x80"), 4u);
}

TEST_F(Lab, InitCreatesTheSchemaAndTheThreeRolesAndAgainChangesNothing) {
  Sql sql(admin_);
  EXPECT_EQ(sql.value("SELECT value FROM leafdig.meta WHERE key = 'schema_version'"),
            std::to_string(db::kLabSchemaVersion));
  for (const char* role : {"leafdig_technicians", "leafdig_curators", "leafdig_readers"})
    EXPECT_EQ(sql.value("SELECT rolcanlogin::text FROM pg_roles WHERE rolname = $1", {role}), "false") << role;
  const auto again = db::initServer(admin_);
  EXPECT_EQ(again.fromVersion, db::kLabSchemaVersion);
  EXPECT_EQ(again.toVersion, db::kLabSchemaVersion);
  EXPECT_TRUE(again.rolesCreated.empty());
  // A database that does not keep UTF-8 is refused, named.
  sql.rows("CREATE DATABASE ascii_" + database_ +
           " ENCODING 'SQL_ASCII' TEMPLATE template0 LC_COLLATE 'C' LC_CTYPE 'C'");
  try {
    (void)db::initServer(clusterOf().adminUrl("ascii_" + database_));
    FAIL() << "initialised a SQL_ASCII database";
  } catch (const db::StoreError& e) {
    EXPECT_NE(std::string(e.what()).find("not UTF-8"), std::string::npos) << e.what();
  }
  // A store that was never initialised is named as such.
  try {
    db::LabStore store(clusterOf().adminUrl("postgres"));
    FAIL();
  } catch (const db::StoreError& e) {
    EXPECT_EQ(e.kind(), db::StoreErrorKind::NotLeafdig);
    EXPECT_NE(e.remedy().find("server init"), std::string::npos);
  }
}

TEST_F(Lab, APushSendsEveryEventExactlyAndASecondPushSendsNothing) {
  db::Store station(file("a.sqlite"));
  for (int leaf = 1; leaf <= 3; ++leaf) (void)captureSession(station, "bench-a", leaf, 2 + leaf);
  const std::string tech = login(db::LabRole::Technician, "bench-a");
  db::SyncOptions small;
  small.eventsPerTransaction = 7;  // several transactions per session
  const auto first = db::push(station, tech, small);
  EXPECT_TRUE(first.problems.empty()) << first.problems.front().problem;
  EXPECT_EQ(first.sessionsNew, 3);
  std::int64_t events = 0;
  for (const auto& s : station.sessions()) events += s.headSeq;
  EXPECT_EQ(first.eventsSent, events);
  EXPECT_GT(first.transactions, 3);
  EXPECT_EQ(serverEvents(), fileEvents(station));

  const auto second = db::push(station, tech);
  EXPECT_EQ(second.eventsSent, 0);
  EXPECT_EQ(second.sessionsUpToDate, 3);
  EXPECT_EQ(serverEvents(), fileEvents(station));

  // The server as a store: the same sessions, chains that verify, projections from the events.
  db::LabStore server(login(db::LabRole::Reader));
  const auto sessions = server.sessions();
  ASSERT_EQ(sessions.size(), 3u);
  for (const auto& s : sessions) {
    EXPECT_EQ(s.station, "bench-a");
    const auto local = station.session(s.stationSessionId);
    ASSERT_TRUE(local);
    EXPECT_EQ(s.project, local->project);
    EXPECT_EQ(s.leafPosition, local->leafPosition);
    EXPECT_EQ(s.measuredAreaMm2, local->measuredAreaMm2);
    EXPECT_EQ(s.status, "complete");
    EXPECT_EQ(s.headHash, local->headHash);
    EXPECT_TRUE(server.verify(s.id).ok) << server.verify(s.id).problem;
    EXPECT_EQ(server.markers(s.id).size(), station.markers(local->id).size());
    EXPECT_EQ(server.thickness(s.id).size(), station.thickness(local->id).size());
  }
  // New events on the station go on their own.
  const auto id = captureSession(station, "bench-a", 4);
  const auto third = db::push(station, tech);
  EXPECT_EQ(third.sessionsNew, 1);
  EXPECT_EQ(third.eventsSent, station.session(id)->headSeq);
  EXPECT_EQ(serverEvents(), fileEvents(station));
}

TEST_F(Lab, APlantSessionGoesToTheServerWholeAndACuratorsDecisionComesBack) {
  db::Store station(file("a.sqlite"));
  (void)captureSession(station, "bench-a", 1, 3);
  const auto plant = capturePlantSession(station, "bench-a");
  const std::string tech = login(db::LabRole::Technician, "bench-a");
  const auto pushed = db::push(station, tech);
  EXPECT_TRUE(pushed.problems.empty()) << pushed.problems[0].problem;
  EXPECT_EQ(pushed.sessionsNew, 2);
  EXPECT_EQ(serverEvents(), fileEvents(station));
  Sql admin(admin_);
  const auto row = admin.rows(
      "SELECT id, kind, leaf_position, leaf_type, measured_area_mm2 IS NULL, status FROM leafdig.sessions WHERE "
      "station = 'bench-a' AND station_session_id = $1",
      {std::to_string(plant)});
  ASSERT_EQ(row.size(), 1U);
  EXPECT_EQ(row[0][1], "plant");
  EXPECT_EQ(row[0][2], "0");
  EXPECT_EQ(row[0][3], "");
  EXPECT_EQ(row[0][4], "t");
  EXPECT_EQ(row[0][5], "complete");
  EXPECT_EQ(admin.value("SELECT kind FROM leafdig.sessions WHERE station_session_id = 1"), "leaf");
  // The server reads it as a plant session, its chain whole.
  db::LabStore reader(login(db::LabRole::Reader));
  const std::int64_t serverId = std::stoll(row[0][0]);
  EXPECT_EQ(reader.session(serverId)->kind, "plant");
  EXPECT_TRUE(reader.verify(serverId).ok);
  const Pushed s{row[0][0], plant};
  // A correction of the plant's landmark 1: a technician's by plain SQL is refused, a curator's
  // taken (the projection holds it), and it comes back to the station with the approval.
  db::MarkerRow landmark;
  for (const db::MarkerRow& m : reader.markers(serverId))
    if (m.what == "landmark" && m.row == 1) landmark = m;
  ASSERT_GT(landmark.seq, 0);
  nlohmann::json fix{{"what", "landmark"},
                     {"row", 1},
                     {"col", nullptr},
                     {"seq", landmark.seq},
                     {"position_mm", {landmark.positionMm[0], landmark.positionMm[1], landmark.positionMm[2]}},
                     {"reason", "taken off the rim"},
                     {"who", "carla"}};
  fix["corrected"] = {{"what", "landmark"}, {"row", 1}, {"col", nullptr}, {"position_mm", {411.5, 201.5, -375.0}}};
  const std::string byTech = appendBySql(Sql(tech), s, "bench-a", "corrected", fix.dump());
  EXPECT_NE(byTech.find("only curators review"), std::string::npos) << byTech;
  nlohmann::json notAnItem = fix;
  notAnItem["corrected"]["what"] = "stem";
  EXPECT_NE(appendBySql(Sql(login(db::LabRole::Curator)), s, "bench-a", "corrected", notAnItem.dump())
                .find("lacks the corrected item"),
            std::string::npos);
  const std::string curator = login(db::LabRole::Curator);
  fix["who"] = carlaAt(curator);
  EXPECT_EQ(appendBySql(Sql(curator), s, "bench-a", "corrected", fix.dump()), "");
  int landmarks1 = 0;
  for (const db::MarkerRow& m : reader.markers(serverId))
    if (m.what == "landmark" && m.row == 1) {
      ++landmarks1;
      EXPECT_EQ(m.positionMm, (std::array<double, 3>{411.5, 201.5, -375.0}));
    }
  EXPECT_EQ(landmarks1, 1);
  // A curator's approval by plain SQL comes back to the station.
  EXPECT_EQ(
      appendBySql(Sql(curator), s, "bench-a", "status",
                  nlohmann::json{{"status", "approved"}, {"who", carlaAt(curator)}, {"why", "a whole plant"}}.dump()),
      "");
  const auto pulled = db::pull(station, tech);
  EXPECT_TRUE(pulled.problems.empty());
  EXPECT_EQ(pulled.eventsTaken, 2);
  EXPECT_EQ(station.session(plant)->status, "approved");
  for (const db::MarkerRow& m : station.markers(plant)) {
    if (m.what == "landmark" && m.row == 1) {
      EXPECT_EQ(m.positionMm, (std::array<double, 3>{411.5, 201.5, -375.0}));
    }
  }
  EXPECT_TRUE(station.verify(plant).ok);
  EXPECT_EQ(serverEvents(), fileEvents(station));
}

TEST_F(Lab, AServerBeforePlantSessionsLeavesThemOnTheStationNamedAndTheLeafSessionsStillGo) {
  db::Store station(file("a.sqlite"));
  (void)captureSession(station, "bench-a", 1, 3);
  const auto plant = capturePlantSession(station, "bench-a");
  (void)captureSession(station, "bench-a", 2, 3);
  (void)Sql(admin_).value("UPDATE leafdig.meta SET value = '2' WHERE key = 'schema_version' RETURNING value");
  const auto pushed = db::push(station, login(db::LabRole::Technician, "bench-a"));
  EXPECT_EQ(pushed.sessionsNew, 2);
  ASSERT_EQ(pushed.problems.size(), 1U);
  EXPECT_EQ(pushed.problems[0].stationSessionId, plant);
  EXPECT_NE(pushed.problems[0].problem.find("is a plant session and the lab server (schema 2)"), std::string::npos)
      << pushed.problems[0].problem;
  EXPECT_NE(pushed.problems[0].remedy.find("leafdig server init"), std::string::npos);
  EXPECT_EQ(Sql(admin_).value("SELECT count(*) FROM leafdig.sessions"), "2");
  EXPECT_EQ(station.session(plant)->kind, "plant");  // untouched
}

TEST_F(Lab, APlantSessionsRetakesWaitForASchema4ServerAndThenGoWhole) {
  db::Store station(file("a.sqlite"));
  const auto plant = capturePlantSession(station, "bench-a", "P-09", "tobacco-2026", "ana", /*complete=*/false);
  // Landmark 2 (event 2) retaken, put back, retaken and taken again, as the station writes them.
  const auto append = [&](const std::string& kind, const std::string& payload) {
    db::EventInput e;
    e.kind = kind;
    e.payloadJson = payload;
    e.monoNs = 900000;
    const db::EventInput change = db::changeOf(db::Event{0, 0, "", 0, e.kind, e.payloadJson, e.raw, "", ""});
    e.projection = change.projection;
    e.retracts = change.retracts;
    return station.append(plant, e);
  };
  const std::string item = R"("what":"landmark","row":2,"col":null,"position_mm":)";
  (void)append("retake", "{" + item + R"([200.0,1.0,20.0],"seq":2})");
  const auto back = append("retake_cancelled", "{" + item + "[200.0,1.0,20.0]}");
  (void)append("retake", "{" + item + R"([200.0,1.0,20.0],"seq":)" + std::to_string(back) + "}");
  (void)append("accepted", "{" + item + "[201.5,1.0,20.0]}");
  ASSERT_TRUE(station.verify(plant).ok);
  const std::string tech = login(db::LabRole::Technician, "bench-a");
  // A schema 3 server would refuse the retakes half-way: the session stays here, whole, named.
  (void)Sql(admin_).value("UPDATE leafdig.meta SET value = '3' WHERE key = 'schema_version' RETURNING value");
  auto pushed = db::push(station, tech);
  ASSERT_EQ(pushed.problems.size(), 1U);
  EXPECT_NE(pushed.problems[0].problem.find("plant session with retakes and the lab server (schema 3)"),
            std::string::npos)
      << pushed.problems[0].problem;
  EXPECT_NE(pushed.problems[0].remedy.find("leafdig server init"), std::string::npos);
  EXPECT_EQ(Sql(admin_).value("SELECT count(*) FROM leafdig.sessions"), "0");
  // Upgraded, it goes, and the server's projection holds landmark 2 once, the new one.
  (void)Sql(admin_).value("UPDATE leafdig.meta SET value = '4' WHERE key = 'schema_version' RETURNING value");
  pushed = db::push(station, tech);
  EXPECT_TRUE(pushed.problems.empty()) << pushed.problems[0].problem;
  db::LabStore reader(login(db::LabRole::Reader));
  const std::int64_t serverId = reader.sessions().at(0).id;
  EXPECT_TRUE(reader.verify(serverId).ok);
  int landmark2 = 0;
  for (const db::MarkerRow& m : reader.markers(serverId))
    if (m.what == "landmark" && m.row == 2) {
      ++landmark2;
      EXPECT_EQ(m.positionMm[0], 201.5);
    }
  EXPECT_EQ(landmark2, 1);
}

// Schema 7 (issue 29): a leaf's transmitter moved — `relocation` and its board points taken
// again, by plain SQL as a technician; what is not one of them, refused by name.
TEST_F(Lab, ALeafSessionTakesAMoveOfTheTransmitterAndItsBoardPointsAgainBySql) {
  db::Store station(file("a.sqlite"));
  const std::string tech = login(db::LabRole::Technician, "bench-a");
  const Pushed leaf = pushOne(station, "bench-a", tech, /*complete=*/false);
  Sql asTech(tech);
  for (const auto& [kind, payload] : std::vector<std::pair<std::string, std::string>>{
           {"relocation", R"({"relocation":1,"step":"started"})"},
           {"accepted", R"({"what":"board_again","row":1,"col":1,"position_mm":[-130,20,-26],"frame":1})"},
           {"accepted", R"({"what":"board_again","row":1,"col":2,"position_mm":[100,-160,-26],"frame":1})"},
           {"accepted", R"({"what":"board_again","row":1,"col":3,"position_mm":[50,250,-50],"frame":1})"},
           {"relocation", R"({"relocation":1,"step":"fitted","rms_mm":0.1,"worst_mm":0.2})"},
           {"accepted", R"({"what":"marker","row":3,"col":1,"position_mm":[160,110,5],"frame":1})"},
           {"accepted", R"({"what":"midrib_thickness","row":1,"col":4,"value_mm":1.2})"}})
    EXPECT_EQ(appendBySql(asTech, leaf, "bench-a", kind, payload), "") << kind << " " << payload;
  for (const auto& [event, words] : std::vector<std::pair<std::pair<std::string, std::string>, std::string>>{
           {{"relocation", R"({"relocation":0,"step":"started"})"}, "not a move of the transmitter"},
           {{"relocation", R"({"relocation":1,"step":"moved"})"}, "not a move of the transmitter"},
           {{"relocation", R"({"relocation":"1","step":"started"})"}, "not a move of the transmitter"},
           {{"relocation", "[1]"}, "not a JSON object"},
           {{"relocation", "{"}, "not JSON"},
           {{"accepted", R"({"what":"board_again","row":1,"col":4,"position_mm":[1,2,3]})"}, "not an item"},
           {{"accepted", R"({"what":"board_again","row":0,"col":1,"position_mm":[1,2,3]})"}, "not an item"},
           {{"accepted", R"({"what":"board_again","row":1,"col":1,"value_mm":3})"}, "not an item"},
           {{"accepted", R"({"what":"marker","row":3,"col":2,"position_mm":[1,2,3],"frame":"1"})"}, "not an item"},
           {{"accepted", R"({"what":"marker","row":3,"col":2,"position_mm":[1,2,3],"frame":-1})"}, "not an item"},
           {{"accepted", R"({"what":"marker","row":3,"col":2,"position_mm":[1,2,3],"frame":1000})"}, "not an item"},
           {{"retake_cancelled", R"({"what":"board_again","row":1,"col":2})"}, "not an item"}}) {
    const std::string refused = appendBySql(asTech, leaf, "bench-a", event.first, event.second);
    EXPECT_NE(refused.find(words), std::string::npos) << event.first << " " << event.second << ": " << refused;
  }
  // A curator adds no capture event to a leaf either.
  EXPECT_NE(appendBySql(Sql(login(db::LabRole::Curator)), leaf, "bench-a", "relocation",
                        R"({"relocation":2,"step":"started"})")
                .find("only the station's technician pushes them"),
            std::string::npos);
  // Schema 8: once complete, a curator corrects a board point taken again by plain SQL — the
  // item it names, no other, and a well-formed one; a technician does not.
  EXPECT_EQ(appendBySql(asTech, leaf, "bench-a", "status", R"({"status":"complete"})"), "");
  const std::string again = Sql(admin_).value(
      "SELECT seq FROM leafdig.events WHERE session_id = $1 AND payload_json::jsonb ->> 'what' = 'board_again' "
      "AND payload_json::jsonb ->> 'col' = '2'",
      {leaf.serverId});
  nlohmann::json fix = nlohmann::json::parse(R"({"what":"board_again","row":1,"col":2,"position_mm":[100,-160,-26]})");
  fix["frame"] = 1;
  fix["seq"] = std::stoll(again);
  fix["reason"] = "pressed on a crumb";
  fix["who"] = "carla";
  fix["corrected"] = {{"what", "board_again"}, {"row", 1}, {"col", 2}, {"position_mm", {100, -160, -24}}, {"frame", 1}};
  EXPECT_NE(appendBySql(asTech, leaf, "bench-a", "corrected", fix.dump()).find("only curators review"),
            std::string::npos);
  for (const auto& [key, value] : std::vector<std::pair<std::string, nlohmann::json>>{
           {"col", 3}, {"row", 2}, {"what", "board"}, {"position_mm", {1, 2}}, {"frame", "1"}}) {
    nlohmann::json bad = fix;
    bad["corrected"][key] = value;
    EXPECT_NE(appendBySql(Sql(login(db::LabRole::Curator)), leaf, "bench-a", "corrected", bad.dump()), "")
        << key << " " << value;
  }
  const std::string carla = login(db::LabRole::Curator);
  fix["who"] = carlaAt(carla);
  EXPECT_EQ(appendBySql(Sql(carla), leaf, "bench-a", "corrected", fix.dump()), "");
  db::LabStore reader(login(db::LabRole::Reader));
  EXPECT_TRUE(reader.verify(std::stoll(leaf.serverId)).ok);
  // Through leafdig, a correction and the points it moves go in one transaction: one the
  // server refuses (here a marker "corrected" into another row) leaves none of them in.
  const std::string marker = Sql(admin_).value(
      "SELECT seq FROM leafdig.events WHERE session_id = $1 AND payload_json::jsonb ->> 'what' = 'marker' "
      "AND payload_json::jsonb ->> 'row' = '3' AND payload_json::jsonb ->> 'col' = '1' AND kind = 'accepted'",
      {leaf.serverId});
  // The board point is now held by the curator's correction, the session's last event.
  const std::string head = Sql(admin_).value("SELECT head_seq FROM leafdig.sessions WHERE id = $1", {leaf.serverId});
  db::LabStore curator(login(db::LabRole::Curator));
  const auto correction = [&](const std::string& seq, nlohmann::json old, nlohmann::json fixed) {
    old["seq"] = std::stoll(seq);
    old["corrected"] = std::move(fixed);
    old["reason"] = "refit";
    old["who"] = curator.signature("carla");
    db::EventInput e;
    e.kind = "corrected";
    e.payloadJson = old.dump();
    return e;
  };
  const nlohmann::json oldMarker =
      nlohmann::json::parse(R"({"what":"marker","row":3,"col":1,"position_mm":[160,110,5],"frame":1})");
  nlohmann::json movedMarker = oldMarker;
  movedMarker["position_mm"] = {160, 110, 6};
  nlohmann::json wrongRow = movedMarker;
  wrongRow["row"] = 4;
  nlohmann::json board = fix["corrected"];
  nlohmann::json boardAgain = board;
  boardAgain["position_mm"] = {100, -160, -25};
  const std::string corrections = "SELECT count(*) FROM leafdig.events WHERE session_id = $1 AND kind = 'corrected'";
  EXPECT_THROW((void)curator.appendAll(std::stoll(leaf.serverId),
                                       {correction(head, board, boardAgain), correction(marker, oldMarker, wrongRow)}),
               db::StoreError);
  EXPECT_EQ(Sql(admin_).value(corrections, {leaf.serverId}), "1");
  EXPECT_EQ(Sql(admin_).value("SELECT head_seq FROM leafdig.sessions WHERE id = $1", {leaf.serverId}), head);
  const auto last = curator.appendAll(
      std::stoll(leaf.serverId), {correction(head, board, boardAgain), correction(marker, oldMarker, movedMarker)});
  EXPECT_EQ(last, std::stoll(head) + 2);
  EXPECT_EQ(Sql(admin_).value(corrections, {leaf.serverId}), "3");
  EXPECT_TRUE(reader.verify(std::stoll(leaf.serverId)).ok);
}

// A leaf session with a moved transmitter waits on the station for a schema 7 server.
TEST_F(Lab, ALeafSessionsMovedTransmitterWaitsForASchema7ServerAndThenGoesWhole) {
  db::Store station(file("a.sqlite"));
  const auto id = captureSession(station, "bench-a", 1, 3, "tobacco-2026", "P-07", "ana", /*complete=*/false);
  db::EventInput e;
  e.kind = "relocation";
  e.payloadJson = R"({"relocation":1,"step":"started"})";
  e.monoNs = 900000;
  (void)station.append(id, e);
  const std::string tech = login(db::LabRole::Technician, "bench-a");
  (void)Sql(admin_).value("UPDATE leafdig.meta SET value = '6' WHERE key = 'schema_version' RETURNING value");
  auto pushed = db::push(station, tech);
  ASSERT_EQ(pushed.problems.size(), 1U);
  EXPECT_NE(pushed.problems[0].problem.find("is a leaf session with a moved transmitter and the lab server (schema 6) "
                                            "does not take a leaf's moved transmitter yet"),
            std::string::npos)
      << pushed.problems[0].problem;
  EXPECT_NE(pushed.problems[0].remedy.find("leafdig server init"), std::string::npos);
  EXPECT_EQ(Sql(admin_).value("SELECT count(*) FROM leafdig.sessions"), "0");
  (void)Sql(admin_).value("UPDATE leafdig.meta SET value = '7' WHERE key = 'schema_version' RETURNING value");
  pushed = db::push(station, tech);
  EXPECT_TRUE(pushed.problems.empty()) << pushed.problems[0].problem;
  EXPECT_EQ(Sql(admin_).value("SELECT count(*) FROM leafdig.events WHERE kind = 'relocation'"), "1");
}

TEST_F(Lab, APlantSessionsBranchesWaitForASchema5ServerAndThenGoWhole) {
  db::Store station(file("a.sqlite"));
  const auto plant = capturePlantSession(station, "bench-a", "P-10", "tobacco-2026", "ana", /*complete=*/false);
  db::EventInput e;
  e.kind = "node_placed";
  e.payloadJson = R"({"node":9,"parent":2,"relation":"+"})";
  e.monoNs = 900000;
  (void)station.append(plant, e);
  ASSERT_TRUE(station.verify(plant).ok);
  const std::string tech = login(db::LabRole::Technician, "bench-a");
  // A schema 4 server would refuse the placement: the session stays here, whole, named.
  (void)Sql(admin_).value("UPDATE leafdig.meta SET value = '4' WHERE key = 'schema_version' RETURNING value");
  auto pushed = db::push(station, tech);
  ASSERT_EQ(pushed.problems.size(), 1U);
  EXPECT_NE(pushed.problems[0].problem.find("plant session with branches and the lab server (schema 4)"),
            std::string::npos)
      << pushed.problems[0].problem;
  EXPECT_NE(pushed.problems[0].remedy.find("leafdig server init"), std::string::npos);
  EXPECT_EQ(Sql(admin_).value("SELECT count(*) FROM leafdig.sessions"), "0");
  (void)Sql(admin_).value("UPDATE leafdig.meta SET value = '5' WHERE key = 'schema_version' RETURNING value");
  pushed = db::push(station, tech);
  EXPECT_TRUE(pushed.problems.empty()) << pushed.problems[0].problem;
  db::LabStore reader(login(db::LabRole::Reader));
  const std::int64_t serverId = reader.sessions().at(0).id;
  EXPECT_TRUE(reader.verify(serverId).ok);
  EXPECT_EQ(Sql(admin_).value("SELECT count(*) FROM leafdig.events WHERE kind = 'node_placed'"), "1");
}

TEST_F(Lab, APlantSessionIsHeldToThePlantsWordsAndALeafSessionToTheLeafsBySql) {
  db::Store station(file("a.sqlite"));
  const std::string tech = login(db::LabRole::Technician, "bench-a");
  const Pushed leaf = pushOne(station, "bench-a", tech, /*complete=*/false);
  const auto plantId = capturePlantSession(station, "bench-a", "P-08", "tobacco-2026", "ana", /*complete=*/false);
  ASSERT_TRUE(db::push(station, tech).problems.empty());
  const Pushed plant{
      Sql(admin_).value("SELECT id FROM leafdig.sessions WHERE station_session_id = $1", {std::to_string(plantId)}),
      plantId};
  Sql asTech(tech);
  // What a plant session holds, taken; what it does not, refused by name.
  const std::vector<std::pair<std::string, std::string>> good{
      {"accepted", R"({"what":"point","row":4,"col":1,"position_mm":[2,0,300]})"},
      {"accepted", R"({"what":"reading","row":4,"col":1,"value_mm":8.5})"},
      {"leaf_chosen", R"({"node":4,"kind":"full","state":"alive"})"},
      {"accepted", R"({"what":"node4.tip","row":null,"col":null,"position_mm":[200,0,400]})"},
      {"accepted", R"({"what":"node4.marker","row":1,"col":1,"position_mm":[150,0,380]})"},
      {"rows_reopened", R"({"node":4})"},
      {"choice_undone", R"({"node":3,"kind":"quick","state":"broken"})"},
      {"leaf_chosen", R"({"node":5,"kind":"quick","state":"alive","type":"lower"})"},
      // A retake (schema 4) names the event that put the item in; the item put back holds it again.
      {"retake", R"({"what":"landmark","row":2,"col":null,"position_mm":[200,1,20],"seq":2})"},
      {"retake_cancelled", R"({"what":"landmark","row":2,"col":null,"position_mm":[200,1,20]})"},
      // Where a node hangs (schema 5): a branch begun, its undo, a branch ended.
      {"node_placed", R"({"node":5,"parent":4,"relation":"+"})"},
      {"placement_undone", R"({"node":5,"parent":4,"relation":"+"})"},
      {"node_placed", R"({"node":7,"parent":4,"relation":"<"})"},
      // The transmitter moved (schema 6): the landmarks again, in the new position's frame, and the fit.
      {"relocation", R"({"relocation":1,"step":"started"})"},
      {"accepted", R"({"what":"landmark_again","row":2,"col":1,"position_mm":[210,4,18],"frame":1})"},
      {"relocation", R"({"relocation":1,"step":"fitted","rms_mm":0.2,"worst_mm":0.3})"},
      {"accepted", R"({"what":"point","row":8,"col":1,"position_mm":[2,0,500],"frame":1})"},
  };
  for (const auto& [kind, payload] : good)
    EXPECT_EQ(appendBySql(asTech, plant, "bench-a", kind, payload), "") << kind << " " << payload;
  const std::vector<std::pair<std::pair<std::string, std::string>, std::string>> bad{
      {{"accepted", R"({"what":"marker","row":1,"col":1,"position_mm":[1,2,3]})"}, "not a plant's item"},
      {{"accepted", R"({"what":"node4.board","row":null,"col":null,"position_mm":[1,2,3]})"}, "not a plant's item"},
      {{"accepted", R"({"what":"node0.marker","row":1,"col":1,"position_mm":[1,2,3]})"}, "not a plant's item"},
      {{"accepted", R"({"what":"landmark","row":1,"col":null,"position_mm":[1,2]})"}, "not a plant's item"},
      {{"accepted", R"({"what":"collar_diameter","row":null,"col":null,"value_mm":-3})"}, "not a plant's item"},
      {{"leaf_chosen", R"({"node":5,"kind":"sketch","state":"alive"})"}, "not a leaf's choice"},
      {{"leaf_chosen", R"({"node":"5","kind":"full","state":"alive"})"}, "not a leaf's choice"},
      {{"leaf_chosen", R"({"node":6,"kind":"quick","state":"alive","type":5})"}, "not a leaf's choice"},
      {{"leaf_chosen", R"({"node":6,"kind":"quick","state":"alive","type":")" + std::string(65, 'x') + "\"}"},
       "not a leaf's choice"},
      {{"rows_ended", "{}"}, "does not name the node"},
      {{"retake_started", R"({"what":"point","seq":2})"}, "not one leafdig writes for a plant session"},
      {{"retake", R"({"what":"landmark","seq":4})"}, "which is not a captured item"},  // landmarks_ended
      {{"retake", R"({"what":"landmark","seq":99999})"}, "does not name an earlier event"},
      {{"retake_cancelled", R"({"what":"marker","row":1,"col":1,"position_mm":[1,2,3]})"}, "not a plant's item"},
      {{"undone", R"({"what":"point","seq":99999})"}, "does not name an earlier event"},
      {{"undone", R"({"what":"point","seq":4})"}, "which is not a captured item"},  // landmarks_ended
      {{"node_placed", R"({"node":5,"parent":5,"relation":"+"})"}, "not where a node hangs"},
      {{"node_placed", R"({"node":5,"parent":"4","relation":"+"})"}, "not where a node hangs"},
      {{"node_placed", R"({"node":5,"parent":4,"relation":"^"})"}, "not where a node hangs"},
      {{"node_placed", R"({"node":5,"parent":0,"relation":"<"})"}, "not where a node hangs"},
      {{"placement_undone", R"({"parent":4,"relation":"+"})"}, "not where a node hangs"},
      {{"relocation", R"({"relocation":0,"step":"started"})"}, "not a move of the transmitter"},
      {{"relocation", R"({"relocation":1,"step":"moved"})"}, "not a move of the transmitter"},
      {{"relocation", R"({"step":"fitted"})"}, "not a move of the transmitter"},
      {{"accepted", R"({"what":"landmark_again","row":2,"col":1,"value_mm":3})"}, "not a plant's item"},
      {{"accepted", R"({"what":"point","row":8,"col":1,"position_mm":[2,0,500],"frame":"1"})"}, "not a plant's item"},
  };
  for (const auto& [event, words] : bad) {
    const std::string refused = appendBySql(asTech, plant, "bench-a", event.first, event.second);
    EXPECT_NE(refused.find(words), std::string::npos) << event.first << " " << event.second << ": " << refused;
  }
  // A leaf session takes none of the plant's words (a move of the transmitter: schema 7, below).
  for (const auto& [kind, payload] : std::vector<std::pair<std::string, std::string>>{
           {"landmarks_ended", "{}"},
           {"leaf_chosen", R"({"node":1,"kind":"full","state":"alive"})"},
           {"node_placed", R"({"node":3,"parent":2,"relation":"+"})"},
           {"accepted", R"({"what":"landmark_again","row":1,"col":1,"position_mm":[1,2,3]})"},
           {"accepted", R"({"what":"landmark","row":1,"col":null,"position_mm":[1,2,3]})"}}) {
    const std::string refused = appendBySql(asTech, leaf, "bench-a", kind, payload);
    EXPECT_FALSE(refused.empty()) << kind;
  }
  EXPECT_NE(appendBySql(asTech, leaf, "bench-a", "plant_ended", "{}").find("a plant session's event"),
            std::string::npos);
  // Roles are unchanged: a curator adds no capture event, a technician decides nothing.
  EXPECT_NE(appendBySql(Sql(login(db::LabRole::Curator)), plant, "bench-a", "accepted",
                        R"({"what":"point","row":5,"col":1,"position_mm":[2,0,400]})")
                .find("only the station's technician pushes them"),
            std::string::npos);
  EXPECT_NE(appendBySql(asTech, plant, "bench-a", "status", R"({"status":"approved","who":"ana","why":""})")
                .find("only curators review"),
            std::string::npos);
  // A session's kind is what its settings say, and a plant has no leaf.
  const auto insert = [&](std::int64_t id, const std::string& position, const std::string& settings,
                          const std::string& kind) {
    return asTech.error(
        "INSERT INTO leafdig.sessions(station, station_session_id, project, plant, leaf_position, operator, mode, "
        "capture_order, settings_json, created_utc, genesis_hash, kind) VALUES ('bench-a', $1, 'p', 'p', $2, 'x', "
        "'standard', 'sequential', $3, 't', $4, $5)",
        {std::to_string(id), position, settings, db::genesisHash(id, "t", settings), kind});
  };
  EXPECT_NE(insert(901, "3", R"({"kind":"plant"})", "plant").find("sessions_kind_known"), std::string::npos);
  EXPECT_NE(insert(902, "0", "{}", "plant").find("pushed as a plant session but its settings are a leaf's"),
            std::string::npos);
  EXPECT_NE(
      insert(903, "2", R"({"kind":"plant"})", "leaf").find("pushed as a leaf session but its settings are a plant's"),
      std::string::npos);
  EXPECT_NE(insert(904, "0", R"({"kind":"tree"})", "tree").find("sessions_kind_known"), std::string::npos);
  EXPECT_EQ(insert(905, "0", R"({"kind":"plant"})", "plant"), "");
  // Everything taken still reads and verifies on the server.
  db::LabStore reader(login(db::LabRole::Reader));
  EXPECT_TRUE(reader.verify(std::stoll(plant.serverId)).ok);
  EXPECT_TRUE(reader.verify(std::stoll(leaf.serverId)).ok);
}

TEST_F(Lab, TheServerRechecksEveryChainAndNamesTheSessionAndEventItRefuses) {
  db::Store station(file("a.sqlite"));
  const auto id = captureSession(station, "bench-a", 1, 3, "tobacco-2026", "P-07", "ana", /*complete=*/false);
  const std::string tech = login(db::LabRole::Technician, "bench-a");
  ASSERT_TRUE(db::push(station, tech).problems.empty());
  Sql sql(tech);
  const std::string serverId = sql.value(
      "SELECT id FROM leafdig.sessions WHERE station = 'bench-a' AND station_session_id = $1", {std::to_string(id)});
  const auto head = station.session(id)->headSeq;
  const std::string headHash = station.session(id)->headHash;
  const std::string insert =
      "INSERT INTO leafdig.events(session_id, station, seq, utc, mono_ns, kind, payload_json, raw, prev_hash, hash) "
      "VALUES ($1, 'bench-a', $2, '2026-11-24T10:00:00.000Z', 5, 'paused', '{\"reason\":\"lunch\"}', '', $3, $4)";
  const auto hashOf = [&](std::int64_t seq, const std::string& prev) {
    return db::eventHash(prev, id, seq, "2026-11-24T10:00:00.000Z", 5, "paused", R"({"reason":"lunch"})", "");
  };
  // A gap.
  const std::string gap = sql.error(insert, {serverId, std::to_string(head + 2), headHash, hashOf(head + 2, headHash)});
  EXPECT_NE(gap.find("session bench-a:" + std::to_string(id) + " event " + std::to_string(head + 2) +
                     " does not follow: the server holds events 1 to " + std::to_string(head)),
            std::string::npos)
      << gap;
  // Another previous event.
  const std::string fork = sql.error(
      insert, {serverId, std::to_string(head + 1), std::string(64, 'a'), hashOf(head + 1, std::string(64, 'a'))});
  EXPECT_NE(fork.find("event " + std::to_string(head + 1) + " does not follow the server's event"), std::string::npos)
      << fork;
  // A hash that is not the content's.
  const std::string forged = sql.error(insert, {serverId, std::to_string(head + 1), headHash, std::string(64, 'b')});
  EXPECT_NE(forged.find("does not hash to its hash"), std::string::npos) << forged;
  // The right one is taken, and the session's head moves with it.
  EXPECT_EQ(sql.error(insert, {serverId, std::to_string(head + 1), headHash, hashOf(head + 1, headHash)}), "");
  EXPECT_EQ(sql.value("SELECT head_seq FROM leafdig.sessions WHERE id = $1", {serverId}), std::to_string(head + 1));
  // Nobody edits or removes an event, not even the administrator.
  Sql admin(admin_);
  EXPECT_NE(admin.error("UPDATE leafdig.events SET raw = 'x' WHERE seq = 1").find("append-only"), std::string::npos);
  EXPECT_NE(admin.error("DELETE FROM leafdig.events").find("append-only"), std::string::npos);
  EXPECT_NE(admin.error("TRUNCATE leafdig.events CASCADE").find("append-only"), std::string::npos);
  // A technician cannot move a session's head by hand.
  EXPECT_NE(sql.error("UPDATE leafdig.sessions SET head_seq = 1").find("permission denied"), std::string::npos);
}

// Schema 9 checks a statement's events together, after the statement (issue 26: the push's
// rate): still in order of seq, still all or nothing, with the words of the row that fails,
// and the session's own status events in the statement count for the rows after them.
TEST_F(Lab, AStatementOfManyEventsIsCheckedInOrderAndTakenWholeOrNotAtAll) {
  db::Store station(file("a.sqlite"));
  const std::string tech = login(db::LabRole::Technician, "bench-a");
  const Pushed s = pushOne(station, "bench-a", tech, /*complete=*/false);
  Sql admin(admin_);
  const auto headOf = [&] {
    const auto r = admin.rows("SELECT head_seq, head_hash, status FROM leafdig.sessions WHERE id = $1", {s.serverId});
    return std::tuple<std::int64_t, std::string, std::string>{std::stoll(r[0][0]), r[0][1], r[0][2]};
  };
  const auto [head, headHash, status] = headOf();
  ASSERT_EQ(status, "open");
  const std::string count = admin.value("SELECT count(*) FROM leafdig.events");
  // One INSERT of the events (kind, payload), chained right from the server's head unless
  // `tamper` changes an event's previous hash: "" when taken, else the server's words.
  const auto insertAll = [&](const std::vector<std::pair<std::string, std::string>>& events,
                             const std::function<void(std::size_t, std::string&)>& tamper = {}) {
    std::string sql =
        "INSERT INTO leafdig.events(session_id, station, seq, utc, mono_ns, kind, payload_json, raw, prev_hash, hash) "
        "VALUES ";
    std::vector<std::string> params{s.serverId};
    std::string prev = headHash;
    for (std::size_t i = 0; i < events.size(); ++i) {
      const std::int64_t seq = head + 1 + static_cast<std::int64_t>(i);
      std::string linked = prev;
      if (tamper) tamper(i, linked);
      const std::string hash =
          db::eventHash(linked, s.stationId, seq, "2026-11-27T10:00:00.000Z", 9, events[i].first, events[i].second, "");
      const auto n = params.size();
      sql += (i ? ",($1, 'bench-a', $" : "($1, 'bench-a', $") + std::to_string(n + 1) +
             ", '2026-11-27T10:00:00.000Z', 9, $" + std::to_string(n + 2) + ", $" + std::to_string(n + 3) + ", '', $" +
             std::to_string(n + 4) + ", $" + std::to_string(n + 5) + ")";
      params.insert(params.end(), {std::to_string(seq), events[i].first, events[i].second, linked, hash});
      prev = hash;
    }
    return Sql(tech).error(sql, params);
  };
  const std::string lunch = R"({"reason":"lunch"})";
  const auto untouched = [&](const std::string& why) {
    EXPECT_EQ(headOf(), std::make_tuple(head, headHash, std::string("open"))) << why;
    EXPECT_EQ(admin.value("SELECT count(*) FROM leafdig.events"), count) << why;
  };
  const std::string at = "session bench-a:" + std::to_string(s.stationId) + " event ";
  // The third of three has a payload that is not JSON: the statement is refused by its words.
  const std::string badPayload = insertAll({{"paused", lunch}, {"resumed", "{}"}, {"paused", "not json"}});
  EXPECT_NE(badPayload.find(at + std::to_string(head + 3) + " (paused) refused: its payload is not JSON"),
            std::string::npos)
      << badPayload;
  untouched("a bad payload");
  // The second does not follow the first.
  const std::string fork = insertAll({{"paused", lunch}, {"resumed", "{}"}}, [](std::size_t i, std::string& prev) {
    prev = i == 1 ? std::string(64, 'a') : prev;
  });
  EXPECT_NE(
      fork.find(at + std::to_string(head + 2) + " does not follow the server's event " + std::to_string(head + 1)),
      std::string::npos)
      << fork;
  untouched("a fork");
  // The statement's own "complete" ends the capture for the rows after it.
  const std::string afterEnd =
      insertAll({{"paused", lunch}, {"status", R"({"status":"complete"})"}, {"resumed", "{}"}});
  EXPECT_NE(afterEnd.find("is complete: its capture is over and only a curator adds to it (event " +
                          std::to_string(head + 3) + " refused)"),
            std::string::npos)
      << afterEnd;
  untouched("a capture event after the statement's own end");
  // A technician's statement cannot carry a decision, wherever it stands in it.
  const std::string decision =
      insertAll({{"paused", lunch}, {"status", R"({"status":"complete"})"}, {"status", R"({"status":"approved"})"}});
  EXPECT_NE(decision.find("only curators review"), std::string::npos) << decision;
  untouched("a decision in a technician's statement");
  // A right statement is taken whole: the head is its last event.
  ASSERT_EQ(insertAll({{"paused", lunch}, {"resumed", "{}"}}), "");
  EXPECT_EQ(std::get<0>(headOf()), head + 2);
  EXPECT_EQ(std::get<1>(headOf()), admin.value("SELECT hash FROM leafdig.events WHERE session_id = $1 AND seq = $2",
                                               {s.serverId, std::to_string(head + 2)}));
  EXPECT_EQ(admin.value("SELECT count(DISTINCT written_by) || ' ' || bool_and(written_by = $2) FROM leafdig.events "
                        "WHERE session_id = $1 AND seq > $3",
                        {s.serverId, Sql(tech).value("SELECT session_user"), std::to_string(head)}),
            "1 true");
  // The same statement again: the server holds those events already, and says so.
  const std::string again = Sql(tech).error(
      "INSERT INTO leafdig.events(session_id, station, seq, utc, mono_ns, kind, payload_json, raw, prev_hash, hash) "
      "SELECT session_id, station, seq, utc, mono_ns, kind, payload_json, raw, prev_hash, hash FROM leafdig.events "
      "WHERE session_id = $1 AND seq > $2 ORDER BY seq",
      {s.serverId, std::to_string(head)});
  EXPECT_NE(again.find(at + std::to_string(head + 1) + " does not follow: the server holds events 1 to " +
                       std::to_string(head + 2)),
            std::string::npos)
      << again;
  // A statement's status is the session's once it is taken.
  const std::string heldHash = std::get<1>(headOf());
  const std::string end = R"({"status":"complete"})";
  EXPECT_EQ(Sql(tech).error("INSERT INTO leafdig.events(session_id, station, seq, utc, mono_ns, kind, payload_json, "
                            "raw, prev_hash, hash) VALUES ($1, 'bench-a', $2, 't', 1, 'status', $3, '', $4, $5)",
                            {s.serverId, std::to_string(head + 3), end, heldHash,
                             db::eventHash(heldHash, s.stationId, head + 3, "t", 1, "status", end, "")}),
            "");
  EXPECT_EQ(headOf(), std::make_tuple(head + 3,
                                      admin.value("SELECT hash FROM leafdig.events WHERE session_id = $1 "
                                                  "AND seq = $2",
                                                  {s.serverId, std::to_string(head + 3)}),
                                      std::string("complete")));
}

// Row-level security holds by itself (schema 9 looks the login's station up once per
// statement in the policy): with both arrival triggers disabled by the owner, a technician
// still adds no event of another station and no review event.
TEST_F(Lab, ThePoliciesHoldWithoutTheTriggers) {
  db::Store station(file("a.sqlite"));
  const std::string tech = login(db::LabRole::Technician, "bench-a");
  const Pushed s = pushOne(station, "bench-a", tech, /*complete=*/false);
  Sql admin(admin_);
  (void)admin.rows("ALTER TABLE leafdig.events DISABLE TRIGGER event_arrives");
  (void)admin.rows("ALTER TABLE leafdig.events DISABLE TRIGGER events_arrived");
  const std::string insert =
      "INSERT INTO leafdig.events(session_id, station, seq, utc, mono_ns, kind, payload_json, raw, prev_hash, hash) "
      "VALUES ($1, $2, 999, 't', 1, $3, $4, '', 'x', 'y')";
  Sql asTech(tech);
  EXPECT_NE(asTech.error(insert, {s.serverId, "bench-b", "paused", "{}"}).find("row-level security"),
            std::string::npos);
  EXPECT_NE(
      asTech.error(insert, {s.serverId, "bench-a", "status", R"({"status":"approved"})"}).find("row-level security"),
      std::string::npos);
  EXPECT_NE(asTech.error(insert, {s.serverId, "bench-a", "corrected", "{}"}).find("row-level security"),
            std::string::npos);
  EXPECT_EQ(asTech.error(insert, {s.serverId, "bench-a", "paused", "{}"}), "");  // the policy's own reach ends here
  EXPECT_NE(Sql(login(db::LabRole::Curator))
                .error(insert, {s.serverId, "bench-a", "paused", "{}"})
                .find("row-level security"),
            std::string::npos);
}

// The push sends each column as one array: text that array syntax would take apart (quotes,
// backslashes, braces, commas, NULL, an empty raw record) arrives as the station wrote it.
TEST_F(Lab, EventsWhoseTextLooksLikeArraySyntaxArriveUnchanged) {
  db::Store station(file("a.sqlite"));
  const std::string tech = login(db::LabRole::Technician, "bench-a");
  const auto id = captureSession(station, "bench-a", 1, 2, "tobacco-2026", "P-07", "ana", /*complete=*/false);
  for (const std::string& text : {std::string(R"({"reason":"a \"quoted\", {braced} back\\slash"})"),
                                  std::string(R"({"reason":"NULL"})"), std::string(R"({"reason":"}\\\\,\"{"})")}) {
    db::EventInput e;
    e.kind = "paused";
    e.payloadJson = text;
    e.raw = text.size() % 2 ? "" : "NULL,{\"\\\"}";
    (void)station.append(id, e);
  }
  const auto report = db::push(station, tech);
  ASSERT_TRUE(report.problems.empty()) << report.problems.front().problem;
  EXPECT_EQ(serverEvents(), fileEvents(station));
}

TEST_F(Lab, EachRoleIsHeldToWhatItMayDoByTheServer) {
  db::Store a(file("a.sqlite"));
  db::Store b(file("b.sqlite"));
  const auto idA = captureSession(a, "bench-a", 1);
  (void)captureSession(b, "bench-b", 1);
  const std::string techA = login(db::LabRole::Technician, "bench-a");
  const std::string techB = login(db::LabRole::Technician, "bench-b");
  const std::string curator = login(db::LabRole::Curator);
  const std::string reader = login(db::LabRole::Reader);

  // A technician pushes its own station only.
  const auto wrong = db::push(b, techA);
  ASSERT_EQ(wrong.problems.size(), 1u);
  EXPECT_NE(wrong.problems[0].problem.find("pushes for station bench-a, not for station bench-b"), std::string::npos)
      << wrong.problems[0].problem;
  EXPECT_EQ(wrong.eventsSent, 0);
  ASSERT_TRUE(db::push(a, techA).problems.empty());
  ASSERT_TRUE(db::push(b, techB).problems.empty());
  // …and sees its own station's sessions only; curators and readers see all.
  EXPECT_EQ(db::LabStore(techA).sessions().size(), 1u);
  EXPECT_EQ(db::LabStore(curator).sessions().size(), 2u);
  EXPECT_EQ(db::LabStore(reader).sessions().size(), 2u);

  // Approving is a curator's: a technician's attempt is refused by the server, in words.
  db::LabStore asTech(techA);
  const auto serverIdA = asTech.sessions().front().id;
  try {
    (void)asTech.setStatus(serverIdA, "approved", "ana", "");
    FAIL() << "a technician approved";
  } catch (const db::StoreError& e) {
    EXPECT_EQ(e.kind(), db::StoreErrorKind::Refused);
    EXPECT_NE(std::string(e.what()).find("may not approve, reject or correct sessions (session bench-a:" +
                                         std::to_string(idA)),
              std::string::npos)
        << e.what();
  }
  // …also when the approval was made in the station's file and pushed.
  (void)a.setStatus(idA, "approved", "ana", "looked fine");
  const auto pushedApproval = db::push(a, techA);
  ASSERT_EQ(pushedApproval.problems.size(), 1u);
  EXPECT_NE(pushedApproval.problems[0].problem.find("only curators review"), std::string::npos);
  EXPECT_EQ(db::LabStore(curator).session(serverIdA)->status, "complete");
  // A reader changes nothing.
  try {
    (void)db::LabStore(reader).setStatus(serverIdA, "approved", "rita", "");
    FAIL() << "a reader approved";
  } catch (const db::StoreError& e) {
    EXPECT_EQ(e.kind(), db::StoreErrorKind::Refused) << e.what();
  }
  EXPECT_FALSE(db::push(a, reader).problems.empty());
  // A curator approves any session, and pushes no capture events.
  db::LabStore asCurator(curator);
  for (const auto& s : asCurator.sessions()) {
    if (s.station == "bench-b") (void)asCurator.setStatus(s.id, "rejected", "carla", "blurred tip");
  }
  (void)asCurator.setStatus(serverIdA, "approved", "carla", "");
  EXPECT_EQ(asCurator.session(serverIdA)->status, "approved");
  db::EventInput paused;
  paused.kind = "paused";
  paused.payloadJson = R"({"reason":"coffee"})";
  EXPECT_THROW((void)asCurator.append(serverIdA, paused), db::StoreError);
  // Row-level security holds even without the triggers' words: a technician reading
  // another station's rows directly gets none.
  Sql sqlA(techA);
  EXPECT_EQ(sqlA.value("SELECT count(*) FROM leafdig.events WHERE station = 'bench-b'"), "0");
  EXPECT_EQ(Sql(reader).value("SELECT count(*) > 0 FROM leafdig.events WHERE station = 'bench-b'"), "t");
}

// ---- the lab server under attack (issue 25): each through plain SQL as the role ----------------

TEST_F(Lab, AfterACuratorsDecisionNothingFollowsFromATechnicianNeitherBySqlNorByPush) {
  db::Store station(file("a.sqlite"));
  const std::string tech = login(db::LabRole::Technician, "bench-a");
  const Pushed s = pushOne(station, "bench-a", tech);
  db::LabStore curator(login(db::LabRole::Curator));
  (void)curator.setStatus(std::stoll(s.serverId), "approved", "carla", "");
  Sql asTech(tech);
  for (const char* status : {"open", "abandoned", "complete"}) {
    const std::string refused =
        appendBySql(asTech, s, "bench-a", "status", std::string(R"({"status":")") + status + R"(","who":"ana"})");
    EXPECT_NE(refused.find("was approved by a curator: the decision is final"), std::string::npos) << refused;
  }
  EXPECT_NE(appendBySql(asTech, s, "bench-a", "paused", R"({"reason":"x"})").find("the decision is final"),
            std::string::npos);
  EXPECT_EQ(statusOf(s), "approved");
  // The same from the station's file: the decision pulled, then the file reopened and pushed.
  ASSERT_TRUE(db::pull(station, tech).problems.empty());
  (void)station.setStatus(s.stationId, "open", "ana", "reopened by hand");
  const auto pushed = db::push(station, tech);
  ASSERT_EQ(pushed.problems.size(), 1u);
  EXPECT_NE(pushed.problems[0].problem.find("the decision is final"), std::string::npos) << pushed.problems[0].problem;
  EXPECT_EQ(statusOf(s), "approved");
  // A curator cannot decide twice either (the decision stands as taken).
  EXPECT_NE(appendBySql(Sql(admin_), s, "bench-a", "status", R"({"status":"rejected","who":"carla","why":"x"})")
                .find("the decision is final"),
            std::string::npos);
  // Every other station pulls the one decision.
  db::Store copy(file("b.sqlite"));
  EXPECT_EQ(db::LabStore(login(db::LabRole::Reader)).session(std::stoll(s.serverId))->status, "approved");
}

// A curator reopens a decision, saying why (issue 49): by plain SQL and through leafdig, only a
// curator, only a decided session, only naming its decision; after it the session is complete
// again — corrections and a new decision follow, a capture event does not — and the station
// that captured it pulls the whole record.
TEST_F(Lab, OnlyACuratorReopensADecisionAndTheStationPullsTheRecord) {
  db::Store station(file("a.sqlite"));
  const std::string tech = login(db::LabRole::Technician, "bench-a");
  const Pushed s = pushOne(station, "bench-a", tech, /*complete=*/true);
  const std::string carla = login(db::LabRole::Curator);
  const std::string carlaLogin = Sql(carla).value("SELECT session_user");
  const auto reopening = [&](const std::string& who, const std::string& why, const std::string& reopens) {
    return nlohmann::json{{"status", "complete"}, {"who", who}, {"why", why}, {"reopens", reopens}}.dump();
  };
  // Nothing to reopen yet.
  EXPECT_NE(appendBySql(Sql(carla), s, "bench-a", "status", reopening(carlaLogin, "x", "approved"))
                .find("only an approved or rejected session is reopened"),
            std::string::npos);
  db::LabStore asCarla(carla);
  const std::int64_t id = std::stoll(s.serverId);
  (void)leafdig::acquisition::review(asCarla, id, "approved", "", "fine");
  EXPECT_EQ(statusOf(s), "approved");
  // The technician may not reopen, even its own capture; a reopening needs a reason and the
  // decision it reopens.
  const std::string techLogin = Sql(tech).value("SELECT session_user");
  EXPECT_NE(appendBySql(Sql(tech), s, "bench-a", "status", reopening(techLogin, "more rows", "approved")), "");
  EXPECT_NE(
      appendBySql(Sql(carla), s, "bench-a", "status", reopening(carlaLogin, "", "approved")).find("says who and why"),
      std::string::npos);
  EXPECT_NE(appendBySql(Sql(carla), s, "bench-a", "status", reopening(carlaLogin, "x", "rejected"))
                .find("only an approved or rejected session is reopened, naming its decision"),
            std::string::npos);
  EXPECT_EQ(statusOf(s), "approved");
  // Taken from a curator by plain SQL: complete again; a capture event still may not follow.
  EXPECT_EQ(appendBySql(Sql(carla), s, "bench-a", "status", reopening(carlaLogin, "leaf 3 misread", "approved")), "");
  EXPECT_EQ(statusOf(s), "complete");
  EXPECT_NE(appendBySql(Sql(tech), s, "bench-a", "paused", R"({"reason":"x"})").find("its capture is over"),
            std::string::npos);
  EXPECT_THROW((void)leafdig::acquisition::reopen(asCarla, id, "", "again"), std::invalid_argument);
  // Through leafdig: reject, reopen, approve.
  (void)leafdig::acquisition::review(asCarla, id, "rejected", "", "row 2 is short");
  (void)leafdig::acquisition::reopen(asCarla, id, "Dr Carla", "row 2 was complete after all");
  (void)leafdig::acquisition::review(asCarla, id, "approved", "", "checked twice");
  EXPECT_EQ(statusOf(s), "approved");
  // The station takes the whole record in, in order, and verifies.
  db::SyncOptions options;
  options.replays = leafdig::acquisition::requireReplays;
  const auto pulled = db::pull(station, tech, options);
  ASSERT_TRUE(pulled.problems.empty()) << pulled.problems.front().problem;
  EXPECT_EQ(pulled.eventsTaken, 5);
  EXPECT_EQ(station.session(s.stationId)->status, "approved");
  EXPECT_TRUE(station.verify(s.stationId).ok);
  const auto history = db::reviewHistory(station.events(s.stationId));
  std::vector<std::string> actions;
  for (const auto& h : history) actions.push_back(h.action);
  EXPECT_EQ(actions, (std::vector<std::string>{"approved", "reopened", "rejected", "reopened", "approved"}));
  EXPECT_EQ(history[3].reopens, "rejected");
  EXPECT_EQ(history[3].who, "Dr Carla (" + carlaLogin + ")");
  ASSERT_TRUE(db::lastDecision(history).has_value());
  EXPECT_EQ(db::lastDecision(history)->why, "checked twice");
  // A tampered server's reopening of a session the station holds complete is refused by the pull.
  db::Store second(file("b.sqlite"));
  const std::string tech2 = login(db::LabRole::Technician, "bench-b");
  const Pushed t = pushOne(second, "bench-b", tech2, /*complete=*/true);
  Sql owner(admin_);
  (void)owner.rows("ALTER TABLE leafdig.events DISABLE TRIGGER USER");
  EXPECT_EQ(appendBySql(owner, t, "bench-b", "status", reopening("carla", "forged", "approved")), "");
  (void)owner.rows(
      "UPDATE leafdig.sessions x SET head_seq = e.seq, head_hash = e.hash FROM leafdig.events e "
      "WHERE x.id = $1 AND e.session_id = x.id AND e.seq = (SELECT max(seq) FROM leafdig.events WHERE session_id = "
      "x.id)",
      {t.serverId});
  (void)owner.rows("ALTER TABLE leafdig.events ENABLE TRIGGER USER");
  const auto forged = db::pull(second, tech2, options);
  ASSERT_EQ(forged.problems.size(), 1u);
  EXPECT_NE(forged.problems.front().problem.find("reopens a session approved that is complete at the station"),
            std::string::npos)
      << forged.problems.front().problem;
  EXPECT_EQ(forged.eventsTaken, 0);
  EXPECT_EQ(second.session(t.stationId)->status, "complete");
}

TEST_F(Lab, StatusesAreAClosedSetAndATechnicianOnlyEndsItsOwnCapture) {
  db::Store station(file("a.sqlite"));
  const std::string tech = login(db::LabRole::Technician, "bench-a");
  const Pushed s = pushOne(station, "bench-a", tech, /*complete=*/false);
  Sql asTech(tech);
  for (const char* fake : {"approved ", "APPROVED", "approved\u200b", "finished", ""}) {
    const std::string refused =
        appendBySql(asTech, s, "bench-a", "status", nlohmann::json{{"status", fake}, {"who", "ana"}}.dump());
    EXPECT_NE(refused.find("its status is not one of open, complete, approved, rejected, abandoned"), std::string::npos)
        << fake << ": " << refused;
  }
  EXPECT_NE(appendBySql(asTech, s, "bench-a", "status", R"({"status":7})").find("its status is not one of"),
            std::string::npos);
  EXPECT_NE(appendBySql(asTech, s, "bench-a", "status", R"({"status":"open","who":"ana"})")
                .find("a capture ends as complete or abandoned, not open"),
            std::string::npos);
  EXPECT_EQ(statusOf(s), "open");
  // A status the server does not know cannot be written around the trigger either.
  EXPECT_NE(Sql(admin_)
                .error("UPDATE leafdig.sessions SET status = 'approved ' WHERE id = " + s.serverId)
                .find("sessions_status_known"),
            std::string::npos);
  // Its own capture's end is the technician's.
  EXPECT_EQ(appendBySql(asTech, s, "bench-a", "status", R"({"status":"complete","who":"ana","why":"done"})"), "");
  EXPECT_EQ(statusOf(s), "complete");
  EXPECT_EQ(db::LabStore(login(db::LabRole::Reader)).sessions().front().status, "complete");
}

TEST_F(Lab, ACuratorsCorrectionIsTheCuratorsAloneAndNoTechnicianUndoesIt) {
  db::Store station(file("a.sqlite"));
  const std::string tech = login(db::LabRole::Technician, "bench-a");
  const Pushed s = pushOne(station, "bench-a", tech);
  db::LabStore curator(login(db::LabRole::Curator));
  const auto id = std::stoll(s.serverId);
  const db::MarkerRow tip = curator.markers(id).front();
  ASSERT_EQ(tip.what, "tip");
  nlohmann::json payload{{"what", "tip"},
                         {"row", nullptr},
                         {"col", nullptr},
                         {"seq", tip.seq},
                         {"position_mm", {tip.positionMm[0], tip.positionMm[1], tip.positionMm[2]}}};
  payload["corrected"] = {{"what", "tip"}, {"row", nullptr}, {"col", nullptr}, {"position_mm", {1.5, 2.5, 3.5}}};
  payload["reason"] = "slipped";
  payload["who"] = curator.signature("carla");
  db::EventInput corrected;
  corrected.kind = "corrected";
  corrected.payloadJson = payload.dump();
  const auto correction = curator.append(id, corrected);
  Sql asTech(tech);
  const std::string undo =
      appendBySql(asTech, s, "bench-a", "undone",
                  nlohmann::json{{"what", "tip"}, {"row", nullptr}, {"col", nullptr}, {"seq", correction}}.dump());
  EXPECT_NE(undo.find("its capture is over and only a curator adds to it"), std::string::npos) << undo;
  const std::string retip =
      appendBySql(asTech, s, "bench-a", "accepted", R"({"what":"tip","row":null,"col":null,"position_mm":[99,99,99]})");
  EXPECT_NE(retip.find("its capture is over"), std::string::npos) << retip;
  // Not even an administrator's capture event undoes a correction: a curator corrects again.
  EXPECT_NE(
      appendBySql(Sql(admin_), s, "bench-a", "undone", nlohmann::json{{"what", "tip"}, {"seq", correction}}.dump())
          .find("its capture is over"),
      std::string::npos);
  (void)curator.setStatus(id, "approved", "carla", "");
  int tips = 0;
  for (const auto& m : db::LabStore(login(db::LabRole::Reader)).markers(id))
    if (m.what == "tip") {
      ++tips;
      EXPECT_EQ(m.positionMm, (std::array<double, 3>{1.5, 2.5, 3.5}));
    }
  EXPECT_EQ(tips, 1);
}

TEST_F(Lab, ATemporaryPgRolesTableMakesNoTechnicianAnAdministrator) {
  db::Store station(file("a.sqlite"));
  const std::string tech = login(db::LabRole::Technician, "bench-a");
  const Pushed s = pushOne(station, "bench-a", tech);
  {
    // Since schema 10's init a lab login makes no temporary table at all (TEMPORARY revoked
    // from PUBLIC)...
    const std::string refused = Sql(tech).error("CREATE TEMP TABLE pg_roles (rolname name, rolsuper boolean)");
    EXPECT_NE(refused.find("permission denied"), std::string::npos) << refused;
  }
  // ... and should an administrator grant it, the functions still read the real catalogs.
  (void)Sql(admin_).rows("GRANT TEMPORARY ON DATABASE " + database_ + " TO " + Sql(tech).value("SELECT session_user"));
  Sql asTech(tech);
  ASSERT_EQ(asTech.error("CREATE TEMP TABLE pg_roles (rolname name, rolsuper boolean)"), "");
  ASSERT_EQ(asTech.error("INSERT INTO pg_roles VALUES (current_user, true)"), "");
  EXPECT_EQ(asTech.value("SELECT leafdig.is_admin(session_user)::text"), "false");
  ASSERT_EQ(asTech.error("CREATE TEMP TABLE pg_namespace (nspname name, nspowner oid)"), "");
  ASSERT_EQ(asTech.error("INSERT INTO pg_namespace SELECT 'leafdig', oid FROM pg_catalog.pg_roles WHERE rolname = "
                         "current_user"),
            "");
  EXPECT_EQ(asTech.value("SELECT leafdig.is_admin(session_user)::text"), "false");
  const std::string approve =
      appendBySql(asTech, s, "bench-a", "status", R"({"status":"approved","who":"ana","why":""})");
  EXPECT_NE(approve.find("only curators review"), std::string::npos) << approve;
  EXPECT_EQ(statusOf(s), "complete");
  // Every function of the schema searches the catalogs first and the temporary schema last.
  for (const auto& row : Sql(admin_).rows(
           "SELECT p.proname, coalesce(array_to_string(p.proconfig, ','), '') FROM pg_proc p JOIN pg_namespace n ON "
           "n.oid = p.pronamespace WHERE n.nspname = 'leafdig'"))
    EXPECT_EQ(row[1], "search_path=pg_catalog, pg_temp") << row[0];
}

TEST_F(Lab, IdsSignaturesAndArrivalTimesAreTheServersAlone) {
  db::Store a(file("a.sqlite"));
  db::Store b(file("b.sqlite"));
  const std::string techA = login(db::LabRole::Technician, "bench-a");
  const std::string techB = login(db::LabRole::Technician, "bench-b");
  const Pushed s = pushOne(a, "bench-a", techA);
  Sql asTech(techA);
  const std::string next = Sql(admin_).value("SELECT coalesce(max(id), 0) + 1 FROM leafdig.sessions");
  // Claiming the next session ids: refused, whatever the syntax.
  const std::string claim = asTech.error(
      "INSERT INTO leafdig.sessions(id, station, station_session_id, project, plant, leaf_position, operator, mode, "
      "capture_order, settings_json, created_utc, genesis_hash) OVERRIDING SYSTEM VALUE VALUES ($1, 'bench-a', 999, "
      "'p', 'p', 1, 'x', 'standard', 'sequential', '{}', 't', $2)",
      {next, db::genesisHash(999, "t", "{}")});
  EXPECT_NE(claim.find("permission denied"), std::string::npos) << claim;
  for (const std::string column : {"pushed_by", "head_seq", "status", "first_pushed"})
    EXPECT_NE(asTech
                  .error("INSERT INTO leafdig.sessions(station, station_session_id, project, plant, leaf_position, "
                         "operator, mode, capture_order, settings_json, created_utc, genesis_hash, " +
                             column +
                             ") VALUES ('bench-a', 998, 'p', 'p', 1, 'x', 'standard', 'sequential', '{}', 't', $1, "
                             "DEFAULT)",
                         {db::genesisHash(998, "t", "{}")})
                  .find("permission denied"),
              std::string::npos)
        << column;
  // …so another station's new session still goes.
  (void)pushOne(b, "bench-b", techB);
  EXPECT_EQ(Sql(admin_).value("SELECT count(*) FROM leafdig.sessions"), "2");
  // An export is signed by the login that records it.
  EXPECT_NE(asTech
                .error("INSERT INTO leafdig.exports(session_id, path, format, utc, written_by) VALUES ($1, 'x.glb', "
                       "'glb', 't', 'carla')",
                       {s.serverId})
                .find("permission denied"),
            std::string::npos);
  EXPECT_NE(asTech
                .error("INSERT INTO leafdig.exports(id, session_id, path, format, utc) OVERRIDING SYSTEM VALUE "
                       "VALUES (77, $1, 'x.glb', 'glb', 't')",
                       {s.serverId})
                .find("permission denied"),
            std::string::npos);
  EXPECT_EQ(asTech.error("INSERT INTO leafdig.exports(session_id, path, format, utc) VALUES ($1, 'x.glb', 'glb', 't')",
                         {s.serverId}),
            "");
  const std::string techLogin = asTech.value("SELECT current_user");
  EXPECT_EQ(Sql(admin_).value("SELECT written_by FROM leafdig.exports"), techLogin);
  // An event's signature and arrival time likewise.
  EXPECT_NE(asTech
                .error("INSERT INTO leafdig.events(session_id, station, seq, utc, mono_ns, kind, payload_json, raw, "
                       "prev_hash, hash, written_by) VALUES ($1, 'bench-a', 99, 't', 1, 'paused', '{}', '', 'x', "
                       "'y', 'carla')",
                       {s.serverId})
                .find("permission denied"),
            std::string::npos);
}

TEST_F(Lab, ARefusalNamesNothingOfWhatTheLoginMayNotSee) {
  db::Store a(file("a.sqlite"));
  db::Store b(file("b.sqlite"));
  const std::string techA = login(db::LabRole::Technician, "bench-a");
  const std::string techB = login(db::LabRole::Technician, "bench-b");
  (void)pushOne(a, "bench-a", techA);
  const Pushed other = pushOne(b, "bench-b", techB, /*complete=*/false);
  Sql asA(techA);
  const std::string insert =
      "INSERT INTO leafdig.events(session_id, station, seq, utc, mono_ns, kind, payload_json, raw, prev_hash, hash) "
      "VALUES ($1, 'bench-a', 1, 't', 1, 'paused', '{}', '', 'x', 'y')";
  const std::string aboutB = asA.error(insert, {other.serverId});
  const std::string aboutNothing = asA.error(insert, {"987654"});
  EXPECT_EQ(aboutB.find("bench-b"), std::string::npos) << aboutB;
  const auto headB = Sql(admin_).value("SELECT head_seq FROM leafdig.sessions WHERE id = $1", {other.serverId});
  EXPECT_EQ(aboutB.find(" " + headB), std::string::npos) << "event count leaked: " << aboutB;
  // The same words as for a session that does not exist at all, but for its number.
  std::string x = aboutB;
  x.replace(x.find(other.serverId), other.serverId.size(), "987654");
  EXPECT_EQ(x, aboutNothing);
  // …also when the event names station bench-b itself.
  const std::string named = asA.error(
      "INSERT INTO leafdig.events(session_id, station, seq, utc, mono_ns, kind, payload_json, raw, prev_hash, hash) "
      "VALUES ($1, 'bench-b', 1, 't', 1, 'paused', '{}', '', 'x', 'y')",
      {other.serverId});
  EXPECT_EQ(named.find("bench-b:"), std::string::npos) << named;
  EXPECT_EQ(named.find(" " + headB), std::string::npos) << named;
}

TEST_F(Lab, OnlyWhatLeafdigWritesIsTakenSoNoSessionIsLeftUnreadable) {
  db::Store station(file("a.sqlite"));
  const std::string tech = login(db::LabRole::Technician, "bench-a");
  const Pushed s = pushOne(station, "bench-a", tech, /*complete=*/false);
  Sql asTech(tech);
  const std::vector<std::pair<std::pair<std::string, std::string>, std::string>> bad{
      {{"accepted", "not json"}, "its payload is not JSON"},
      {{"accepted", "[1,2]"}, "not a JSON object"},
      {{"hack", "{}"}, "its kind is not one leafdig writes"},
      {{"accepted", R"({"what":"marker","row":1,"col":1})"}, "its payload is not an item"},
      {{"accepted", R"({"what":"marker","row":1,"col":1,"position_mm":[1,2]})"}, "its payload is not an item"},
      {{"accepted", R"({"what":"lasers","row":1,"col":1,"value_mm":1})"}, "its payload is not an item"},
      {{"accepted", R"({"what":"midrib_thickness","row":1,"col":4,"value_mm":-1})"}, "its payload is not an item"},
      {{"undone", R"({"what":"marker","seq":"3"})"}, "does not name an earlier event"},
      {{"undone", R"({"what":"marker","seq":99999})"}, "does not name an earlier event"},
      {{"undone", R"({"what":"marker","seq":1.5})"}, "does not name an earlier event"},
  };
  for (const auto& [event, words] : bad) {
    const std::string refused = appendBySql(asTech, s, "bench-a", event.first, event.second);
    EXPECT_NE(refused.find(words), std::string::npos) << event.first << " " << event.second << ": " << refused;
  }
  // An undo names a captured item: event 2 (the first marker) yes; a `rows_ended` no.
  const auto rowsEnded =
      Sql(admin_).value("SELECT seq FROM leafdig.events WHERE session_id = $1 AND kind = 'rows_ended'", {s.serverId});
  EXPECT_NE(appendBySql(asTech, s, "bench-a", "undone", R"({"what":"marker","seq":)" + rowsEnded + "}")
                .find("which is not a captured item"),
            std::string::npos);
  // The session still reads on the server and pulls at the station.
  db::LabStore reader(login(db::LabRole::Reader));
  EXPECT_TRUE(reader.verify(std::stoll(s.serverId)).ok);
  EXPECT_FALSE(reader.markers(std::stoll(s.serverId)).empty());
  EXPECT_TRUE(db::pull(station, tech).problems.empty());
}

// One definition of a valid event (issue 47): every case of tests/data/event_cases.json is
// decided alike by the server (plain SQL as the role that would write it) and by the
// station's reader (db::eventProblem, then the replay of the whole session). A case the
// server takes and the station refuses fails here, as does one the server takes wrongly.
TEST_F(Lab, TheServerAndTheStationDecideEveryEventCaseAlike) {
  std::ifstream in(std::string(LEAFDIG_SOURCE_DIR) + "/tests/data/event_cases.json");
  ASSERT_TRUE(in) << "tests/data/event_cases.json";
  const nlohmann::json table = nlohmann::json::parse(in);
  const std::string curator = login(db::LabRole::Curator);
  const std::string curatorLogin = Sql(curator).value("SELECT session_user");
  const std::string other = Sql(admin_).value("SELECT session_user");
  int n = 0;
  for (const auto& c : table.at("cases")) {
    const std::string name = c.at("name").get<std::string>();
    const bool complete = c.at("state") == "complete";
    // Each case on a station of its own (a session's id is its station's).
    const std::string stationName = "case-" + std::to_string(++n);
    const std::string tech = login(db::LabRole::Technician, stationName);
    db::Store station(file(stationName + ".sqlite"));
    const Pushed s = pushOne(station, stationName, tech, complete);
    // The seqs the payloads name, read from the station's own projections and events.
    std::string marker, undone, midrib;
    for (const auto& m : station.markers(s.stationId))
      if (m.what == "marker" && m.row == 1 && m.col == 1) marker = std::to_string(m.seq);
    for (const auto& t : station.thickness(s.stationId))
      if (t.what == "midrib_thickness" && t.row == 1) midrib = std::to_string(t.seq);
    for (const auto& e : station.events(s.stationId))
      if (e.kind == "undone") undone = std::to_string(nlohmann::json::parse(e.payloadJson).at("seq").get<int>());
    ASSERT_FALSE(marker.empty() || undone.empty() || midrib.empty());
    const std::string writer = complete ? curatorLogin : Sql(tech).value("SELECT session_user");
    const auto fill = [&](std::string t) {
      for (const auto& [token, value] :
           std::vector<std::pair<std::string, std::string>>{{"$MARKER", marker},
                                                            {"$UNDONE", undone},
                                                            {"$MIDRIB", midrib},
                                                            {"$LOGIN", writer},
                                                            {"$OTHER", other},
                                                            {"$BIG", std::string(70000, 'x')}})
        for (std::size_t at = t.find(token); at != std::string::npos; at = t.find(token, at + value.size()))
          t.replace(at, token.size(), value);
      return t;
    };
    // The station's verdict: the reader's rules for each new event, then the replay of all.
    std::vector<db::Event> events = station.events(s.stationId);
    std::vector<std::pair<std::string, std::string>> added;
    for (const auto& b : c.value("before", nlohmann::json::array()))
      added.emplace_back(b.at("kind").get<std::string>(), fill(b.at("payload").get<std::string>()));
    added.emplace_back(c.at("kind").get<std::string>(), fill(c.at("payload").get<std::string>()));
    std::string stationWords;
    for (const auto& [kind, payload] : added) {
      db::Event e;
      e.session = s.stationId;
      e.seq = events.back().seq + 1;
      e.kind = kind;
      e.payloadJson = payload;
      if (const auto problem = db::eventProblem(kind, payload, "")) stationWords = *problem;
      events.push_back(e);
    }
    if (stationWords.empty()) {
      try {
        leafdig::acquisition::requireReplays(*station.session(s.stationId), events);
      } catch (const std::exception& e) {
        stationWords = e.what();
      }
    }
    // The server's verdict, through plain SQL as the login that would write it.
    std::string serverWords;
    for (std::size_t k = 0; k < added.size(); ++k) {
      serverWords = appendBySql(Sql(complete ? curator : tech), s, stationName, added[k].first, added[k].second);
      if (k + 1 < added.size()) {
        ASSERT_EQ(serverWords, "") << name << ": its 'before' event was refused";
      }
    }
    const bool valid = c.at("valid").get<bool>();
    EXPECT_EQ(serverWords.empty(), valid) << name << " — the server says: " << serverWords;
    if (valid || !c.value("server_only", false)) {
      EXPECT_EQ(stationWords.empty(), valid) << name << " — the station says: " << stationWords;
    }
    // Whatever the server took, the station pulls and reads: no session is left unreadable.
    if (serverWords.empty()) {
      db::SyncOptions options;
      options.replays = leafdig::acquisition::requireReplays;
      const auto pulled = db::pull(station, tech, options);
      if (complete) {
        EXPECT_TRUE(pulled.problems.empty()) << name << ": " << pulled.problems.front().problem;
        EXPECT_TRUE(station.verify(s.stationId).ok) << name;
      }
    }
  }
}

// A tampered server (issue 47, 14): its owner disables the triggers and appends, with valid
// hashes, an undo of a marker, a new point and a status that reopens the completed capture.
// `sync pull` takes none of it — only a curator's review of a completed capture comes back —
// and says so in words; the station's file is unchanged and still verifies.
TEST_F(Lab, ATamperedServerCannotRewriteOrReopenACompletedCaptureThroughPull) {
  db::Store station(file("a.sqlite"));
  const std::string tech = login(db::LabRole::Technician, "bench-a");
  const Pushed s = pushOne(station, "bench-a", tech, /*complete=*/true);
  const auto before = fileEvents(station);
  const std::string marker = std::to_string(station.markers(s.stationId).front().seq);
  const auto m = station.markers(s.stationId).front();
  const std::string item = R"({"what":"marker","row":)" + std::to_string(*m.row) + R"(,"col":)" +
                           std::to_string(*m.col) + R"(,"position_mm":[1,2,3])";
  const std::vector<std::pair<std::string, std::string>> forged{
      {"undone", item + R"(,"seq":)" + marker + "}"},
      {"accepted", R"({"what":"marker","row":9,"col":1,"position_mm":[500,500,500]})"},
      {"status", R"({"status":"open","who":"ana","why":"reopened"})"},
  };
  // The owner, past the triggers: `change`, then the session's head moved as the triggers would.
  const auto asTamperingOwner = [&](const std::function<void(Sql&)>& change) {
    Sql owner(admin_);
    (void)owner.rows("ALTER TABLE leafdig.events DISABLE TRIGGER USER");
    change(owner);
    (void)owner.rows(
        "UPDATE leafdig.sessions x SET head_seq = e.seq, head_hash = e.hash FROM leafdig.events e "
        "WHERE x.id = $1 AND e.session_id = x.id AND e.seq = (SELECT max(seq) FROM leafdig.events WHERE session_id = "
        "x.id)",
        {s.serverId});
    (void)owner.rows("ALTER TABLE leafdig.events ENABLE TRIGGER USER");
  };
  for (const auto& [kind, payload] : forged) {
    asTamperingOwner([&](Sql& owner) { EXPECT_EQ(appendBySql(owner, s, "bench-a", kind, payload), "") << kind; });
    db::SyncOptions options;
    options.replays = leafdig::acquisition::requireReplays;
    const auto pulled = db::pull(station, tech, options);
    ASSERT_EQ(pulled.problems.size(), 1u) << kind;
    EXPECT_EQ(pulled.eventsTaken, 0) << kind;
    EXPECT_NE(pulled.problems.front().problem.find("is not a curator's correction, decision or reopening"),
              std::string::npos)
        << pulled.problems.front().problem;
    EXPECT_NE(pulled.problems.front().remedy.find("nothing of the session was taken in"), std::string::npos);
    EXPECT_EQ(fileEvents(station), before) << kind;
    EXPECT_EQ(station.session(s.stationId)->status, "complete");
    EXPECT_TRUE(station.verify(s.stationId).ok);
    // Remove the forged event again (the owner may), so the next forgery stands alone.
    asTamperingOwner([&](Sql& owner) {
      (void)owner.rows("DELETE FROM leafdig.events WHERE session_id = $1 AND seq > $2",
                       {s.serverId, std::to_string(before.begin()->second.size())});
    });
  }
  // A correction that names one item and carries another, forged past the triggers: refused
  // by the station's replay, nothing taken.
  const auto reading = station.thickness(s.stationId).front();
  nlohmann::json bad{{"what", "marker"},   {"row", *m.row}, {"col", *m.col}, {"position_mm", {1, 2, 3}},
                     {"seq", reading.seq}, {"reason", "r"}, {"who", "carla"}};
  bad["corrected"] = {{"what", "marker"}, {"row", *m.row}, {"col", *m.col}, {"position_mm", {4, 5, 6}}};
  asTamperingOwner([&](Sql& owner) { EXPECT_EQ(appendBySql(owner, s, "bench-a", "corrected", bad.dump()), ""); });
  db::SyncOptions options;
  options.replays = leafdig::acquisition::requireReplays;
  const auto pulled = db::pull(station, tech, options);
  ASSERT_EQ(pulled.problems.size(), 1u);
  EXPECT_NE(pulled.problems.front().problem.find("does not replay"), std::string::npos)
      << pulled.problems.front().problem;
  EXPECT_EQ(fileEvents(station), before);
}

// A review is signed by the login that writes it (issue 47, 6 and 16): a curator cannot sign
// as another login, and a login cannot be a curator and its station's technician at once.
TEST_F(Lab, AReviewIsSignedByItsOwnLoginAndNobodyReviewsTheirOwnCapture) {
  db::Store station(file("a.sqlite"));
  const std::string tech = login(db::LabRole::Technician, "bench-a");
  const Pushed s = pushOne(station, "bench-a", tech, /*complete=*/true);
  const std::string carla = login(db::LabRole::Curator);
  const std::string bob = login(db::LabRole::Curator);
  const std::string bobLogin = Sql(bob).value("SELECT session_user");
  const std::string carlaLogin = Sql(carla).value("SELECT session_user");
  // carla signs as bob: refused by plain SQL and through LabStore; as herself or a display name: taken.
  EXPECT_NE(
      appendBySql(Sql(carla), s, "bench-a", "status", R"({"status":"approved","who":")" + bobLogin + R"(","why":""})")
          .find("a review is signed by the login that writes it"),
      std::string::npos);
  // Through leafdig, bob's login given as a name is carla's signature: "bob (carla)".
  EXPECT_EQ(db::LabStore(carla).signature(bobLogin), bobLogin + " (" + carlaLogin + ")");
  // A display name alone hides the login (schema 11): refused by plain SQL; leafdig signs it
  // "NAME (login)", which a login cannot forge for another ("carla (bob)" written by carla).
  EXPECT_NE(appendBySql(Sql(carla), s, "bench-a", "status", R"({"status":"approved","who":"Dr Carla","why":""})")
                .find("a review is signed by the login that writes it (\"" + carlaLogin + "\", or \"NAME (" +
                      carlaLogin + ")\")"),
            std::string::npos);
  EXPECT_NE(
      appendBySql(Sql(carla), s, "bench-a", "status",
                  nlohmann::json{{"status", "approved"}, {"who", "Dr Bob (" + bobLogin + ")"}, {"why", ""}}.dump())
          .find("a review is signed by the login that writes it"),
      std::string::npos);
  db::LabStore asCarla(carla);
  EXPECT_EQ(asCarla.signature("Dr Carla"), "Dr Carla (" + carlaLogin + ")");
  EXPECT_EQ(asCarla.signature("  "), carlaLogin);
  EXPECT_EQ(asCarla.signature(carlaLogin), carlaLogin);
  EXPECT_EQ(asCarla.signature("Dr Carla (" + carlaLogin + ")"), "Dr Carla (" + carlaLogin + ")");
  EXPECT_EQ(statusOf(s), "complete");
  // add-user will not make one login two roles; the server refuses a technician's review
  // even if an administrator grants the group by hand.
  const std::string techLogin = Sql(tech).value("SELECT session_user");
  try {
    (void)db::addUser(admin_, techLogin, db::LabRole::Curator, "", std::nullopt);
    ADD_FAILURE() << "a technician was made a curator too";
  } catch (const db::StoreError& e) {
    EXPECT_NE(std::string(e.what()).find("is already a technician"), std::string::npos) << e.what();
  }
  (void)Sql(admin_).rows("GRANT leafdig_curators TO " + techLogin);
  EXPECT_NE(
      appendBySql(Sql(tech), s, "bench-a", "status", R"({"status":"approved","who":")" + techLogin + R"(","why":""})")
          .find("nobody reviews their own capture"),
      std::string::npos);
  EXPECT_EQ(appendBySql(Sql(carla), s, "bench-a", "status",
                        R"({"status":"approved","who":")" + carlaLogin + R"(","why":"ok"})"),
            "");
  EXPECT_EQ(Sql(admin_).value("SELECT written_by FROM leafdig.events WHERE session_id = $1 AND kind = 'status' "
                              "ORDER BY seq DESC LIMIT 1",
                              {s.serverId}),
            carlaLogin);
}

// What statistics tell (issue 47, 8): a technician no longer reads how many rows every station
// pushed through pg_stat_user_tables or its functions (init as the cluster's superuser takes
// them from PUBLIC in this database only); the administrator still does.
TEST_F(Lab, ATechnicianReadsNoTableStatisticsOfOtherStations) {
  db::Store a(file("a.sqlite"));
  db::Store b(file("b.sqlite"));
  const std::string techA = login(db::LabRole::Technician, "bench-a");
  const std::string techB = login(db::LabRole::Technician, "bench-b");
  (void)pushOne(a, "bench-a", techA, /*complete=*/true);
  (void)pushOne(b, "bench-b", techB, /*complete=*/true);
  Sql tech(techA);
  for (const char* query : {"SELECT n_tup_ins FROM pg_stat_user_tables WHERE relname = 'events'",
                            "SELECT n_tup_ins FROM pg_stat_xact_all_tables WHERE relname = 'events'",
                            "SELECT heap_blks_read FROM pg_statio_user_tables WHERE relname = 'events'",
                            "SELECT pg_stat_get_live_tuples('leafdig.events'::regclass)",
                            "SELECT pg_stat_get_tuples_inserted('leafdig.sessions'::regclass)"})
    EXPECT_NE(tech.error(query).find("permission denied"), std::string::npos) << query;
  // The lab's own rows stay the technician's to read; the administrator reads the statistics.
  EXPECT_EQ(tech.value("SELECT count(DISTINCT station) FROM leafdig.sessions"), "1");
  EXPECT_NO_THROW((void)Sql(admin_).rows("SELECT n_tup_ins FROM pg_stat_user_tables"));
  // Run again, init finds nothing left to take.
  EXPECT_TRUE(db::initServer(admin_).notes.empty());
}

// Roles and limits (issue 47, 7 and 9): a lab's login connects to its own lab's database only
// (the group roles are the cluster's), each login has a connection limit and timeouts, and an
// upgrade that a reader's open transaction blocks gives up in words naming that reader.
TEST_F(Lab, ALoginReachesItsOwnLabOnlyWithinLimitsAndAnUpgradeNamesWhatBlocksIt) {
  const std::string curatorA = login(db::LabRole::Curator);
  const std::string labB = clusterOf().createDatabase();
  (void)db::initServer(clusterOf().adminUrl(labB));
  const std::string curatorLogin = Sql(curatorA).value("SELECT session_user");
  const std::string inB = clusterOf().url(curatorLogin, "pw \"" + curatorLogin + "\" 's", labB);
  try {
    Sql reach(inB);
    ADD_FAILURE() << "a curator of lab A connected to lab B";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("permission denied for database"), std::string::npos) << e.what();
  }
  const auto limits = Sql(admin_).rows("SELECT rolconnlimit::text FROM pg_roles WHERE rolname = $1", {curatorLogin});
  EXPECT_EQ(limits.at(0).at(0), std::to_string(db::kLoginConnectionLimit));
  Sql asCurator(curatorA);
  EXPECT_EQ(asCurator.value("SHOW idle_in_transaction_session_timeout"), "1min");
  EXPECT_EQ(asCurator.value("SHOW statement_timeout"), "5min");
  // A reader's transaction left open on the schema: the upgrade gives up after --lock-wait.
  const std::string reader = login(db::LabRole::Reader);
  const std::string readerLogin = Sql(reader).value("SELECT session_user");
  Sql open(reader);
  (void)open.rows("BEGIN");
  (void)open.rows("SELECT count(*) FROM leafdig.sessions");
  (void)Sql(admin_).value("UPDATE leafdig.meta SET value = '9' WHERE key = 'schema_version' RETURNING value");
  try {
    (void)db::initServer(admin_, 1.0);
    ADD_FAILURE() << "init did not wait for the reader";
  } catch (const db::StoreError& e) {
    EXPECT_NE(std::string(e.what()).find("login " + readerLogin), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("holds the leafdig tables"), std::string::npos) << e.what();
    EXPECT_NE(e.remedy().find("pg_terminate_backend"), std::string::npos) << e.remedy();
  }
  EXPECT_EQ(Sql(admin_).value("SELECT value FROM leafdig.meta WHERE key = 'schema_version'"), "9");
  (void)open.rows("COMMIT");
  EXPECT_EQ(db::initServer(admin_, 5.0).toVersion, db::kLabSchemaVersion);
}

// Nothing already captured becomes unreadable (issue 47): a station file written by the
// leafdig before this change (station schema 2, every genesis of form 1: tests/data/legacy/)
// pushed to a lab server at schema 9 as released, which `server init` then upgrades to 10.
// Its sessions still verify, show and take a curator's decision under the new rules; the
// station file upgrades when opened for writing, and a session captured after that (form 2,
// its station in its genesis) goes to the same server.
TEST_F(Lab, SessionsWrittenBeforeTheUpgradeStillReadOnTheServerAndTheStation) {
  const std::string old = clusterOf().createDatabase();
  const std::string oldAdmin = clusterOf().adminUrl(old);
  {
    Sql a(oldAdmin);
    std::string all = "BEGIN;\n";
    for (int v = 0; v < 9; ++v) all += db::detail::kLabMigrations[static_cast<std::size_t>(v)];
    all += "INSERT INTO leafdig.meta(key, value) VALUES ('schema_version', '9'); COMMIT;";
    a.script(all);
  }
  const std::string name = "legacy_tech_" + old;
  (void)db::addUser(oldAdmin, name, db::LabRole::Technician, "legacy-bench", "pw");
  const std::string tech = clusterOf().url(name, "pw", old);
  fs::copy_file(std::string(LEAFDIG_SOURCE_DIR) + "/tests/data/legacy/station-schema2.sqlite", file("legacy.sqlite"));
  db::Store station(file("legacy.sqlite"));
  const auto sessions = station.sessions();
  ASSERT_GE(sessions.size(), 2u);
  for (const auto& s : sessions) {
    EXPECT_EQ(s.genesisForm, 1) << s.id;
    EXPECT_TRUE(station.verify(s.id).ok) << s.id << ": " << station.verify(s.id).problem;
  }
  const auto pushed = db::push(station, tech);
  ASSERT_TRUE(pushed.problems.empty()) << pushed.problems.front().problem;
  // The upgrade; then the server's copy reads, verifies and takes a decision.
  EXPECT_EQ(db::initServer(oldAdmin).toVersion, db::kLabSchemaVersion);
  const std::string curatorName = "legacy_curator_" + old;
  (void)db::addUser(oldAdmin, curatorName, db::LabRole::Curator, "", "pw");
  db::LabStore curator(clusterOf().url(curatorName, "pw", old));
  std::int64_t decided = 0;
  for (const auto& s : curator.sessions()) {
    EXPECT_EQ(s.genesisForm, 1);
    EXPECT_TRUE(curator.verify(s.id).ok) << curator.verify(s.id).problem;
    EXPECT_FALSE(curator.events(s.id).empty());
    if (s.status == "complete" && decided == 0) {
      (void)curator.setStatus(s.id, "approved", curatorName, "read after the upgrade");
      decided = s.stationSessionId;
    }
  }
  ASSERT_NE(decided, 0);
  db::SyncOptions options;
  options.replays = leafdig::acquisition::requireReplays;
  const auto pulled = db::pull(station, tech, options);
  EXPECT_TRUE(pulled.problems.empty()) << pulled.problems.front().problem;
  EXPECT_EQ(station.session(decided)->status, "approved");
  // A session captured now is of form 2 and goes to the upgraded server whole.
  const auto fresh = captureSession(station, "legacy-bench", 9);
  EXPECT_EQ(station.session(fresh)->genesisForm, 2);
  EXPECT_TRUE(station.verify(fresh).ok);
  EXPECT_TRUE(db::push(station, tech).problems.empty());
  bool found = false;
  for (const auto& s : curator.sessions())
    if (s.stationSessionId == fresh) {
      found = true;
      EXPECT_EQ(s.genesisForm, 2);
      EXPECT_TRUE(curator.verify(s.id).ok);
    }
  EXPECT_TRUE(found);
}

// The station is in a new session's chain (issue 47, 15): a copy of another station's file
// with its station edited no longer verifies, at the station or on the server.
TEST_F(Lab, AStationIdEditedIntoACopyOfAnotherStationsFileIsRefused) {
  const fs::path path = file("a.sqlite");
  {
    db::Store a(path.string());
    (void)captureSession(a, "bench-a", 1);
  }
  {
    // The copy, edited as a technician of bench-b would with sqlite3.
    db::Store probe(path.string());
    ASSERT_TRUE(probe.verify(1).ok);
  }
  const fs::path copy = file("copy.sqlite");
  fs::copy_file(path, copy);
  {
    sqlite3* h = nullptr;
    ASSERT_EQ(sqlite3_open(copy.c_str(), &h), SQLITE_OK);
    ASSERT_EQ(sqlite3_exec(h, "UPDATE sessions SET station = 'bench-b'", nullptr, nullptr, nullptr), SQLITE_OK);
    sqlite3_close(h);
  }
  db::Store edited(copy.string());
  const auto report = edited.verify(1);
  EXPECT_FALSE(report.ok);
  EXPECT_NE(report.problem.find("its station, kind, creation time or settings were changed"), std::string::npos)
      << report.problem;
  // Pushed by bench-b's technician: the session's genesis (worked out for bench-b) is not the
  // one its first event follows, so the server takes none of its events.
  const std::string techB = login(db::LabRole::Technician, "bench-b");
  const auto pushed = db::push(edited, techB);
  ASSERT_EQ(pushed.problems.size(), 1u);
  EXPECT_NE(pushed.problems.front().problem.find("event 1 does not follow"), std::string::npos)
      << pushed.problems.front().problem;
  EXPECT_EQ(Sql(admin_).value("SELECT count(*) FROM leafdig.events e JOIN leafdig.sessions s ON s.id = e.session_id "
                              "WHERE s.station = 'bench-b'"),
            "0");
  // And a session row whose genesis was kept as it was (byte-identical, as a copy has it)
  // is refused by the server's own recomputation.
  Sql asB(techB);
  const auto info = *edited.session(1);
  const std::string refused = asB.error(
      "INSERT INTO leafdig.sessions(station, station_session_id, project, plant, leaf_position, operator, mode, "
      "capture_order, settings_json, created_utc, genesis_hash, genesis_form) VALUES ('bench-b', 1, $1, $2, 1, $3, "
      "$4, $5, $6, $7, $8, 2)",
      {info.project, info.plant, info.operatorName, info.mode, info.order, info.settingsJson, info.createdUtc,
       db::genesisOf(*db::Store(path.string()).session(1))});
  EXPECT_NE(refused.find("does not hash to its genesis hash"), std::string::npos) << refused;
}

TEST_F(Lab, InitWaitsForItsLockAndThenNamesWhoHoldsIt) {
  const std::string reader = login(db::LabRole::Reader);
  Sql holder(reader);
  ASSERT_EQ(holder.value("SELECT pg_advisory_lock(4710468163)::text"), "");  // void
  const std::string readerLogin = holder.value("SELECT current_user");
  try {
    (void)db::initServer(admin_, 0.5);
    FAIL() << "init ran while another login held its lock";
  } catch (const db::StoreError& e) {
    EXPECT_EQ(e.kind(), db::StoreErrorKind::Busy) << e.what();
    EXPECT_NE(std::string(e.what()).find("login " + readerLogin), std::string::npos) << e.what();
    EXPECT_NE(e.remedy().find("pg_terminate_backend"), std::string::npos) << e.remedy();
  }
  (void)holder.value("SELECT pg_advisory_unlock(4710468163)::text");
  EXPECT_EQ(db::initServer(admin_, 0.5).toVersion, db::kLabSchemaVersion);
}

TEST_F(Lab, ACuratorsDecisionsComeBackToTheStationThatCapturedTheSession) {
  db::Store station(file("a.sqlite"));
  const auto id = captureSession(station, "bench-a", 1);
  const auto other = captureSession(station, "bench-a", 2);
  const std::string tech = login(db::LabRole::Technician, "bench-a");
  ASSERT_TRUE(db::push(station, tech).problems.empty());
  db::LabStore curator(login(db::LabRole::Curator));
  std::int64_t serverId = 0;
  for (const auto& s : curator.sessions())
    if (s.stationSessionId == id) serverId = s.id;
  // A correction of the row-2 midrib reading, then the approval.
  const auto oldReading = station.thickness(id)[2];
  ASSERT_EQ(oldReading.what, "midrib_thickness");
  nlohmann::json payload{{"what", oldReading.what},          {"row", *oldReading.row}, {"col", *oldReading.col},
                         {"value_mm", oldReading.valueMm},   {"seq", oldReading.seq},  {"reason", "slipped"},
                         {"who", curator.signature("carla")}};
  payload["corrected"] = {
      {"what", oldReading.what}, {"row", *oldReading.row}, {"col", *oldReading.col}, {"value_mm", 1.25}};
  db::EventInput corrected;
  corrected.kind = "corrected";
  corrected.payloadJson = payload.dump();
  corrected.raw = "corrected by carla";
  (void)curator.append(serverId, corrected);
  (void)curator.setStatus(serverId, "approved", "carla", "");

  const auto pushed = db::push(station, tech);  // nothing to send: the server is ahead
  EXPECT_EQ(pushed.eventsSent, 0);
  EXPECT_EQ(pushed.sessionsBehind, 1);
  const auto pulled = db::pull(station, tech);
  EXPECT_TRUE(pulled.problems.empty());
  EXPECT_EQ(pulled.sessionsUpdated, 1);
  EXPECT_EQ(pulled.eventsTaken, 2);
  EXPECT_EQ(station.session(id)->status, "approved");
  EXPECT_EQ(station.session(other)->status, "complete");
  EXPECT_TRUE(station.verify(id).ok);
  EXPECT_EQ(serverEvents(), fileEvents(station));
  bool found = false;
  for (const auto& t : station.thickness(id))
    if (t.what == "midrib_thickness" && t.row == oldReading.row) {
      found = true;
      EXPECT_DOUBLE_EQ(t.valueMm, 1.25);
    }
  EXPECT_TRUE(found);
  EXPECT_EQ(db::pull(station, tech).eventsTaken, 0);  // again: nothing
  EXPECT_EQ(db::push(station, tech).eventsSent, 0);
}

TEST_F(Lab, FourStationsPushAtOnceWhileACuratorApprovesAndTheServerHoldsExactlyTheirUnion) {
  constexpr int kStations = 4;
  std::vector<std::unique_ptr<db::Store>> files;
  std::vector<std::string> urls;
  for (int k = 0; k < kStations; ++k) {
    const std::string station = "bench-" + std::to_string(k);
    files.push_back(std::make_unique<db::Store>(file(station + ".sqlite")));
    for (int leaf = 1; leaf <= 6; ++leaf) (void)captureSession(*files.back(), station, leaf, 3 + leaf % 3);
    urls.push_back(login(db::LabRole::Technician, station));
  }
  const std::string curatorUrl = login(db::LabRole::Curator);
  std::atomic<bool> pushing{true};
  std::atomic<int> approved{0};
  std::thread curator([&] {
    db::LabStore store(curatorUrl);
    std::set<std::int64_t> done;
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(120);
    while ((pushing || done.size() < static_cast<std::size_t>(kStations * 6)) &&
           std::chrono::steady_clock::now() < deadline) {
      for (const auto& s : store.sessions()) {
        // A session is approved once all of it has arrived (its last event is `complete`).
        if (done.count(s.id) || s.status != "complete") continue;
        (void)store.setStatus(s.id, "approved", "carla", "");
        done.insert(s.id);
        ++approved;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
  });
  std::vector<std::thread> pushers;
  std::vector<db::PushReport> reports(kStations);
  for (int k = 0; k < kStations; ++k)
    pushers.emplace_back([&, k] {
      db::SyncOptions o;
      o.eventsPerTransaction = 5;
      reports[static_cast<std::size_t>(k)] =
          db::push(*files[static_cast<std::size_t>(k)], urls[static_cast<std::size_t>(k)], o);
    });
  for (auto& t : pushers) t.join();
  pushing = false;
  curator.join();
  for (const auto& r : reports) EXPECT_TRUE(r.problems.empty()) << r.problems.front().problem;
  EXPECT_EQ(approved, kStations * 6);
  // The server holds every station's events and one approval per session, nothing else.
  auto onServer = serverEvents();
  std::map<std::pair<std::string, std::int64_t>, std::vector<std::vector<std::string>>> expected;
  for (const auto& f : files)
    for (auto& [key, events] : fileEvents(*f)) expected[key] = events;
  ASSERT_EQ(onServer.size(), expected.size());
  for (auto& [key, events] : onServer) {
    ASSERT_EQ(events.size(), expected[key].size() + 1) << key.first << ":" << key.second;
    EXPECT_EQ(std::vector<std::vector<std::string>>(events.begin(), events.end() - 1), expected[key]);
    EXPECT_NE(events.back()[4].find("\"approved\""), std::string::npos);
  }
  db::LabStore reader(login(db::LabRole::Reader));
  for (const auto& s : reader.sessions()) EXPECT_TRUE(reader.verify(s.id).ok) << s.station << ":" << s.stationSessionId;
  // Each station takes its decisions in.
  for (int k = 0; k < kStations; ++k) {
    const auto r = db::pull(*files[static_cast<std::size_t>(k)], urls[static_cast<std::size_t>(k)]);
    EXPECT_EQ(r.eventsTaken, 6);
    for (const auto& s : files[static_cast<std::size_t>(k)]->sessions()) EXPECT_EQ(s.status, "approved");
  }
}

TEST_F(Lab, AConnectionCutInTheMiddleOfATransactionLosesNothingAndTheNextPushCompletes) {
  db::Store station(file("a.sqlite"));
  for (int leaf = 1; leaf <= 8; ++leaf) (void)captureSession(station, "bench-a", leaf, 8);
  const std::string name = "technician_cut_" + database_;
  (void)db::addUser(admin_, name, db::LabRole::Technician, "bench-a", std::string("pw"));
  db::SyncOptions o;
  o.eventsPerTransaction = 10;
  int cuts = 0;
  for (const std::size_t cutAfter : {30'000u, 30'000u, 30'000u}) {
    leafdig::test::CuttingProxy proxy(clusterOf().port(), cutAfter);
    try {
      (void)db::push(station, clusterOf().url(name, "pw", database_, proxy.port()), o);
    } catch (const db::StoreError& e) {
      EXPECT_EQ(e.kind(), db::StoreErrorKind::Unreachable) << e.what();
      EXPECT_EQ(std::string(e.what()).find(":pw@"), std::string::npos) << "the password stays out: " << e.what();
    }
    cuts += proxy.cuts();
    // Whatever arrived is a prefix of each session, every chain intact.
    const auto onServer = serverEvents();
    const auto local = fileEvents(station);
    for (const auto& [key, events] : onServer) {
      const auto& mine = local.at(key);
      ASSERT_LE(events.size(), mine.size());
      EXPECT_EQ(events,
                std::vector<std::vector<std::string>>(mine.begin(), mine.begin() + static_cast<long>(events.size())));
    }
  }
  EXPECT_EQ(cuts, 3) << "the proxy cut each push's connection in the middle";
  const auto rest = db::push(station, clusterOf().url(name, "pw", database_), o);
  EXPECT_TRUE(rest.problems.empty());
  EXPECT_EQ(serverEvents(), fileEvents(station));
  db::LabStore reader(login(db::LabRole::Reader));
  for (const auto& s : reader.sessions()) EXPECT_TRUE(reader.verify(s.id).ok);
}

TEST_F(Lab, HostileTextIsStoredAndReturnedUnchangedAndTextThatIsNotUtf8IsRefusedByName) {
  db::Store station(file("a.sqlite"));
  const std::string quotes = R"(P'07"; DROP TABLE leafdig.events; -- \ $1 %s)";
  const std::string longName(100'000, 'x');
  const std::string unicode = "Nicotiana tabacum \xe2\x80\x94 Blatt \xc3\xa9t\xc3\xa9 \xf0\x9f\x8c\xbf";
  const auto a = captureSession(station, "bench-a", 1, 2, quotes, longName, unicode);
  const auto bad = captureSession(station, "bench-a", 2, 2, "tobacco", "P-\xff\xfe", "ana");
  const auto c = captureSession(station, "bench-a", 3, 2);
  const auto report = db::push(station, login(db::LabRole::Technician, "bench-a"));
  ASSERT_EQ(report.problems.size(), 1u);
  EXPECT_EQ(report.problems[0].stationSessionId, bad);
  EXPECT_NE(report.problems[0].problem.find("plant is not UTF-8 text (byte 2)"), std::string::npos)
      << report.problems[0].problem;
  db::LabStore server(login(db::LabRole::Reader));
  std::set<std::int64_t> arrived;
  for (const auto& s : server.sessions()) {
    arrived.insert(s.stationSessionId);
    if (s.stationSessionId == a) {
      EXPECT_EQ(s.project, quotes);
      EXPECT_EQ(s.plant, longName);
      EXPECT_EQ(s.operatorName, unicode);
    }
  }
  EXPECT_EQ(arrived, (std::set<std::int64_t>{a, c}));
  EXPECT_EQ(Sql(admin_).value("SELECT count(*) FROM leafdig.events") != "0", true);  // the table is still there
}

TEST_F(Lab, TwoStationsThatShareAnIdAreToldApartNotMerged) {
  db::Store first(file("first.sqlite"));
  db::Store second(file("second.sqlite"));
  (void)captureSession(first, "bench-a", 1);
  (void)captureSession(second, "bench-a", 1);  // another machine, the same host name
  const std::string tech = login(db::LabRole::Technician, "bench-a");
  ASSERT_TRUE(db::push(first, tech).problems.empty());
  const auto clash = db::push(second, tech);
  ASSERT_EQ(clash.problems.size(), 1u);
  EXPECT_NE(clash.problems[0].problem.find("two stations use the id 'bench-a'"), std::string::npos);
  EXPECT_EQ(serverEvents(), fileEvents(first));
}

TEST_F(Lab, ABadPasswordOrAnUnreachableServerIsNamedWithoutThePassword) {
  const std::string name = "technician_pw_" + database_;
  (void)db::addUser(admin_, name, db::LabRole::Technician, "bench-a", std::string("right"));
  db::Store station(file("a.sqlite"));
  (void)captureSession(station, "bench-a", 1);
  for (const std::string& url : {clusterOf().url(name, "wrong-secret", database_),
                                 clusterOf().url(name, "wrong-secret", database_, leafdig::test::freeLocalPort())}) {
    try {
      (void)db::push(station, url);
      FAIL() << "pushed";
    } catch (const db::StoreError& e) {
      EXPECT_EQ(e.kind(), db::StoreErrorKind::Unreachable);
      EXPECT_EQ(std::string(e.what()).find("wrong-secret"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("***"), std::string::npos) << e.what();
    }
  }
  // A new login needs a password; a technician needs a station; others take none.
  EXPECT_THROW((void)db::addUser(admin_, "nobody_" + database_, db::LabRole::Reader, "", std::nullopt), db::StoreError);
  EXPECT_THROW((void)db::addUser(admin_, name, db::LabRole::Technician, "", std::nullopt), db::StoreError);
  EXPECT_THROW((void)db::addUser(admin_, name, db::LabRole::Curator, "bench-a", std::nullopt), db::StoreError);
  // The password is stored as a SCRAM verifier only.
  EXPECT_EQ(Sql(admin_).value("SELECT left(rolpassword, 14) FROM pg_authid WHERE rolname = $1", {name}),
            "SCRAM-SHA-256$");
}

TEST(LabTls, SyncRunsOverTlsWithTheServersCertificateVerifiedAndAWrongOneIsRefused) {
  PgCluster tls(true);
  const std::string database = tls.createDatabase();
  (void)db::initServer(tls.adminUrl(database));
  (void)db::addUser(tls.adminUrl(database), "tech_tls", db::LabRole::Technician, "bench-t", std::string("pw"));
  const fs::path dir = fs::temp_directory_path() / ("leafdig-lab-tls-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  db::Store station((dir / "s.sqlite").string());
  (void)captureSession(station, "bench-t", 1);
  // verify-full: the certificate must chain to the given root and name the host.
  const std::string url = "postgresql://tech_tls:pw@localhost:" + std::to_string(tls.port()) + "/" + database +
                          "?sslmode=verify-full&sslrootcert=" + tls.certificateFile();
  const auto report = db::push(station, url);
  EXPECT_TRUE(report.problems.empty());
  EXPECT_GT(report.eventsSent, 0);
  EXPECT_EQ(Sql(url).value("SELECT ssl::text FROM pg_stat_ssl WHERE pid = pg_backend_pid()"), "true");
  // Another root certificate (the system's, which did not sign it): refused before anything is sent.
  const std::string wrong = "postgresql://tech_tls:pw@localhost:" + std::to_string(tls.port()) + "/" + database +
                            "?sslmode=verify-full&sslrootcert=/etc/ssl/certs/ca-certificates.crt";
  try {
    (void)db::push(station, wrong);
    FAIL() << "connected with a root that did not sign the server's certificate";
  } catch (const db::StoreError& e) {
    EXPECT_EQ(e.kind(), db::StoreErrorKind::Unreachable);
    EXPECT_NE(std::string(e.what()).find("certificate"), std::string::npos) << e.what();
  }
  fs::remove_all(dir);
}

}  // namespace
