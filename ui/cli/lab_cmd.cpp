#include "lab_cmd.hpp"

#include <chrono>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "leafdig/acquisition/review/review.hpp"
#include "leafdig/db/lab.hpp"
#include "terminal_text.hpp"
#include "web/web_cmd.hpp"

namespace leafdig::cli {
namespace {

using nlohmann::json;

std::string stationFile(const LabOptions& o) {
  return o.db.empty() ? db::Store::defaultPath() : o.db;
}

std::string readPassword(const std::string& file) {
  std::ifstream in(file);
  if (!in)
    throw db::StoreError(db::StoreErrorKind::Input, "cannot read the password file " + file,
                         "give a file holding the password on its first line");
  std::string line;
  std::getline(in, line);
  while (!line.empty() && (line.back() == '\r' || line.back() == '\n')) line.pop_back();
  if (line.empty())
    throw db::StoreError(db::StoreErrorKind::Input, "the password file " + file + " holds no password",
                         "put the password on its first line");
  return line;
}

json problemsJson(const std::vector<db::SyncProblem>& problems) {
  json a = json::array();
  for (const auto& p : problems)
    a.push_back(
        {{"station", p.station}, {"session", p.stationSessionId}, {"problem", p.problem}, {"remedy", p.remedy}});
  return a;
}

// A problem's words without the session they name ("session bench-a:12", "bench-a:12"): the
// same reason for every session of a station reads the same.
std::string reasonOf(const db::SyncProblem& p) {
  std::string text = p.problem;
  const std::string self = p.station + ":" + std::to_string(p.stationSessionId);
  for (std::size_t at = text.find(self); at != std::string::npos; at = text.find(self, at + 1))
    text.replace(at, self.size(), "#");
  return text + "\n" + p.remedy;
}

// Each problem in its words; sessions of one station refused for the same reason (a login
// bound to another station, a server that does not take their kind yet) after the first as
// one line naming how many and which, not a screen of the same words.
void printProblems(const std::vector<db::SyncProblem>& problems) {
  std::vector<bool> told(problems.size(), false);
  std::vector<std::string> reasons;  // each problem's reason, worked out once
  reasons.reserve(problems.size());
  for (const auto& p : problems) reasons.push_back(reasonOf(p));
  for (std::size_t i = 0; i < problems.size(); ++i) {
    if (told[i]) continue;
    const auto& p = problems[i];
    std::cerr << "leafdig: session " << terminalText(p.station) << ":" << p.stationSessionId
              << " not synced: " << terminalMessage(p.problem) << "\n";
    if (!p.remedy.empty()) std::cerr << "  what to do: " << terminalMessage(p.remedy) << "\n";
    std::vector<std::int64_t> same;
    for (std::size_t j = i + 1; j < problems.size(); ++j)
      if (!told[j] && problems[j].station == p.station && reasons[j] == reasons[i]) {
        told[j] = true;
        same.push_back(problems[j].stationSessionId);
      }
    if (same.empty()) continue;
    constexpr std::size_t kNamed = 10;
    std::cerr << "leafdig: " << same.size() << " more session(s) of station " << terminalText(p.station)
              << " not synced for the same reason:";
    for (std::size_t k = 0; k < same.size() && k < kNamed; ++k) std::cerr << (k ? ", " : " ") << same[k];
    if (same.size() > kNamed) std::cerr << " and " << same.size() - kNamed << " more (--json lists each)";
    std::cerr << "\n";
  }
}

int runPush(const LabOptions& o) {
  const std::string path = stationFile(o);
  if (!std::filesystem::exists(path))
    throw db::StoreError(db::StoreErrorKind::Input, "no station database at " + path, "give --db FILE");
  db::Store local(path, true);
  db::SyncOptions options;
  if (!o.station.empty()) options.station = o.station;
  options.eventsPerTransaction = o.eventsPerTransaction;
  if (!o.json)
    options.progress = [](const std::string& line) { std::cout << "  " << terminalText(line) << "\n" << std::flush; };
  const auto t0 = std::chrono::steady_clock::now();
  const db::PushReport r = db::push(local, o.url, options);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (o.json) {
    std::cout << json{{"to", db::redactUrl(o.url)},          {"sessions", r.sessionsSeen},
                      {"new_sessions", r.sessionsNew},       {"up_to_date", r.sessionsUpToDate},
                      {"behind", r.sessionsBehind},          {"events_sent", r.eventsSent},
                      {"transactions", r.transactions},      {"seconds", seconds},
                      {"problems", problemsJson(r.problems)}}
                     .dump()
              << "\n";
  } else {
    std::cout << "pushed " << r.eventsSent << " event(s) of " << r.sessionsSeen << " session(s) to "
              << db::redactUrl(o.url) << " (" << r.sessionsNew << " new, " << r.sessionsUpToDate << " already there"
              << (r.sessionsBehind ? ", " + std::to_string(r.sessionsBehind) + " with curator decisions to pull" : "")
              << ")\n";
  }
  printProblems(r.problems);
  return r.problems.empty() ? 0 : 1;
}

int runPull(const LabOptions& o) {
  const std::string path = stationFile(o);
  if (!std::filesystem::exists(path))
    throw db::StoreError(db::StoreErrorKind::Input, "no station database at " + path, "give --db FILE");
  db::Store local(path);
  db::SyncOptions options;
  if (!o.station.empty()) options.station = o.station;
  if (!o.json)
    options.progress = [](const std::string& line) { std::cout << "  " << terminalText(line) << "\n" << std::flush; };
  options.replays = acquisition::requireReplays;
  const db::PullReport r = db::pull(local, o.url, options);
  if (o.json)
    std::cout << json{{"from", db::redactUrl(o.url)},
                      {"sessions", r.sessionsSeen},
                      {"updated", r.sessionsUpdated},
                      {"events_taken", r.eventsTaken},
                      {"problems", problemsJson(r.problems)}}
                     .dump()
              << "\n";
  else
    std::cout << "took in " << r.eventsTaken << " event(s) for " << r.sessionsUpdated << " session(s) from "
              << db::redactUrl(o.url) << "\n";
  printProblems(r.problems);
  return r.problems.empty() ? 0 : 1;
}

int runInit(const LabOptions& o) {
  const db::ServerInit r = db::initServer(o.url, o.lockWaitSeconds);
  if (o.json) {
    std::cout << json{{"url", db::redactUrl(o.url)},
                      {"from_version", r.fromVersion},
                      {"to_version", r.toVersion},
                      {"roles_created", r.rolesCreated},
                      {"notes", r.notes}}
                     .dump()
              << "\n";
  } else {
    std::cout << "lab server " << db::redactUrl(o.url) << ": schema "
              << (r.fromVersion == r.toVersion
                      ? "already at version " + std::to_string(r.toVersion)
                      : "version " + std::to_string(r.fromVersion) + " -> " + std::to_string(r.toVersion))
              << "\n";
    for (const auto& role : r.rolesCreated) std::cout << "  created group role " << role << "\n";
    for (const auto& note : r.notes) std::cout << "  note: " << terminalText(note) << "\n";
    std::cout << "next: leafdig server add-user --url URL --login NAME --role technician|curator|reader\n";
  }
  return 0;
}

int runWeb(const LabOptions& o) {
  web::WebOptions options;
  options.serverUrl = o.url;
  options.idle = std::chrono::seconds(static_cast<std::int64_t>(o.idleMinutes * 60));
  options.secureCookie = o.secureCookie;
  return web::serve(options, o.listen);
}

int runAddUser(const LabOptions& o) {
  const db::LabRole role = db::labRoleFromString(o.role);
  std::optional<std::string> password;
  if (!o.passwordFile.empty()) password = readPassword(o.passwordFile);
  const db::AddedUser u = db::addUser(o.url, o.login, role, o.station, password);
  if (o.json)
    std::cout << json{{"login", u.login},
                      {"role", db::toString(u.role)},
                      {"created", u.created},
                      {"station", u.station}}
                     .dump()
              << "\n";
  else
    std::cout << (u.created ? "created login " : "login ") << u.login << ": " << db::toString(u.role)
              << (u.station.empty() ? "" : " of station " + u.station) << "\n";
  return 0;
}

void declareLabCommands(CLI::App& app, LabOptions& o) {
  CLI::App* server = app.add_subcommand("server", "The lab's PostgreSQL server: create its schema, add logins");
  server->require_subcommand(1);
  CLI::App* init = server->add_subcommand("init", "Create or migrate the schema and the three group roles (admin)");
  CLI::App* add =
      server->add_subcommand("add-user", "Put a login in its group: technician (of one station), curator, reader");
  for (CLI::App* c : {init, add}) {
    c->add_option("--url", o.url, "postgresql://ADMIN@HOST/DB (the password from ~/.pgpass or PGPASSWORD)")->required();
    c->add_flag("--json", o.json, "JSON output");
  }
  init->add_option("--lock-wait", o.lockWaitSeconds,
                   "Seconds to wait for another init's lock before naming who holds it (default 30)")
      ->check(CLI::Range(0.0, 3600.0));
  add->add_option("--login", o.login, "The login role (created when --password-file is given)")->required();
  add->add_option("--role", o.role, "technician, curator or reader")
      ->required()
      ->check(CLI::IsMember(wordsIn(db::kLabRoleNames)));
  add->add_option("--station", o.station, "A technician's station id (required for technicians only)");
  add->add_option("--password-file", o.passwordFile, "File whose first line is the new login's password");
  CLI::App* web = server->add_subcommand(
      "web", "Serve the lab server's sessions to curators and readers in a browser (docs/web.md)");
  web->add_option("--db", o.url, "postgresql://HOST[:PORT]/DATABASE: each browser logs in with its own login")
      ->required();
  web->add_option("--listen", o.listen, "HOST:PORT to serve on (default 127.0.0.1:8080; TLS is a proxy's)");
  web->add_option("--idle-minutes", o.idleMinutes, "A browser session unused this long ends (default 30)")
      ->check(CLI::Range(1.0, 24.0 * 60));
  web->add_flag("--secure-cookie", o.secureCookie, "Send the session cookie over https only (behind a TLS proxy)");

  CLI::App* sync = app.add_subcommand("sync", "Send this station's sessions to the lab server, bring decisions back");
  sync->require_subcommand(1);
  CLI::App* push = sync->add_subcommand("push", "Send every event the server lacks (idempotent, resumable)");
  CLI::App* pull = sync->add_subcommand("pull", "Take in the curators' decisions on this station's sessions");
  push->add_option("--to", o.url, "The lab server's postgresql:// URL")->required();
  pull->add_option("--from", o.url, "The lab server's postgresql:// URL")->required();
  push->add_option("--batch", o.eventsPerTransaction, "Events per transaction (default 2000)")
      ->check(CLI::Range(1, 100000));
  for (CLI::App* c : {push, pull}) {
    c->add_option("--db", o.db, "The station's SQLite file (default: the station's)");
    c->add_option("--station", o.station, "Only this station's sessions (default: every session in the file)");
    c->add_flag("--json", o.json, "JSON output");
  }
}

// The lab server's URL, checked before anything is opened.
void checkServerUrl(const LabOptions& o) {
  if (!db::isServerUrl(o.url))
    throw db::StoreError(db::StoreErrorKind::Input, "'" + db::redactUrl(o.url) + "' is not a postgresql:// URL",
                         "give the lab server as postgresql://USER@HOST[:PORT]/DATABASE (docs/lab.md)");
}

}  // namespace

void addLabCommands(CLI::App& app, CommandTable& table) {
  auto o = std::make_shared<LabOptions>();
  declareLabCommands(app, *o);
  const auto add = [&](CLI::App* command, int (*run)(const LabOptions&)) {
    table.add(command, [o, run] {
      checkServerUrl(*o);
      return run(*o);
    });
  };
  add(app.get_subcommand("server")->get_subcommand("init"), runInit);
  add(app.get_subcommand("server")->get_subcommand("add-user"), runAddUser);
  add(app.get_subcommand("server")->get_subcommand("web"), runWeb);
  add(app.get_subcommand("sync")->get_subcommand("push"), runPush);
  add(app.get_subcommand("sync")->get_subcommand("pull"), runPull);
}

}  // namespace leafdig::cli
