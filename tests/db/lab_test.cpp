// The lab server against a real PostgreSQL cluster started for these tests (initdb +
// pg_ctl in a temporary directory, tests/support/pg_cluster.hpp): schema and roles, push and
// pull, the server's own checks of every chain, each role's refusals, hostile text, four
// stations at once beside a curator, and a connection cut in the middle of a transaction.
// The server is read back with libpq directly (test::Sql), not through leafdig's code.
#include "leafdig/db/lab.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <thread>

#include "../support/cutting_proxy.hpp"
#include "../support/pg_cluster_environment.hpp"
#include "../support/station_sessions.hpp"
#include "leafdig/db/store.hpp"

namespace fs = std::filesystem;
namespace db = leafdig::db;
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

  fs::path dir_;
  std::string database_, admin_;
  int logins_ = 0;
};

TEST(LabUrl, PasswordsAreRedactedInEveryForm) {
  EXPECT_EQ(db::redactUrl("postgresql://tech:s3cret@lab.example:5432/leafdig"),
            "postgresql://tech:***@lab.example:5432/leafdig");
  EXPECT_EQ(db::redactUrl("postgres://tech@lab/leafdig?sslmode=verify-full&password=s3cret&x=1"),
            "postgres://tech@lab/leafdig?sslmode=verify-full&password=***&x=1");
  EXPECT_EQ(db::redactUrl("host=lab user=tech password='a b' dbname=leafdig"),
            "host=lab user=tech password=*** dbname=leafdig");
  EXPECT_EQ(db::redactUrl("postgresql://lab/leafdig"), "postgresql://lab/leafdig");
  EXPECT_TRUE(db::isServerUrl("postgresql://lab/x"));
  EXPECT_FALSE(db::isServerUrl("/home/ana/station.sqlite"));
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
  EXPECT_EQ(sql.value("SELECT value FROM leafdig.meta WHERE key = 'schema_version'"), "1");
  for (const char* role : {"leafdig_technicians", "leafdig_curators", "leafdig_readers"})
    EXPECT_EQ(sql.value("SELECT rolcanlogin::text FROM pg_roles WHERE rolname = $1", {role}), "false") << role;
  const auto again = db::initServer(admin_);
  EXPECT_EQ(again.fromVersion, 1);
  EXPECT_EQ(again.toVersion, 1);
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

TEST_F(Lab, TheServerRechecksEveryChainAndNamesTheSessionAndEventItRefuses) {
  db::Store station(file("a.sqlite"));
  const auto id = captureSession(station, "bench-a", 1);
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
  nlohmann::json payload{
      {"what", oldReading.what}, {"row", *oldReading.row}, {"col", *oldReading.col}, {"value_mm", oldReading.valueMm},
      {"seq", oldReading.seq},   {"reason", "slipped"},    {"who", "carla"}};
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
