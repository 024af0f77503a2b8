// The lab server (issue 17 targets): pushing a station of 1 000 leaves (events per second),
// an incremental push with nothing new (≤ 200 ms), listing 10 000 sessions from the server;
// and the web review (issue 49): 50 readers at once listing those 10 000 sessions through
// `leafdig server web` (p50/p99/max of each request, as a browser sees it).
// A real PostgreSQL cluster started by the benchmark (tests/support/pg_cluster.hpp).
// LEAFDIG_BENCH_LEAVES scales both files down for the smoke run. Results: docs/benchmarks.md.
#include <benchmark/benchmark.h>
#include <httplib.h>
#include <signal.h>
#include <spawn.h>
#include <sqlite3.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <nlohmann/json.hpp>
#include <sstream>
#include <thread>

#include "../support/pg_cluster.hpp"
#include "../support/station_sessions.hpp"
#include "latency_counters.hpp"
#include "leafdig/db/lab.hpp"

namespace {

namespace fs = std::filesystem;
namespace db = leafdig::db;

leafdig::test::PgCluster& cluster() {
  static leafdig::test::PgCluster c;
  return c;
}

int scaled(int leaves) {
  const char* e = std::getenv("LEAFDIG_BENCH_LEAVES");
  return e ? std::max(2, std::min(leaves, std::atoi(e))) : leaves;
}

// A station file of `leaves` complete sessions. The first is written as a capture writes it
// (test::captureSession, `rows` rows); the others are copies of its events re-chained for
// their own id (valid hashes: the server checks every one), written in one transaction.
fs::path stationFile(int leaves, int rows) {
  const fs::path path = fs::temp_directory_path() /
                        ("leafdig-labbench-" + std::to_string(leaves) + "x" + std::to_string(rows) + ".sqlite");
  if (fs::exists(path)) return path;
  std::vector<db::Event> events;
  {
    db::Store s(path.string());
    const auto first = leafdig::test::captureSession(s, "bench-lab", 1, rows);
    events = s.events(first);
    const auto op = s.ensureOperator("ana");
    const auto plant = s.ensurePlant(s.ensureProject("tobacco-2026"), "P-07");
    for (int leaf = 2; leaf <= leaves; ++leaf)
      (void)s.createSession(s.ensureLeaf(plant, leaf, "middle"), op, "bench-lab", "standard", "sequential",
                            R"({"engine":{"still_mm":0.5}})");
  }
  sqlite3* raw = nullptr;
  sqlite3_open(path.c_str(), &raw);
  sqlite3_exec(raw, "PRAGMA synchronous=OFF; BEGIN", nullptr, nullptr, nullptr);
  sqlite3_stmt* ins = nullptr;
  sqlite3_prepare_v2(raw,
                     "INSERT INTO events(session_id, seq, utc, mono_ns, kind, payload_json, raw, prev_hash, hash) "
                     "VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9)",
                     -1, &ins, nullptr);
  sqlite3_stmt* head = nullptr;
  sqlite3_prepare_v2(raw, "UPDATE sessions SET head_seq=?1, head_hash=?2, status='complete' WHERE id=?3", -1, &head,
                     nullptr);
  sqlite3_stmt* genesis = nullptr;
  sqlite3_prepare_v2(raw, "SELECT genesis_hash FROM sessions WHERE id=?1", -1, &genesis, nullptr);
  for (std::int64_t id = 2; id <= leaves; ++id) {
    sqlite3_bind_int64(genesis, 1, id);
    sqlite3_step(genesis);
    std::string prev = reinterpret_cast<const char*>(sqlite3_column_text(genesis, 0));
    sqlite3_reset(genesis);
    for (const db::Event& e : events) {
      const std::string hash = db::eventHash(prev, id, e.seq, e.utc, e.monoNs, e.kind, e.payloadJson, e.raw);
      sqlite3_bind_int64(ins, 1, id);
      sqlite3_bind_int64(ins, 2, e.seq);
      sqlite3_bind_text(ins, 3, e.utc.c_str(), -1, SQLITE_TRANSIENT);
      sqlite3_bind_int64(ins, 4, e.monoNs);
      sqlite3_bind_text(ins, 5, e.kind.c_str(), -1, SQLITE_TRANSIENT);
      sqlite3_bind_text(ins, 6, e.payloadJson.c_str(), -1, SQLITE_TRANSIENT);
      sqlite3_bind_text(ins, 7, e.raw.c_str(), -1, SQLITE_TRANSIENT);
      sqlite3_bind_text(ins, 8, prev.c_str(), -1, SQLITE_TRANSIENT);
      sqlite3_bind_text(ins, 9, hash.c_str(), -1, SQLITE_TRANSIENT);
      sqlite3_step(ins);
      sqlite3_reset(ins);
      prev = hash;
    }
    sqlite3_bind_int64(head, 1, events.back().seq);
    sqlite3_bind_text(head, 2, prev.c_str(), -1, SQLITE_TRANSIENT);
    sqlite3_bind_int64(head, 3, id);
    sqlite3_step(head);
    sqlite3_reset(head);
  }
  for (sqlite3_stmt* st : {ins, head, genesis}) sqlite3_finalize(st);
  sqlite3_exec(raw, "COMMIT", nullptr, nullptr, nullptr);
  sqlite3_close(raw);
  return path;
}

// A fresh lab database with the schema and a technician of station bench-lab.
std::string freshServer() {
  static int n = 0;
  const std::string name = cluster().createDatabase();
  (void)db::initServer(cluster().adminUrl(name));
  const std::string login = "tech_bench_" + std::to_string(::getpid()) + "_" + std::to_string(++n);
  (void)db::addUser(cluster().adminUrl(name), login, db::LabRole::Technician, "bench-lab", std::string("pw"));
  return cluster().url(login, "pw", name);
}

std::int64_t eventsIn(const db::Store& s) {
  std::int64_t n = 0;
  for (const auto& info : s.sessions()) n += info.headSeq;
  return n;
}

// A station of 1 000 leaves (14 rows each: ~130 events) pushed to an empty server.
void BM_PushStation(benchmark::State& state) {
  const fs::path file = stationFile(scaled(static_cast<int>(state.range(0))), 14);
  const db::Store local(file.string(), true);
  const std::int64_t events = eventsIn(local);
  db::Store writable(file.string(), true);
  double seconds = 0;
  for (auto _ : state) {
    state.PauseTiming();
    const std::string url = freshServer();
    state.ResumeTiming();
    const auto t0 = std::chrono::steady_clock::now();
    const db::PushReport r = db::push(writable, url);
    seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (r.eventsSent != events || !r.problems.empty()) state.SkipWithError("the push did not send every event");
  }
  state.counters["leaves"] = static_cast<double>(local.sessions().size());
  state.counters["events"] = static_cast<double>(events);
  state.counters["events_per_s"] = static_cast<double>(events) * static_cast<double>(state.iterations()) / seconds;
}
BENCHMARK(BM_PushStation)->Arg(1000)->Iterations(2)->Unit(benchmark::kMillisecond)->UseRealTime();

// The machine's limit for the same rows (issue 26): COPY of every event of the same station
// into a table of the same columns with no trigger, no policy and no key, as the admin. The
// ratio to BM_PushStation is what the server's per-row checks (who may add what, the closed
// sets, the chain's SHA-256 and the session's head) cost.
void BM_CopyBaseline(benchmark::State& state) {
  const fs::path file = stationFile(scaled(static_cast<int>(state.range(0))), 14);
  const db::Store local(file.string(), true);
  std::string rows;  // COPY's text format: tab-separated, \N for NULL, backslashes escaped
  const auto field = [&rows](const std::string& v) {
    for (const char c : v) {
      if (c == '\\' || c == '\t' || c == '\n' || c == '\r') {
        rows += '\\';
        rows += c == '\t' ? 't' : c == '\n' ? 'n' : c == '\r' ? 'r' : '\\';
      } else {
        rows += c;
      }
    }
  };
  std::int64_t events = 0;
  for (const auto& info : local.sessions())
    for (const db::Event& e : local.events(info.id)) {
      rows += std::to_string(info.id) + "\tbench-lab\t" + std::to_string(e.seq) + "\t";
      field(e.utc);
      rows += "\t" + std::to_string(e.monoNs) + "\t";
      for (const std::string* v : {&e.kind, &e.payloadJson, &e.raw, &e.prevHash}) {
        field(*v);
        rows += '\t';
      }
      field(e.hash);
      rows += '\n';
      ++events;
    }
  double seconds = 0;
  for (auto _ : state) {
    state.PauseTiming();
    const std::string name = cluster().createDatabase();
    PGconn* c = PQconnectdb(cluster().adminUrl(name).c_str());
    PQclear(PQexec(c,
                   "CREATE TABLE plain (session_id bigint, station text, seq bigint, utc text, mono_ns bigint, "
                   "kind text, payload_json text, raw text, prev_hash text, hash text)"));
    state.ResumeTiming();
    const auto t0 = std::chrono::steady_clock::now();
    PQclear(PQexec(c, "BEGIN"));
    PQclear(PQexec(c, "COPY plain FROM STDIN"));
    const bool sent =
        PQputCopyData(c, rows.data(), static_cast<int>(rows.size())) == 1 && PQputCopyEnd(c, nullptr) == 1;
    PGresult* r = PQgetResult(c);
    const bool ok = sent && PQresultStatus(r) == PGRES_COMMAND_OK;
    PQclear(r);
    while ((r = PQgetResult(c)) != nullptr) PQclear(r);
    PQclear(PQexec(c, "COMMIT"));
    seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    PGresult* count = PQexec(c, "SELECT count(*) FROM plain");
    if (!ok || std::atoll(PQgetvalue(count, 0, 0)) != events) state.SkipWithError("COPY did not take every row");
    PQclear(count);
    PQfinish(c);
  }
  state.counters["events"] = static_cast<double>(events);
  state.counters["events_per_s"] = static_cast<double>(events) * static_cast<double>(state.iterations()) / seconds;
}
BENCHMARK(BM_CopyBaseline)->Arg(1000)->Iterations(2)->Unit(benchmark::kMillisecond)->UseRealTime();

// The same station pushed again: nothing new (what a station does every few minutes).
void BM_PushNothingNew(benchmark::State& state) {
  const fs::path file = stationFile(scaled(1000), 14);
  db::Store local(file.string(), true);
  const std::string url = freshServer();
  (void)db::push(local, url);
  for (auto _ : state) {
    const db::PushReport r = db::push(local, url);
    if (r.eventsSent != 0) state.SkipWithError("a second push sent events");
    benchmark::DoNotOptimize(r.sessionsUpToDate);
  }
  state.counters["leaves"] = static_cast<double>(local.sessions().size());
}
BENCHMARK(BM_PushNothingNew)->Unit(benchmark::kMillisecond)->UseRealTime();

// Listing 10 000 sessions from the server, as `sessions list --db postgresql://…` and the
// review view do (short sessions: the listing reads the sessions table, not the events).
void BM_ListSessionsFromServer(benchmark::State& state) {
  const int leaves = scaled(static_cast<int>(state.range(0)));
  const fs::path file = stationFile(leaves, 1);
  db::Store local(file.string(), true);
  const std::string url = freshServer();
  (void)db::push(local, url);
  db::LabStore server(url);
  std::size_t n = 0;
  for (auto _ : state) {
    n = server.sessions().size();
    benchmark::DoNotOptimize(n);
  }
  if (n != static_cast<std::size_t>(leaves)) state.SkipWithError("not every session listed");
  state.counters["sessions"] = static_cast<double>(n);
}
BENCHMARK(BM_ListSessionsFromServer)->Arg(10000)->Unit(benchmark::kMillisecond)->UseRealTime();

// 50 readers of the web review, each logged in in a browser session of its own (13 reader
// logins: a login keeps at most 4), listing the 10 000 sessions at once, 10 times each. The web
// server is `leafdig server web` as a lab runs it, on loopback, with the lab server on the same
// two cores. Reports each request's latency (p50, p99, max) and the requests per second.
void BM_WebReadersListSessions(benchmark::State& state) {
  const int leaves = scaled(static_cast<int>(state.range(0)));
  const int readers = 50, logins = 13, rounds = 10;
  const fs::path file = stationFile(leaves, 1);
  db::Store local(file.string(), true);
  const std::string url = freshServer();
  (void)db::push(local, url);
  const std::string database = url.substr(url.rfind('/') + 1);
  for (int i = 0; i < logins; ++i)
    (void)db::addUser(cluster().adminUrl(database), "reader_" + database + "_" + std::to_string(i), db::LabRole::Reader,
                      "", std::string("pw"));
  const fs::path out = fs::temp_directory_path() / ("leafdig-webbench-" + std::to_string(::getpid()) + ".out");
  const std::string server = "postgresql://127.0.0.1:" + std::to_string(cluster().port()) + "/" + database;
  std::vector<std::string> args{LEAFDIG_CLI, "server", "web", "--db", server, "--listen", "127.0.0.1:0"};
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  posix_spawn_file_actions_addopen(&fa, 1, out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  pid_t pid = 0;
  if (posix_spawn(&pid, LEAFDIG_CLI, &fa, nullptr, argv.data(), environ) != 0) {
    state.SkipWithError("cannot start leafdig server web");
    return;
  }
  posix_spawn_file_actions_destroy(&fa);
  int port = 0;
  for (int wait = 0; wait < 600 && port == 0; ++wait) {
    std::ifstream in(out);
    std::stringstream text;
    text << in.rdbuf();
    if (const auto at = text.str().find("http://127.0.0.1:");
        at != std::string::npos && text.str().find('\n') != std::string::npos)
      port = std::stoi(text.str().substr(at + 17));
    else
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  std::vector<std::string> cookies(readers);
  for (int r = 0; r < readers && port != 0; ++r) {
    httplib::Client c("127.0.0.1", port);
    const nlohmann::json body{{"login", "reader_" + database + "_" + std::to_string(r % logins)}, {"password", "pw"}};
    const auto answer = c.Post("/api/login", body.dump(), "application/json");
    if (answer && answer->status == 200) {
      const std::string set = answer->get_header_value("Set-Cookie");
      cookies[r] = set.substr(0, set.find(';'));
    }
  }
  std::vector<double> ms;
  std::mutex msMutex;
  std::size_t listed = 0, failed = 0;
  double seconds = 0;
  for (auto _ : state) {
    const auto t0 = std::chrono::steady_clock::now();
    std::vector<std::thread> threads;
    for (int r = 0; r < readers; ++r)
      threads.emplace_back([&, r] {
        httplib::Client c("127.0.0.1", port);
        c.set_read_timeout(120, 0);
        for (int k = 0; k < rounds; ++k) {
          const auto start = std::chrono::steady_clock::now();
          // As a browser asks: any encoding it knows (the web server answers gzip).
          const auto answer =
              c.Get("/api/sessions", {{"Cookie", cookies[r]}, {"Accept-Encoding", "gzip, deflate, br"}});
          const double took =
              std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
          const std::lock_guard lock(msMutex);
          if (!answer || answer->status != 200) {
            ++failed;
            continue;
          }
          ms.push_back(took);
          listed = nlohmann::json::parse(answer->body).size();
        }
      });
    for (auto& t : threads) t.join();
    seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }
  ::kill(pid, SIGTERM);
  ::waitpid(pid, nullptr, 0);
  fs::remove(out);
  if (port == 0 || failed > 0 || listed != static_cast<std::size_t>(leaves)) {
    state.SkipWithError("the web review did not list every session to every reader");
    return;
  }
  (void)leafdig::bench::reportLatency(state, ms);
  state.counters["readers"] = readers;
  state.counters["sessions"] = static_cast<double>(listed);
  state.counters["requests_per_s"] = static_cast<double>(ms.size()) / seconds;
}
BENCHMARK(BM_WebReadersListSessions)->Arg(10000)->Iterations(1)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
