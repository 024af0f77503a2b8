// Push and pull between a station's file and the lab server (docs/lab.md, "Sync").
#include <algorithm>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>

#include "leafdig/db/event_rules.hpp"
#include "leafdig/db/lab.hpp"
#include "pg.hpp"

namespace leafdig::db {
namespace {

std::string label(const SessionInfo& s) {
  return s.station + ":" + std::to_string(s.id);
}

struct ServerHead {
  std::int64_t id = 0, headSeq = 0;
  std::string headHash, genesis;
};

// The server's view of a station's sessions, by their id at the station.
std::map<std::int64_t, ServerHead> serverHeads(pg::Connection& c, const std::string& station) {
  const auto r = c.exec(
      "SELECT station_session_id, id, head_seq, head_hash, genesis_hash FROM leafdig.sessions WHERE station = $1",
      {station});
  std::map<std::int64_t, ServerHead> out;
  for (int i = 0; i < r.rows(); ++i) out[r.int64(i, 0)] = {r.int64(i, 1), r.int64(i, 2), r.text(i, 3), r.text(i, 4)};
  return out;
}

// A session's text that the server cannot hold as it is (not UTF-8, or a NUL byte).
std::optional<std::string> untransportable(const SessionInfo& s, const std::vector<Event>& events) {
  const std::pair<const char*, const std::string*> fields[] = {
      {"project", &s.project},    {"plant", &s.plant},           {"operator", &s.operatorName},
      {"leaf type", &s.leafType}, {"settings", &s.settingsJson}, {"creation time", &s.createdUtc}};
  for (const auto& [name, text] : fields)
    if (const auto bad = badTextByte(*text))
      return std::string("its ") + name + " is not UTF-8 text (byte " + std::to_string(*bad) + ")";
  for (const Event& e : events)
    for (const std::string* text : {&e.payloadJson, &e.raw, &e.kind, &e.utc})
      if (const auto bad = badTextByte(*text))
        return "event " + std::to_string(e.seq) + " holds text that is not UTF-8 (byte " + std::to_string(*bad) + ")";
  return std::nullopt;
}

// The server's schema version (plant sessions from 3 on).
int serverSchema(pg::Connection& c) {
  const auto v = c.exec("SELECT value FROM leafdig.meta WHERE key = 'schema_version'");
  return v.rows() ? std::stoi(v.text(0, 0)) : 0;
}

void insertSession(pg::Connection& c, const SessionInfo& s) {
  // A server before plant sessions has no `kind` (and takes only leaf sessions: push checks);
  // one before schema 10 no `genesis_form` (and takes only form 1: push checks).
  const bool plant = s.kind == "plant";
  const bool form2 = s.genesisForm >= 2;
  (void)c.exec(
      std::string("INSERT INTO leafdig.sessions(station, station_session_id, project, plant, leaf_position, leaf_type, "
                  "measured_area_mm2, operator, mode, capture_order, settings_json, created_utc, genesis_hash") +
          (plant ? ", kind" : "") + (form2 ? ", genesis_form" : "") +
          ") VALUES ($1, $2, $3, $4, $5, $6, $7, $8, $9, $10, $11, $12, $13" + (plant ? ", 'plant'" : "") +
          (form2 ? ", 2" : "") + ")",
      {s.station, std::to_string(s.id), s.project, s.plant, std::to_string(s.leafPosition), s.leafType,
       s.measuredAreaMm2 ? std::optional<std::string>(std::to_string(*s.measuredAreaMm2)) : std::nullopt,
       s.operatorName, s.mode, s.order, s.settingsJson, s.createdUtc, genesisOf(s)});
}

// A text array literal of `values` ({"a","b\\"c"}): each element quoted, its quotes and
// backslashes escaped (PostgreSQL's array input).
std::string arrayLiteral(const std::vector<std::string>& values) {
  std::string out = "{";
  for (std::size_t i = 0; i < values.size(); ++i) {
    out += i ? ",\"" : "\"";
    for (const char ch : values[i]) {
      if (ch == '"' || ch == '\\') out += '\\';
      out += ch;
    }
    out += '"';
  }
  return out + "}";
}

// Events [first, last) in one statement: each column one array parameter, so the statement
// is the same short text whatever its rows (parsed in microseconds, where a VALUES list of
// 5 000 parameters took milliseconds), its rows in the station's order. The server checks
// them in order of seq (schema 9: once per statement; before: row by row).
void insertEvents(pg::Connection& c, std::int64_t serverId, const std::string& station,
                  const std::vector<Event>& events, std::size_t first, std::size_t last) {
  std::vector<std::string> columns[8];
  for (auto& column : columns) column.reserve(last - first);
  for (std::size_t i = first; i < last; ++i) {
    const Event& e = events[i];
    std::size_t k = 0;
    for (auto& v :
         {std::to_string(e.seq), e.utc, std::to_string(e.monoNs), e.kind, e.payloadJson, e.raw, e.prevHash, e.hash})
      columns[k++].push_back(v);
  }
  std::vector<pg::Param> params{std::to_string(serverId), station};
  for (const auto& column : columns) params.emplace_back(arrayLiteral(column));
  (void)c.exec(
      "INSERT INTO leafdig.events(session_id, station, seq, utc, mono_ns, kind, payload_json, raw, prev_hash, hash) "
      "SELECT $1::bigint, $2::text, u.seq, u.utc, u.mono_ns, u.kind, u.payload_json, u.raw, u.prev_hash, u.hash "
      "FROM unnest($3::bigint[], $4::text[], $5::bigint[], $6::text[], $7::text[], $8::text[], $9::text[], "
      "$10::text[]) WITH ORDINALITY AS u(seq, utc, mono_ns, kind, payload_json, raw, prev_hash, hash, n) "
      "ORDER BY u.n",
      params);
}

// What a session holds that a server of `schema` does not take yet, in words ("is a plant
// session with branches and the lab server (schema 4) does not take a plant's branches yet"):
// plant sessions at all before schema 3, a plant's retakes before 4, its branches before 5, its
// moved transmitter before 6, a leaf's moved transmitter before 7; nothing when the server
// takes it all.
std::optional<std::string> beyondServer(const SessionInfo& s, int schema, bool genesisForms, Store& local) {
  const std::string server = " and the lab server (schema " + std::to_string(schema) + ") does not take ";
  // A genesis that covers the station (station schema 3) needs a server that knows it (10).
  if (s.genesisForm >= 2 && !genesisForms)
    return "is a session whose chain covers its station" + server + "such sessions yet";
  if (schema >= 7) return std::nullopt;
  const bool plant = s.kind == "plant";
  if (plant && schema < 3) return "is a plant session" + server + "plant sessions yet";
  struct Since {
    bool plant;
    int schema;
    const char *first, *second, *what;
  };
  static constexpr Since kSince[] = {{true, 4, "retake", "retake_cancelled", "retakes"},
                                     {true, 5, "node_placed", "placement_undone", "branches"},
                                     {true, 6, "relocation", "relocation", "moved transmitter"},
                                     {false, 7, "relocation", "relocation", "moved transmitter"}};
  const std::vector<Event> events = local.events(s.id);
  const std::string kind = plant ? "plant" : "leaf";
  for (const Since& since : kSince)
    if (since.plant == plant && schema < since.schema && std::any_of(events.begin(), events.end(), [&](const Event& e) {
          return e.kind == since.first || e.kind == since.second;
        }))
      return "is a " + kind + " session with " + (since.schema == 4 || since.schema == 5 ? "" : "a ") + since.what +
             server + "a " + kind + "'s " + since.what + " yet";
  return std::nullopt;
}

}  // namespace

PushReport push(Store& local, const std::string& url, const SyncOptions& options) {
  PushReport report;
  std::vector<SessionInfo> sessions = local.sessions();
  if (options.station) {
    checkStationId(*options.station);
    sessions.erase(std::remove_if(sessions.begin(), sessions.end(),
                                  [&](const SessionInfo& s) { return s.station != *options.station; }),
                   sessions.end());
  }
  pg::Connection c(url);
  const int schema = serverSchema(c);
  // Whether the server knows a genesis that covers the station (lab schema 10).
  const bool genesisForms = pg::hasGenesisForms(c);
  std::map<std::string, std::map<std::int64_t, ServerHead>> heads;  // by station
  const auto problem = [&](const SessionInfo& s, const std::string& what, const std::string& remedy) {
    report.problems.push_back({s.station, s.id, what, remedy});
    if (options.progress) options.progress("session " + label(s) + ": " + what);
  };
  // Statements of at most this many rows (libpq takes up to 65 535 parameters).
  constexpr std::size_t kRowsPerStatement = 500;
  for (const SessionInfo& s : sessions) {
    ++report.sessionsSeen;
    try {
      checkStationId(s.station);
    } catch (const StoreError& e) {
      problem(s, e.what(), e.remedy());
      continue;
    }
    // What a server of an older schema cannot take yet stays on this station, whole, named.
    if (const auto missing = beyondServer(s, schema, genesisForms, local)) {
      problem(s, *missing + "; it stays on this station, whole",
              "the lab's administrator runs 'leafdig server init --url …' with this leafdig (it upgrades the server), "
              "then push again");
      continue;
    }
    auto stationHeads = heads.find(s.station);
    if (stationHeads == heads.end()) stationHeads = heads.emplace(s.station, serverHeads(c, s.station)).first;
    for (int attempt = 0;; ++attempt) {
      try {
        const auto found = stationHeads->second.find(s.id);
        const bool onServer = found != stationHeads->second.end();
        ServerHead head = onServer ? found->second : ServerHead{0, 0, genesisOf(s), genesisOf(s)};
        if (onServer && head.genesis != genesisOf(s)) {
          problem(s,
                  "the server holds another session " + label(s) +
                      " (created at another time or with other settings): two stations use the id '" + s.station + "'",
                  "give each station its own id (--station, or [station] id= in the settings file) and push again");
          break;
        }
        if (head.headSeq > s.headSeq) {
          ++report.sessionsBehind;  // a curator's events: `sync pull` takes them in
          break;
        }
        const std::vector<Event> events = local.events(s.id, std::max<std::int64_t>(head.headSeq, 1));
        if (head.headSeq > 0 && (events.empty() || events.front().seq != head.headSeq)) {
          problem(s, "the station's file lacks event " + std::to_string(head.headSeq) + " that the server holds",
                  "run 'leafdig sessions verify' on the station's file");
          break;
        }
        const std::string localHashAtServerHead = head.headSeq == 0 ? genesisOf(s) : events.front().hash;
        if (localHashAtServerHead != head.headHash) {
          problem(s,
                  "the station's copy and the server's differ at event " + std::to_string(head.headSeq) +
                      " (the server's holds another event there)",
                  "nothing was sent for this session; a curator decides which copy stands (docs/lab.md, Conflicts)");
          break;
        }
        if (head.headSeq == s.headSeq) {
          ++report.sessionsUpToDate;
          break;
        }
        const std::size_t from = head.headSeq == 0 ? 0 : 1;  // events[0] is the server's head, already there
        if (const auto bad = untransportable(s, events)) {
          problem(s, *bad, "the lab server keeps text as UTF-8; this session stays on the station");
          break;
        }
        std::int64_t serverId = head.id;
        for (std::size_t at = from; at < events.size();) {
          const std::size_t end = std::min(events.size(), at + options.eventsPerTransaction);
          c.begin();
          try {
            if (serverId == 0) {
              insertSession(c, s);
              serverId = c.exec("SELECT id FROM leafdig.sessions WHERE station = $1 AND station_session_id = $2",
                                {s.station, std::to_string(s.id)})
                             .int64(0, 0);
            }
            for (std::size_t k = at; k < end; k += kRowsPerStatement)
              insertEvents(c, serverId, s.station, events, k, std::min(end, k + kRowsPerStatement));
            c.commit();
          } catch (...) {
            c.rollback();
            throw;
          }
          ++report.transactions;
          if (head.id == 0 && at == from) ++report.sessionsNew;
          report.eventsSent += static_cast<std::int64_t>(end - at);
          stationHeads->second[s.id] = {serverId, events[end - 1].seq, events[end - 1].hash, genesisOf(s)};
          head.id = serverId;
          at = end;
        }
        if (options.progress)
          options.progress("session " + label(s) + ": events " + std::to_string(events[from].seq) + " to " +
                           std::to_string(events.back().seq) + " sent");
        break;
      } catch (const pg::Error& e) {
        if (e.kind() == StoreErrorKind::Unreachable) throw;
        if (e.kind() == StoreErrorKind::Conflict && attempt == 0) {
          // Someone else (a second push of this file, a curator) moved the session on the
          // server since we looked: look again, once.
          stationHeads->second = serverHeads(c, s.station);
          continue;
        }
        problem(s, e.what(), e.remedy());
        break;
      }
    }
  }
  return report;
}

namespace {

// What a pull may bring (docs/lab.md, "Sync"): a curator's review of a capture the station
// completed — corrections, a decision (approved or rejected), and after a decision only a
// curator's reopening of it, after which corrections and a decision again — each event one
// leafdig writes, and the session as a whole still replaying. A server that sends anything else
// (an undo, a new point, a capture's status) is refused in words and nothing of the session is
// taken: the station's own capture is never rewritten from outside.
void checkPulled(Store& local, const SessionInfo& s, const std::vector<Event>& events, const SyncOptions& options) {
  const auto refuse = [&](const Event& e, const std::string& why) {
    throw StoreError(StoreErrorKind::Conflict,
                     "the server sends event " + std::to_string(e.seq) + " (" + e.kind.substr(0, 40) + ") of session " +
                         label(s) + ", which " + why,
                     "nothing of the session was taken in; a pull brings only a curator's corrections and decision "
                     "of a completed capture — ask the lab's administrator to check the server (docs/lab.md, "
                     "\"Sync\")");
  };
  std::string state = s.status;
  for (const Event& e : events) {
    if (const auto problem = eventProblem(e.kind, e.payloadJson, e.raw)) refuse(e, "leafdig cannot read: " + *problem);
    // A status names its status; a reopening (eventProblem checked its shape) also the decision it
    // reopens. The payload is read once.
    std::string status, reopens;
    if (e.kind == "status") {
      const auto p = nlohmann::json::parse(e.payloadJson, nullptr, false);
      const auto text = [&p](const char* key) {
        return p.is_object() && p.contains(key) && p.at(key).is_string() ? p.at(key).get<std::string>() : std::string();
      };
      status = text("status");
      if (!status.empty()) reopens = text("reopens");
    }
    const bool review = e.kind == "corrected" || status == "approved" || status == "rejected" || !reopens.empty();
    if (!review) refuse(e, "is not a curator's correction, decision or reopening");
    if (!reopens.empty()) {
      if (state != reopens)
        refuse(e, "reopens a session " + reopens + " that is " + state +
                      " at the station: only an approved or rejected session is reopened");
    } else if (state != "complete") {
      refuse(e, "reviews a session that is " + state + " at the station: only a complete capture is reviewed");
    }
    if (!status.empty()) state = status;
  }
  if (options.replays) {
    std::vector<Event> all = local.events(s.id);
    all.insert(all.end(), events.begin(), events.end());
    try {
      options.replays(s, all);
    } catch (const StoreError&) {
      throw;
    } catch (const std::exception& x) {
      refuse(events.front(), std::string("with the events after it does not replay: ") + x.what());
    }
  }
}

}  // namespace

PullReport pull(Store& local, const std::string& url, const SyncOptions& options) {
  PullReport report;
  std::vector<SessionInfo> sessions = local.sessions();
  if (options.station) checkStationId(*options.station);
  pg::Connection c(url);
  std::map<std::string, std::map<std::int64_t, ServerHead>> heads;
  for (const SessionInfo& s : sessions) {
    if (options.station && s.station != *options.station) continue;
    ++report.sessionsSeen;
    try {
      checkStationId(s.station);
    } catch (const StoreError&) {
      continue;  // never pushed: nothing to pull
    }
    auto stationHeads = heads.find(s.station);
    if (stationHeads == heads.end()) stationHeads = heads.emplace(s.station, serverHeads(c, s.station)).first;
    const auto found = stationHeads->second.find(s.id);
    if (found == stationHeads->second.end() || found->second.headSeq <= s.headSeq) continue;
    const ServerHead& head = found->second;
    try {
      if (head.genesis != genesisOf(s))
        throw StoreError(
            StoreErrorKind::Conflict,
            "the server holds another session " + label(s) + ": two stations use the id '" + s.station + "'",
            "give each station its own id (--station)");
      const std::vector<Event> events = pg::readEvents(c, head.id, s.headSeq + 1, s.id);
      checkPulled(local, s, events, options);
      local.import(s.id, events);
      ++report.sessionsUpdated;
      report.eventsTaken += static_cast<std::int64_t>(events.size());
      if (options.progress)
        options.progress("session " + label(s) + ": " + std::to_string(events.size()) + " event(s) taken in");
    } catch (const pg::Error& e) {
      if (e.kind() == StoreErrorKind::Unreachable) throw;
      report.problems.push_back({s.station, s.id, e.what(), e.remedy()});
    } catch (const StoreError& e) {
      if (e.kind() == StoreErrorKind::DiskFull || e.kind() == StoreErrorKind::Io) throw;
      report.problems.push_back({s.station, s.id, e.what(), e.remedy()});
    }
  }
  return report;
}

}  // namespace leafdig::db
