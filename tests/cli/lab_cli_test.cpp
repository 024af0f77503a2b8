// `leafdig server` and `leafdig sync` as a lab uses them, against a real PostgreSQL cluster
// started for these tests: set-up, push, review on the server, pull; refusals with exit
// codes and words; passwords never printed; and `sync push` killed with SIGKILL at seeded
// random instants, the server checked after every kill with libpq directly.
#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>

#include <chrono>
#include <random>
#include <thread>

#include "../support/pg_cluster_environment.hpp"
#include "../support/station_sessions.hpp"
#include "../support/strict_formats.hpp"
#include "lab_cli_support.hpp"
#include "leafdig/db/lab.hpp"

namespace {

using leafdig::test::PgCluster;
using leafdig::test::Sql;

const auto* const kEnvironment = ::testing::AddGlobalTestEnvironment(new leafdig::test::PgClusterEnvironment);

TEST_F(LabCli, ALabSetsUpPushesReviewsOnTheServerAndTheStationTakesTheDecisionsIn) {
  const Result init = leafdig("server init --url " + quote(admin_) + " --json");
  ASSERT_EQ(init.exitCode, 0) << init.err;
  EXPECT_EQ(json::parse(init.out).at("to_version"), leafdig::db::kLabSchemaVersion);
  EXPECT_EQ(leafdig("server init --url " + quote(admin_) + " --json").exitCode, 0);  // again: nothing to do
  const std::string tech = addUser("tech_bench_a_" + database_, "technician", "bench-a");
  const std::string curator = addUser("carla_" + database_, "curator");
  const std::string reader = addUser("rita_" + database_, "reader");
  const fs::path file = dir_ / "station.sqlite";
  {
    leafdig::db::Store s(file.string());
    for (int leaf = 1; leaf <= 3; ++leaf) (void)leafdig::test::captureSession(s, "bench-a", leaf);
  }
  Result push = leafdig("sync push --db " + quote(file) + " --to " + quote(tech) + " --json");
  ASSERT_EQ(push.exitCode, 0) << push.err;
  const json pushed = json::parse(push.out);
  EXPECT_EQ(pushed.at("new_sessions"), 3);
  EXPECT_GT(pushed.at("events_sent").get<int>(), 90);
  // The password is not printed, even in the URL it was given in.
  EXPECT_EQ(push.out.find("s3cret"), std::string::npos) << push.out;
  EXPECT_NE(pushed.at("to").get<std::string>().find(":***@"), std::string::npos);
  push = leafdig("sync push --db " + quote(file) + " --to " + quote(tech) + " --json");
  EXPECT_EQ(json::parse(push.out).at("events_sent"), 0);
  EXPECT_EQ(json::parse(push.out).at("up_to_date"), 3);

  // The curators' list, from the server.
  const Result list = leafdig("sessions list --json --db " + quote(curator));
  ASSERT_EQ(list.exitCode, 0) << list.err;
  const json sessions = json::parse(list.out);
  ASSERT_EQ(sessions.size(), 3u);
  EXPECT_EQ(sessions[0].at("station"), "bench-a");
  const std::string first = std::to_string(sessions[0].at("id").get<int>());
  EXPECT_EQ(leafdig("sessions verify --db " + quote(reader)).exitCode, 0);
  // A technician's approval is refused by the server, in words, with exit code 2.
  const Result denied = leafdig("sessions approve " + first + " --who tom --db " + quote(tech));
  EXPECT_EQ(denied.exitCode, 2);
  EXPECT_NE(denied.err.find("may not approve, reject or correct sessions (session bench-a:1"), std::string::npos)
      << denied.err;
  EXPECT_EQ(denied.err.find("s3cret"), std::string::npos);
  // A reader's too.
  EXPECT_EQ(leafdig("sessions reject " + first + " --who rita --why x --db " + quote(reader)).exitCode, 2);
  // The curator approves; the station takes it in.
  const Result approved = leafdig("sessions approve " + first + " --who carla --db " + quote(curator));
  ASSERT_EQ(approved.exitCode, 0) << approved.err;
  const Result pull = leafdig("sync pull --db " + quote(file) + " --from " + quote(tech) + " --json");
  ASSERT_EQ(pull.exitCode, 0) << pull.err;
  EXPECT_EQ(json::parse(pull.out).at("events_taken"), 1);
  const json local = json::parse(leafdig("sessions list --json --db " + quote(file)).out);
  EXPECT_EQ(local[0].at("status"), "approved");
  EXPECT_EQ(local[1].at("status"), "complete");
  EXPECT_EQ(leafdig("sessions verify --db " + quote(file)).exitCode, 0);

  // Bad input is named: not a URL, a technician without a station, a missing password file.
  Result bad = leafdig("sync push --db " + quote(file) + " --to /tmp/not-a-server");
  EXPECT_EQ(bad.exitCode, 2);
  EXPECT_NE(bad.err.find("not a postgresql:// URL"), std::string::npos);
  bad = leafdig("server add-user --url " + quote(admin_) + " --login t2 --role technician --password-file " +
                quote(write("t2.pw", "x\n")));
  EXPECT_EQ(bad.exitCode, 2);
  EXPECT_NE(bad.err.find("give --station"), std::string::npos);
  bad = leafdig("server add-user --url " + quote(admin_) + " --login t3 --role reader --password-file " +
                quote(dir_ / "missing.pw"));
  EXPECT_EQ(bad.exitCode, 2);
  EXPECT_NE(bad.err.find("cannot read the password file"), std::string::npos);
}

// The attacks of issue 25 that go through leafdig rather than plain SQL: a station file whose
// technician reopens an approved session or writes a status outside the closed set, pushed
// with `sync push`; `server init` while another login holds its lock.
// A login bound to another station refuses every session of the file for one reason: the
// reason is said once, then how many more and which (a station of 1 000 sessions printed the
// same words 1 000 times); --json still lists each.
TEST_F(LabCli, ManySessionsRefusedForOneReasonAreToldOnceWithTheirCount) {
  ASSERT_EQ(leafdig("server init --url " + quote(admin_)).exitCode, 0);
  const std::string otherTech = addUser("tech_bench_b_" + database_, "technician", "bench-b");
  const fs::path file = dir_ / "station.sqlite";
  {
    leafdig::db::Store s(file.string());
    for (int leaf = 1; leaf <= 14; ++leaf) (void)leafdig::test::captureSession(s, "bench-a", leaf, 1);
  }
  const Result push = leafdig("sync push --db " + quote(file) + " --to " + quote(otherTech));
  EXPECT_NE(push.exitCode, 0);
  const auto count = [&](const std::string& words) {
    std::size_t n = 0;
    for (auto at = push.err.find(words); at != std::string::npos; at = push.err.find(words, at + 1)) ++n;
    return n;
  };
  EXPECT_EQ(count("not synced: "), 1u) << push.err;
  EXPECT_EQ(count("pushes for station bench-b, not for station bench-a"), 1u) << push.err;
  EXPECT_NE(push.err.find("leafdig: 13 more session(s) of station bench-a not synced for the same reason: 2, 3, 4, 5, "
                          "6, 7, 8, 9, 10, 11 and 3 more (--json lists each)"),
            std::string::npos)
      << push.err;
  const Result asJson = leafdig("sync push --db " + quote(file) + " --to " + quote(otherTech) + " --json");
  EXPECT_EQ(json::parse(asJson.out).at("problems").size(), 14u) << asJson.out;
}

TEST_F(LabCli, AStationFileCannotOverturnADecisionOrFakeOneAndInitNamesWhoHoldsItsLock) {
  ASSERT_EQ(leafdig("server init --url " + quote(admin_)).exitCode, 0);
  const std::string tech = addUser("tech_bench_d_" + database_, "technician", "bench-d");
  const std::string curator = addUser("carla_d_" + database_, "curator");
  const std::string reader = addUser("rita_d_" + database_, "reader");
  const fs::path file = dir_ / "station.sqlite";
  std::int64_t decided = 0, open = 0;
  {
    leafdig::db::Store s(file.string());
    decided = leafdig::test::captureSession(s, "bench-d", 1);
    open = leafdig::test::captureSession(s, "bench-d", 2, 3, "tobacco-2026", "P-07", "ana", /*complete=*/false);
  }
  ASSERT_EQ(leafdig("sync push --db " + quote(file) + " --to " + quote(tech)).exitCode, 0);
  const json listed = json::parse(leafdig("sessions list --json --db " + quote(curator)).out);
  const std::string serverId = std::to_string(listed[0].at("id").get<int>());
  ASSERT_EQ(leafdig("sessions approve " + serverId + " --who carla --db " + quote(curator)).exitCode, 0);
  ASSERT_EQ(leafdig("sync pull --db " + quote(file) + " --from " + quote(tech)).exitCode, 0);
  {
    leafdig::db::Store s(file.string());
    (void)s.setStatus(decided, "open", "ana", "reopened to fix a point");  // the technician's own file
    leafdig::db::EventInput fake;
    fake.kind = "status";
    fake.payloadJson = R"({"status":"approved ","who":"ana","why":""})";
    (void)s.append(open, fake);
  }
  const Result push = leafdig("sync push --db " + quote(file) + " --to " + quote(tech));
  EXPECT_EQ(push.exitCode, 1);
  EXPECT_NE(push.err.find("session bench-d:" + std::to_string(decided) + " not synced"), std::string::npos) << push.err;
  EXPECT_NE(push.err.find("the decision is final"), std::string::npos) << push.err;
  EXPECT_NE(push.err.find("its status is not one of open, complete, approved, rejected, abandoned"), std::string::npos)
      << push.err;
  const json after = json::parse(leafdig("sessions list --json --db " + quote(reader)).out);
  EXPECT_EQ(after[0].at("status"), "approved");
  EXPECT_EQ(after[1].at("status"), "open");
  // Only a curator reopens the decision, saying why (issue 49): the technician's and the
  // reader's logins are refused by the server (exit 2, its words), the curator's is taken.
  for (const std::string& login : {tech, reader}) {
    const Result refused = leafdig("sessions reopen " + serverId + " --why 'fix a point' --db " + quote(login));
    EXPECT_EQ(refused.exitCode, 2) << refused.err;
    EXPECT_EQ(json::parse(leafdig("sessions list --json --db " + quote(reader)).out)[0].at("status"), "approved");
  }
  const Result reopened = leafdig("sessions reopen " + serverId + " --why 'a point to fix' --db " + quote(curator));
  ASSERT_EQ(reopened.exitCode, 0) << reopened.err;
  EXPECT_EQ(json::parse(leafdig("sessions list --json --db " + quote(reader)).out)[0].at("status"), "complete");
  ASSERT_EQ(leafdig("sessions approve " + serverId + " --who carla --db " + quote(curator)).exitCode, 0);
  // Init waits a moment for its lock, then says which login holds it.
  Sql holder(reader);
  (void)holder.value("SELECT pg_advisory_lock(4710468163)::text");
  const Result blocked = leafdig("server init --lock-wait 1 --url " + quote(admin_));
  EXPECT_EQ(blocked.exitCode, 1);
  EXPECT_NE(blocked.err.find("holds it"), std::string::npos) << blocked.err;
  EXPECT_NE(blocked.err.find("login rita_d_" + database_), std::string::npos) << blocked.err;
  (void)holder.value("SELECT pg_advisory_unlock(4710468163)::text");
  EXPECT_EQ(leafdig("server init --lock-wait 1 --url " + quote(admin_)).exitCode, 0);
}

TEST_F(LabCli, ACapturedLeafIsShownCorrectedAndExportedFromTheServerAsFromItsFile) {
  ASSERT_EQ(leafdig("server init --url " + quote(admin_)).exitCode, 0);
  const std::string tech = addUser("tech_bench_c_" + database_, "technician", "bench-c");
  const std::string curator = addUser("carla_c_" + database_, "curator");
  const fs::path file = dir_ / "station.sqlite";
  // A real capture (simulated devices, the virtual technician), at this station's id.
  const Result captured = leafdig("capture --simulate --speed 12 --no-mistakes --station bench-c --db " + quote(file) +
                                  " --markers " + quote(sample("lower-leaf-n10.markers.json")) + " </dev/null");
  ASSERT_EQ(captured.exitCode, 0) << captured.err;
  EXPECT_EQ(leafdig("capture --simulate --station 'bad id' --db " + quote(file)).exitCode, 2);
  const Result intoServer = leafdig("capture --simulate --db " + quote(tech));
  EXPECT_EQ(intoServer.exitCode, 2);
  EXPECT_NE(intoServer.err.find("capture writes the station's own file"), std::string::npos) << intoServer.err;
  EXPECT_EQ(intoServer.err.find("s3cret"), std::string::npos);
  ASSERT_EQ(leafdig("sync push --db " + quote(file) + " --to " + quote(tech)).exitCode, 0);
  const json list = json::parse(leafdig("sessions list --json --db " + quote(curator)).out);
  ASSERT_EQ(list.size(), 1u);
  EXPECT_EQ(list[0].at("station"), "bench-c");
  const std::string id = std::to_string(list[0].at("id").get<int>());
  // `show` from the server equals `show` from the file, but for the server's own id.
  json fromServer = json::parse(leafdig("sessions show " + id + " --json --db " + quote(curator)).out);
  json fromFile = json::parse(leafdig("sessions show 1 --json --db " + quote(file)).out);
  EXPECT_EQ(fromServer.at("chain_ok"), true);
  for (const char* key : {"markers", "thickness", "tip", "status", "events", "step", "station"})
    EXPECT_EQ(fromServer.at(key), fromFile.at(key)) << key;
  // A curator corrects a reading on the server; the export carries it; the station takes it in.
  const Result corrected = leafdig("sessions correct " + id +
                                   " --what midrib_thickness --row 2 --col 4 --value 1.7 --who carla "
                                   "--why 'caliper on the vein' --db " +
                                   quote(curator));
  ASSERT_EQ(corrected.exitCode, 0) << corrected.err;
  const Result exported = leafdig("sessions export " + id + " --format markers,csv --out " + quote(dir_ / "out") +
                                  " --db " + quote(curator));
  ASSERT_EQ(exported.exitCode, 0) << exported.err;
  const std::string thickness = slurp(dir_ / "out" / ("session-" + id + ".thickness.csv"));
  EXPECT_NE(thickness.find("1.7"), std::string::npos) << thickness;
  EXPECT_EQ(Sql(admin_).value("SELECT count(*) FROM leafdig.exports"), "4");  // markers JSON + three CSVs, recorded
  ASSERT_EQ(leafdig("sync pull --db " + quote(file) + " --from " + quote(tech)).exitCode, 0);
  fromFile = json::parse(leafdig("sessions show 1 --json --db " + quote(file)).out);
  fromServer = json::parse(leafdig("sessions show " + id + " --json --db " + quote(curator)).out);
  EXPECT_EQ(fromServer.at("thickness"), fromFile.at("thickness"));
  EXPECT_EQ(fromServer.at("events"), fromFile.at("events"));
}

TEST_F(LabCli, APlantCapturedAtTheStationIsPushedSurveyedExportedAndApprovedOnTheServer) {
  ASSERT_EQ(leafdig("server init --url " + quote(admin_)).exitCode, 0);
  const std::string tech = addUser("tech_bench_p_" + database_, "technician", "bench-p");
  const std::string curator = addUser("carla_p_" + database_, "curator");
  const std::string reader = addUser("rita_p_" + database_, "reader");
  const fs::path file = dir_ / "station.sqlite";
  // The sample plant digitized where it stands through the simulated devices, then pushed.
  const Result captured =
      leafdig("plant capture --simulate --speed 20 --station bench-p --db " + quote(file) + " </dev/null");
  ASSERT_EQ(captured.exitCode, 0) << captured.err;
  const Result pushed = leafdig("sync push --db " + quote(file) + " --to " + quote(tech));
  ASSERT_EQ(pushed.exitCode, 0) << pushed.out << pushed.err;
  const json list = json::parse(leafdig("sessions list --json --db " + quote(curator)).out);
  ASSERT_EQ(list.size(), 1u);
  EXPECT_EQ(list[0].at("kind"), "plant");
  const std::string id = std::to_string(list[0].at("id").get<int>());
  // Its surveys, read from the server by a reader.
  const Result surveys = leafdig("plant surveys tobacco-p12 --json --db " + quote(reader));
  ASSERT_EQ(surveys.exitCode, 0) << surveys.err;
  const json s = json::parse(surveys.out).at("surveys");
  ASSERT_EQ(s.size(), 1u);
  EXPECT_TRUE(s[0].at("verified").get<bool>());
  EXPECT_EQ(s[0].at("nodes"), 5);
  EXPECT_EQ(s[0].at("date"), "2026-06-12");
  // Exported from the server: the MTG through the strict reader, the GLB beside it.
  const Result exported =
      leafdig("sessions export " + id + " --format mtg,glb --out " + quote(dir_ / "out") + " --db " + quote(curator));
  ASSERT_EQ(exported.exitCode, 0) << exported.err;
  const auto mtg = leafdig::test::readMtgStrictly(slurp(dir_ / "out" / ("session-" + id + ".mtg")));
  EXPECT_FALSE(mtg.entities.empty());
  EXPECT_TRUE(fs::exists(dir_ / "out" / ("session-" + id + ".glb")));
  // A curator corrects node 2's stem diameter on the server; the technician may not; the
  // survey exported from the server carries it.
  const std::string fix = " --what reading --row 2 --value 9.5 --why 'read in inches' --db ";
  EXPECT_NE(leafdig("sessions correct " + id + fix + quote(tech) + " --who tom").exitCode, 0);
  const Result fixed = leafdig("sessions correct " + id + fix + quote(curator) + " --who carla --json");
  ASSERT_EQ(fixed.exitCode, 0) << fixed.err;
  EXPECT_EQ(json::parse(fixed.out).at("corrected"), "reading");
  ASSERT_EQ(
      leafdig("sessions export " + id + " --format json --out " + quote(dir_ / "fixed") + " --db " + quote(curator))
          .exitCode,
      0);
  const json survey = json::parse(slurp(dir_ / "fixed" / ("session-" + id + ".survey.json")));
  EXPECT_DOUBLE_EQ(survey.at("nodes").at(1).at("diameter_mm").get<double>(), 9.5);
  // A reader decides nothing; a curator approves; the station takes the decision in.
  EXPECT_NE(leafdig("sessions approve " + id + " --who rita --db " + quote(reader)).exitCode, 0);
  const Result approved =
      leafdig("sessions approve " + id + " --who carla --why 'a whole plant' --db " + quote(curator));
  ASSERT_EQ(approved.exitCode, 0) << approved.err;
  ASSERT_EQ(leafdig("sync pull --db " + quote(file) + " --from " + quote(tech)).exitCode, 0);
  EXPECT_EQ(json::parse(leafdig("sessions list --json --db " + quote(file)).out)[0].at("status"), "approved");
}

TEST_F(LabCli, SyncPushKilledAtRandomInstantsLosesAndDuplicatesNothingAndTheNextRunContinues) {
  const fs::path file = dir_ / "station.sqlite";
  {
    leafdig::db::Store s(file.string());
    for (int leaf = 1; leaf <= 24; ++leaf) (void)leafdig::test::captureSession(s, "bench-k", leaf, 2 + leaf % 4);
  }
  const leafdig::db::Store local(file.string(), true);
  const auto expected = fileHashes(local);
  const char* runsEnv = std::getenv("LEAFDIG_KILL_RUNS");
  // 50 kills on the plain build; the ASan pass asks for fewer (LEAFDIG_KILL_RUNS).
  const int runs = std::max(4, runsEnv ? std::atoi(runsEnv) : 50);
  std::mt19937 rng(20261124);
  // Kill instants come from what this run sees, not from the machine's speed (issue 26): every
  // other run waits for the push to report k of its sessions sent (k random) and kills it
  // then, in the middle by construction; the others kill at a random instant within the
  // duration of a whole push measured here first.
  const auto freshServer = [&](const std::string& name) {
    Sql(clusterOf().adminUrl()).rows("CREATE DATABASE " + name + " ENCODING 'UTF8' TEMPLATE template0");
    admin_ = clusterOf().adminUrl(name);
    database_ = name;
    EXPECT_EQ(leafdig("server init --url " + quote(admin_)).exitCode, 0);
    return addUser("tech_" + name, "technician", "bench-k");
  };
  double wholePushMs = 0;
  {
    const std::string url = freshServer("killmeasure_" + std::to_string(::getpid()));
    const auto t0 = std::chrono::steady_clock::now();
    ASSERT_EQ(leafdig("sync push --db " + quote(file) + " --to " + quote(url) + " --batch 7").exitCode, 0);
    wholePushMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  }
  std::uniform_int_distribution<int> sessionsSent(1, static_cast<int>(expected.size()) - 2);
  std::uniform_real_distribution<double> fraction(0.02, 0.98);
  int killedMidPush = 0, killedAfterProgress = 0;
  for (int run = 0; run < runs; ++run) {
    // Each run on an empty server: the push is killed at a chosen instant, then run again.
    const std::string fresh = "kill" + std::to_string(run) + "_" + std::to_string(::getpid());
    const std::string url = freshServer(fresh);
    const fs::path out = dir_ / "push.out", err = dir_ / "push.err";
    const pid_t pid = spawn({"sync", "push", "--db", file.string(), "--to", url, "--batch", "7"}, out, err);
    if (run % 2 == 0) {
      const auto lines = static_cast<std::size_t>(sessionsSent(rng));
      const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(120);
      for (;;) {
        const std::string text = slurp(out);
        std::size_t sent = 0;
        for (auto at = text.find(" sent\n"); at != std::string::npos; at = text.find(" sent\n", at + 1)) ++sent;
        if (sent >= lines || std::chrono::steady_clock::now() > give_up) break;
        std::this_thread::sleep_for(std::chrono::microseconds(200));
      }
    } else {
      std::this_thread::sleep_for(std::chrono::duration<double, std::milli>(fraction(rng) * wholePushMs));
    }
    ::kill(pid, SIGKILL);
    const int status = reap(pid);
    // The server finishes with the dead client on its own time: a COMMIT already in its socket
    // still commits. Count only once no session of the killed push is left on the server (seen:
    // a batch of 7 committed just after the count, so the next push sent 7 fewer than counted).
    {
      Sql watch(admin_);
      const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(60);
      while (watch.value("SELECT count(*) FROM pg_stat_activity WHERE datname = $1 AND pid <> pg_backend_pid()",
                         {fresh}) != "0" &&
             std::chrono::steady_clock::now() < give_up)
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    // Whatever reached the server is, for every session, exactly the start of the station's
    // copy: nothing lost in the middle, nothing twice, every chain whole.
    const auto onServer = serverHashes(admin_);
    std::size_t events = 0, all = 0;
    for (const auto& [id, hashes] : onServer) {
      const auto& mine = expected.at(id);
      ASSERT_LE(hashes.size(), mine.size()) << "run " << run;
      EXPECT_EQ(hashes, std::vector<std::string>(mine.begin(), mine.begin() + static_cast<long>(hashes.size())))
          << "run " << run << " session " << id;
      events += hashes.size();
    }
    for (const auto& [id, hashes] : expected) all += hashes.size();
    if (WIFSIGNALED(status) && events > 0 && events < all) {
      ++killedMidPush;
      if (run % 2 == 0) ++killedAfterProgress;
    }
    if (HasFailure()) FAIL() << "run " << run << ": " << slurp(err);
    // The next push continues where the server stands: it then holds exactly the file.
    const Result rest = leafdig("sync push --db " + quote(file) + " --to " + quote(url) + " --json");
    ASSERT_EQ(rest.exitCode, 0) << rest.err;
    EXPECT_EQ(json::parse(rest.out).at("events_sent").get<std::size_t>(), all - events) << "run " << run;
    EXPECT_EQ(serverHashes(admin_), expected) << "run " << run;
    leafdig::db::LabStore server(admin_);
    for (const auto& s : server.sessions()) EXPECT_TRUE(server.verify(s.id).ok) << "run " << run;
    if (HasFailure()) FAIL() << "run " << run << " (continued): " << rest.err;
  }
  // A run that waited for k < n - 1 sessions to be reported sent kills a push with sessions
  // still to send — unless, on a loaded machine (ASan beside a build), the push finishes
  // between the line and the signal (seen once: 24 of 25). The invariants above hold either
  // way; here only that the mid-push case was exercised, not how often the machine allowed it.
  EXPECT_GT(killedAfterProgress, 0) << "no kill after a progress line landed inside a push";
  std::printf("sync push kill -9: %d runs, %d killed mid-push, server always a prefix of the station\n", runs,
              killedMidPush);
}

}  // namespace
