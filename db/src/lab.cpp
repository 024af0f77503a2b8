// The lab server: URLs, schema and roles, logins, and the server as a store of sessions.
#include "leafdig/db/lab.hpp"

#include <algorithm>
#include <cctype>

#include "lab_schema.hpp"
#include "pg.hpp"

namespace leafdig::db {

bool isServerUrl(const std::string& text) {
  return text.rfind("postgresql://", 0) == 0 || text.rfind("postgres://", 0) == 0;
}

std::string redactUrl(const std::string& url) {
  std::string out = url;
  // user:password@host
  if (isServerUrl(out)) {
    const std::size_t start = out.find("://") + 3;
    const std::size_t at = out.find('@', start);
    const std::size_t slash = out.find('/', start);
    if (at != std::string::npos && (slash == std::string::npos || at < slash)) {
      const std::size_t colon = out.find(':', start);
      if (colon != std::string::npos && colon < at) out.replace(colon + 1, at - colon - 1, "***");
    }
  }
  // password=… in the query (?password=x&…) or in key=value strings (password=x host=…)
  for (std::size_t p = out.find("password="); p != std::string::npos; p = out.find("password=", p + 1)) {
    if (p > 0 && std::isalnum(static_cast<unsigned char>(out[p - 1])) != 0) continue;  // e.g. "nopassword="
    const std::size_t v = p + 9;
    std::size_t end = v;
    if (end < out.size() && out[end] == '\'') {
      end = out.find('\'', end + 1);
      end = end == std::string::npos ? out.size() : end + 1;
    } else {
      while (end < out.size() && out[end] != '&' && out[end] != ' ') ++end;
    }
    out.replace(v, end - v, "***");
  }
  return out;
}

// ---- schema and roles ---------------------------------------------------------------------

ServerInit initServer(const std::string& url) {
  pg::Connection c(url);
  ServerInit out;
  const std::string encoding = c.exec("SHOW server_encoding").text(0, 0);
  if (encoding != "UTF8")
    throw StoreError(StoreErrorKind::Input,
                     "the database at " + c.where() + " stores text as " + encoding + ", not UTF-8",
                     "create the lab's database with ENCODING 'UTF8' (createdb -E UTF8 …) and run init on it");
  // One init at a time (two administrators, or a retry beside a slow first run).
  (void)c.exec("SELECT pg_advisory_lock(4710468163)");  // "LEAF" in a number
  try {
    for (const char* role : detail::kLabRoles) {
      if (c.exec("SELECT 1 FROM pg_roles WHERE rolname = $1", {std::string(role)}).rows() == 0) {
        (void)c.exec("CREATE ROLE " + c.quoteIdentifier(role) + " NOLOGIN");
        out.rolesCreated.emplace_back(role);
      }
    }
    const bool exists = c.exec("SELECT 1 FROM pg_namespace WHERE nspname = 'leafdig'").rows() > 0;
    if (exists) {
      const auto v = c.exec("SELECT value FROM leafdig.meta WHERE key = 'schema_version'");
      out.fromVersion = v.rows() ? std::stoi(v.text(0, 0)) : 0;
    }
    if (out.fromVersion > kLabSchemaVersion)
      throw StoreError(StoreErrorKind::TooNew,
                       "the lab server " + c.where() + " has schema version " + std::to_string(out.fromVersion) +
                           "; this leafdig knows up to " + std::to_string(kLabSchemaVersion),
                       "install a newer leafdig; the server was not changed");
    for (int v = out.fromVersion; v < kLabSchemaVersion; ++v) {
      c.begin();
      try {
        c.execScript(detail::kLabMigrations[static_cast<std::size_t>(v)]);
        (void)c.exec(
            "INSERT INTO leafdig.meta(key, value) VALUES ('schema_version', $1) "
            "ON CONFLICT (key) DO UPDATE SET value = EXCLUDED.value",
            {std::to_string(v + 1)});
        c.commit();
      } catch (...) {
        c.rollback();
        throw;
      }
    }
    out.toVersion = kLabSchemaVersion;
  } catch (...) {
    (void)c.exec("SELECT pg_advisory_unlock(4710468163)");
    throw;
  }
  (void)c.exec("SELECT pg_advisory_unlock(4710468163)");
  return out;
}

const char* toString(LabRole role) {
  switch (role) {
    case LabRole::Technician: return "technician";
    case LabRole::Curator: return "curator";
    case LabRole::Reader: return "reader";
  }
  return "reader";
}

std::optional<LabRole> labRoleFromString(const std::string& text) {
  for (const LabRole r : {LabRole::Technician, LabRole::Curator, LabRole::Reader})
    if (text == toString(r)) return r;
  return std::nullopt;
}

AddedUser addUser(const std::string& url, const std::string& login, LabRole role, const std::string& station,
                  const std::optional<std::string>& password) {
  if (login.empty() || login.size() > 63 || badTextByte(login))
    throw StoreError(StoreErrorKind::Input, "the login name '" + login + "' cannot be used",
                     "give 1 to 63 characters of UTF-8 text");
  if (role == LabRole::Technician) {
    if (station.empty())
      throw StoreError(StoreErrorKind::Input, "a technician is bound to one station: give --station",
                       "the station id is the one its sessions carry (leafdig doctor shows it)");
    checkStationId(station);
  } else if (!station.empty()) {
    throw StoreError(StoreErrorKind::Input,
                     std::string("a ") + toString(role) + " is not bound to a station: leave out --station",
                     "only technicians push, for their station");
  }
  pg::Connection c(url);
  AddedUser out{false, login, role, station};
  const std::string group = std::string("leafdig_") + toString(role) + "s";
  const std::string ident = c.quoteIdentifier(login);
  c.begin();
  try {
    const bool exists = c.exec("SELECT 1 FROM pg_roles WHERE rolname = $1", {login}).rows() > 0;
    if (!exists && !password)
      throw StoreError(StoreErrorKind::Input, "there is no login '" + login + "' on " + c.where(),
                       "give --password-file to create it, or name an existing login");
    if (password) {
      // The verifier is computed here: the password itself never reaches the server's logs.
      const std::string verifier = c.quoteLiteral(c.encryptPassword(*password, login));
      (void)c.exec((exists ? "ALTER ROLE " : "CREATE ROLE ") + ident + " LOGIN PASSWORD " + verifier);
      out.created = !exists;
    }
    (void)c.exec("GRANT " + c.quoteIdentifier(group) + " TO " + ident);
    if (role == LabRole::Technician)
      (void)c.exec(
          "INSERT INTO leafdig.station_logins(login, station) VALUES ($1, $2) "
          "ON CONFLICT (login) DO UPDATE SET station = EXCLUDED.station",
          {login, station});
    c.commit();
  } catch (...) {
    c.rollback();
    throw;
  }
  return out;
}

// ---- the server as a store of sessions ----------------------------------------------------

namespace {

constexpr const char* kSessionColumns =
    "SELECT id, station_session_id, project, plant, leaf_position, operator, station, status, mode, capture_order, "
    "settings_json, created_utc, head_seq, head_hash, leaf_type, measured_area_mm2 FROM leafdig.sessions ";

SessionInfo sessionAt(const pg::Result& r, int i) {
  SessionInfo s;
  s.id = r.int64(i, 0);
  s.stationSessionId = r.int64(i, 1);
  s.project = r.text(i, 2);
  s.plant = r.text(i, 3);
  s.leafPosition = static_cast<int>(r.int64(i, 4));
  s.operatorName = r.text(i, 5);
  s.station = r.text(i, 6);
  s.status = r.text(i, 7);
  s.mode = r.text(i, 8);
  s.order = r.text(i, 9);
  s.settingsJson = r.text(i, 10);
  s.createdUtc = r.text(i, 11);
  s.headSeq = r.int64(i, 12);
  s.headHash = r.text(i, 13);
  s.leafType = r.text(i, 14);
  if (!r.isNull(i, 15)) s.measuredAreaMm2 = r.number(i, 15);
  return s;
}

}  // namespace

LabStore::LabStore(const std::string& url) : conn_(std::make_unique<pg::Connection>(url)) {
  const auto notLeafdig = [&] {
    return StoreError(StoreErrorKind::NotLeafdig, "the database at " + conn_->where() + " is not a leafdig lab store",
                      "run 'leafdig server init --url …' as the lab's administrator first (docs/lab.md)");
  };
  if (conn_->exec("SELECT 1 FROM pg_namespace WHERE nspname = 'leafdig'").rows() == 0) throw notLeafdig();
  const auto v = conn_->exec("SELECT value FROM leafdig.meta WHERE key = 'schema_version'");
  if (v.rows() == 0) throw notLeafdig();
  if (std::stoi(v.text(0, 0)) > kLabSchemaVersion)
    throw StoreError(StoreErrorKind::TooNew,
                     "the lab server " + conn_->where() + " has schema version " + v.text(0, 0) +
                         "; this leafdig knows up to " + std::to_string(kLabSchemaVersion),
                     "install a newer leafdig");
}

LabStore::~LabStore() = default;

std::string LabStore::describe() const {
  return conn_->where();
}

std::vector<SessionInfo> LabStore::sessions() const {
  const auto r = conn_->exec(std::string(kSessionColumns) + "ORDER BY id");
  std::vector<SessionInfo> out;
  out.reserve(static_cast<std::size_t>(r.rows()));
  for (int i = 0; i < r.rows(); ++i) out.push_back(sessionAt(r, i));
  return out;
}

std::optional<SessionInfo> LabStore::session(std::int64_t id) const {
  const auto r = conn_->exec(std::string(kSessionColumns) + "WHERE id = $1", {std::to_string(id)});
  if (r.rows() == 0) return std::nullopt;
  return sessionAt(r, 0);
}

std::vector<Event> LabStore::events(std::int64_t session, std::int64_t fromSeq) const {
  return pg::readEvents(*conn_, session, fromSeq, session);
}

std::vector<MarkerRow> LabStore::markers(std::int64_t session) const {
  return project(events(session)).markers;
}

std::vector<ThicknessRow> LabStore::thickness(std::int64_t session) const {
  return project(events(session)).thickness;
}

ChainReport LabStore::verify(std::int64_t session) const {
  const auto s = this->session(session);
  if (!s) {
    ChainReport r;
    r.ok = false;
    r.problem = "no session " + std::to_string(session) + " on the server (or not one this login may see)";
    return r;
  }
  const auto g = conn_->exec("SELECT genesis_hash FROM leafdig.sessions WHERE id = $1", {std::to_string(session)});
  return verifyChain(s->stationSessionId, g.text(0, 0), s->headSeq, s->headHash, events(session));
}

std::int64_t LabStore::append(std::int64_t session, const EventInput& in) {
  // The chain is computed here and checked again by the server; another curator deciding
  // at the same instant makes the server refuse one of the two, which then retries once on
  // the new head (and is refused by review's rules if the session is no longer complete).
  for (int attempt = 0;; ++attempt) {
    const auto h =
        conn_->exec("SELECT station, station_session_id, head_seq, head_hash FROM leafdig.sessions WHERE id = $1",
                    {std::to_string(session)});
    if (h.rows() == 0)
      throw StoreError(StoreErrorKind::Input, "no session " + std::to_string(session) + " on " + conn_->where(),
                       "'leafdig sessions list --db …' shows the sessions this login may see");
    for (const std::string* text : {&in.payloadJson, &in.raw})
      if (const auto bad = badTextByte(*text))
        throw StoreError(StoreErrorKind::Input, "the event's text is not UTF-8 (byte " + std::to_string(*bad) + ")",
                         "the lab server stores text as UTF-8");
    Event e;
    e.seq = h.int64(0, 2) + 1;
    e.utc = utcNow();
    e.monoNs = in.monoNs;
    e.prevHash = h.text(0, 3);
    e.hash = eventHash(e.prevHash, h.int64(0, 1), e.seq, e.utc, e.monoNs, in.kind, in.payloadJson, in.raw);
    try {
      (void)conn_->exec(
          "INSERT INTO leafdig.events(session_id, station, seq, utc, mono_ns, kind, payload_json, raw, prev_hash, "
          "hash) "
          "VALUES ($1, $2, $3, $4, $5, $6, $7, $8, $9, $10)",
          {std::to_string(session), h.text(0, 0), std::to_string(e.seq), e.utc, std::to_string(e.monoNs), in.kind,
           in.payloadJson, in.raw, e.prevHash, e.hash});
      return e.seq;
    } catch (const pg::Error& x) {
      if (x.kind() != StoreErrorKind::Conflict || attempt > 0) throw;
    }
  }
}

std::int64_t LabStore::ensureOperator(const std::string&, const std::string&) {
  return 0;  // the server keeps who signed each event in the event (and written_by)
}

std::int64_t LabStore::recordExport(std::int64_t session, const std::string& path, const std::string& format) {
  try {
    const auto r =
        conn_->exec("INSERT INTO leafdig.exports(session_id, path, format, utc) VALUES ($1, $2, $3, $4) RETURNING id",
                    {std::to_string(session), path, format, utcNow()});
    return r.int64(0, 0);
  } catch (const pg::Error& x) {
    if (x.kind() == StoreErrorKind::Refused) return 0;  // a reader exports without a record
    throw;
  }
}

std::unique_ptr<EventStore> openEventStore(const std::string& pathOrUrl, bool readOnly) {
  if (isServerUrl(pathOrUrl)) return std::make_unique<LabStore>(pathOrUrl);
  return std::make_unique<Store>(pathOrUrl, readOnly);
}

namespace pg {

std::vector<Event> readEvents(Connection& c, std::int64_t serverSession, std::int64_t fromSeq, std::int64_t asSession) {
  const auto r = c.exec(
      "SELECT seq, utc, mono_ns, kind, payload_json, raw, prev_hash, hash FROM leafdig.events "
      "WHERE session_id = $1 AND seq >= $2 ORDER BY seq",
      {std::to_string(serverSession), std::to_string(fromSeq)});
  std::vector<Event> out;
  out.reserve(static_cast<std::size_t>(r.rows()));
  for (int i = 0; i < r.rows(); ++i)
    out.push_back(Event{asSession, r.int64(i, 0), r.text(i, 1), r.int64(i, 2), r.text(i, 3), r.text(i, 4), r.text(i, 5),
                        r.text(i, 6), r.text(i, 7)});
  return out;
}

}  // namespace pg
}  // namespace leafdig::db
