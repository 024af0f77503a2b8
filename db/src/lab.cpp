// The lab server: URLs, schema and roles, logins, and the server as a store of sessions.
#include "leafdig/db/lab.hpp"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <map>
#include <thread>

#include "lab_schema.hpp"
#include "leafdig/names/name_table.hpp"
#include "pg.hpp"

namespace leafdig::db {

// ---- schema and roles ---------------------------------------------------------------------

namespace {

constexpr const char* kInitLock = "4710468163";  // "LEAF" in a number

// Takes init's advisory lock, waiting at most `seconds`. Any login may take an advisory lock
// with the same number, so a holder that does not let go is named (pid, login, since when)
// instead of being waited for without end.
void takeInitLock(pg::Connection& c, double seconds) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  for (;;) {
    if (c.exec(std::string("SELECT pg_catalog.pg_try_advisory_lock(") + kInitLock + ")").text(0, 0) == "t") return;
    if (std::chrono::steady_clock::now() >= deadline) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  const auto holder = c.exec(
      "SELECT a.pid, coalesce(a.usename::text, '?'), coalesce(a.application_name, ''), "
      "coalesce(pg_catalog.to_char(a.backend_start, 'YYYY-MM-DD HH24:MI:SS'), '?') "
      "FROM pg_catalog.pg_locks l LEFT JOIN pg_catalog.pg_stat_activity a ON a.pid = l.pid "
      "WHERE l.locktype = 'advisory' AND l.objsubid = 1 AND l.granted AND l.pid <> pg_catalog.pg_backend_pid() "
      "AND ((l.classid::bigint << 32) | l.objid::bigint) = " +
      std::string(kInitLock) + " LIMIT 1");
  std::string who = "another connection";
  std::string remedy = "wait until it ends, then run init again; nothing was changed";
  if (holder.rows() == 1) {
    who = "connection " + holder.text(0, 0) + " (login " + holder.text(0, 1) +
          (holder.text(0, 2).empty() ? "" : ", " + holder.text(0, 2)) + ", connected " + holder.text(0, 3) + " UTC)";
    remedy = "if it is not another init, end it (SELECT pg_terminate_backend(" + holder.text(0, 0) +
             ") as the administrator) and run init again; nothing was changed";
  }
  throw StoreError(StoreErrorKind::Busy,
                   "server init waited " + std::to_string(static_cast<int>(seconds)) + " s for its lock on " +
                       c.where() + ": " + who + " holds it",
                   remedy);
}

// init's migration to `version` gave up waiting for a lock: who holds the leafdig tables (the
// oldest open transaction of another connection on them), and what the administrator may do.
StoreError lockedOut(pg::Connection& c, double seconds, int version) {
  const auto holder = c.exec(
      "SELECT a.pid, coalesce(a.usename::text, '?'), coalesce(a.state, '?'), "
      "coalesce(pg_catalog.to_char(a.xact_start, 'YYYY-MM-DD HH24:MI:SS'), '?') "
      "FROM pg_catalog.pg_locks l JOIN pg_catalog.pg_class r ON r.oid = l.relation "
      "JOIN pg_catalog.pg_namespace n ON n.oid = r.relnamespace "
      "JOIN pg_catalog.pg_stat_activity a ON a.pid = l.pid "
      "WHERE n.nspname = 'leafdig' AND l.granted AND l.pid <> pg_catalog.pg_backend_pid() "
      "ORDER BY a.xact_start LIMIT 1");
  std::string who = "another connection", remedy = "end it, then run init again; nothing was changed";
  if (holder.rows() == 1) {
    who = "connection " + holder.text(0, 0) + " (login " + holder.text(0, 1) + ", " + holder.text(0, 2) + " since " +
          holder.text(0, 3) + " UTC)";
    remedy = "ask " + holder.text(0, 1) + " to end that transaction, or end it as the administrator (SELECT " +
             "pg_terminate_backend(" + holder.text(0, 0) + ")); then run init again — nothing was changed";
  }
  return StoreError(StoreErrorKind::Busy,
                    "server init waited " + std::to_string(static_cast<int>(seconds)) + " s to upgrade " + c.where() +
                        " to schema " + std::to_string(version) + ": " + who + " holds the leafdig tables",
                    remedy);
}

}  // namespace

namespace {

// The statistics PostgreSQL keeps of each table (rows inserted, live, scanned…) tell a login
// how much every station pushed, through rows row-level security hides (issue 47, 8). The
// pg_stat views and their functions are this database's own catalog objects, so taking them
// from PUBLIC here touches no other database; only their owner, the cluster's superuser, may.
// The lab's administrator keeps them (a superuser, or pg_read_all_stats granted by hand).
void hideTableStatistics(pg::Connection& c, ServerInit& out) {
  const auto open = c.exec(
      "SELECT 'TABLE ' || k.oid::pg_catalog.regclass::text FROM pg_catalog.pg_class k "
      "JOIN pg_catalog.pg_namespace n ON n.oid = k.relnamespace "
      "WHERE n.nspname = 'pg_catalog' AND k.relkind = 'v' "
      "AND k.relname ~ '^pg_stat(io)?_(all|user|sys|xact_all|xact_user|xact_sys)_(tables|indexes|sequences)$' "
      "AND pg_catalog.has_table_privilege('public', k.oid, 'SELECT') "
      "UNION ALL SELECT 'FUNCTION ' || p.oid::pg_catalog.regprocedure::text FROM pg_catalog.pg_proc p "
      "JOIN pg_catalog.pg_namespace n ON n.oid = p.pronamespace "
      "WHERE n.nspname = 'pg_catalog' AND p.pronargs = 1 AND p.proargtypes[0] = 'pg_catalog.oid'::pg_catalog.regtype "
      "AND p.proname ~ '^pg_stat_get_(xact_)?(numscans|lastscan|tuples_[a-z_]+|live_tuples|dead_tuples|"
      "mod_since_analyze|ins_since_vacuum|blocks_(fetched|hit)|last_[a-z_]+_time|[a-z]*vacuum_count|"
      "[a-z]*analyze_count)$' "
      "AND pg_catalog.has_function_privilege('public', p.oid, 'EXECUTE') ORDER BY 1");
  if (open.rows() == 0) return;
  if (c.exec("SELECT rolsuper FROM pg_catalog.pg_roles WHERE rolname = current_user").text(0, 0) != "t") {
    out.notes.push_back(
        "every login may still read how many rows each station pushed (pg_stat_user_tables and its "
        "functions): only the cluster's superuser may take them from PUBLIC — run init again as one "
        "(docs/lab.md, \"What a role can still learn\")");
    return;
  }
  for (int i = 0; i < open.rows(); ++i) {
    const std::string object = open.text(i, 0);
    (void)c.exec("REVOKE " + std::string(object.rfind("TABLE ", 0) == 0 ? "SELECT" : "EXECUTE") + " ON " + object +
                 " FROM PUBLIC");
  }
}

}  // namespace

ServerInit initServer(const std::string& url, double lockWaitSeconds) {
  pg::Connection c(url);
  ServerInit out;
  const std::string encoding = c.exec("SHOW server_encoding").text(0, 0);
  if (encoding != "UTF8")
    throw StoreError(StoreErrorKind::Input,
                     "the database at " + c.where() + " stores text as " + encoding + ", not UTF-8",
                     "create the lab's database with ENCODING 'UTF8' (createdb -E UTF8 …) and run init on it");
  // One init at a time (two administrators, or a retry beside a slow first run).
  takeInitLock(c, lockWaitSeconds);
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
    // A migration waits at most --lock-wait for the tables it changes: a reader's transaction
    // left open would otherwise hold the upgrade, and every push behind it, for ever.
    (void)c.exec("SELECT pg_catalog.set_config('lock_timeout', $1, false)",
                 {std::to_string(static_cast<long long>(lockWaitSeconds * 1000)) + "ms"});
    for (int v = out.fromVersion; v < kLabSchemaVersion; ++v) {
      c.begin();
      try {
        try {
          c.execScript(detail::kLabMigrations[static_cast<std::size_t>(v)]);
        } catch (const pg::Error& e) {
          if (e.sqlState() != "55P03") throw;  // lock_not_available
          c.rollback();
          throw lockedOut(c, lockWaitSeconds, v + 1);
        }
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
    // Only the lab's logins reach this database: PUBLIC may neither connect nor make temporary
    // tables here (a login of another lab on the same cluster is a member of the same group
    // roles). The logins this lab already knows keep CONNECT; add-user grants it to each new one.
    const std::string database = c.quoteIdentifier(c.exec("SELECT pg_catalog.current_database()").text(0, 0));
    if (c.exec("SELECT pg_catalog.has_database_privilege('public', pg_catalog.current_database(), 'CONNECT') "
               "OR pg_catalog.has_database_privilege('public', pg_catalog.current_database(), 'TEMPORARY')")
            .text(0, 0) == "t") {
      const auto known = c.exec(
          "SELECT DISTINCT u.rolname FROM pg_catalog.pg_auth_members m "
          "JOIN pg_catalog.pg_roles g ON g.oid = m.roleid JOIN pg_catalog.pg_roles u ON u.oid = m.member "
          "WHERE g.rolname IN ('leafdig_technicians', 'leafdig_curators', 'leafdig_readers') AND u.rolcanlogin "
          "AND (u.rolname IN (SELECT login FROM leafdig.station_logins) "
          "OR u.rolname IN (SELECT written_by FROM leafdig.events) OR u.rolname IN (SELECT pushed_by FROM "
          "leafdig.sessions))");
      for (int i = 0; i < known.rows(); ++i)
        (void)c.exec("GRANT CONNECT ON DATABASE " + database + " TO " + c.quoteIdentifier(known.text(i, 0)));
      (void)c.exec("GRANT CONNECT ON DATABASE " + database + " TO CURRENT_USER");
      (void)c.exec("REVOKE CONNECT, TEMPORARY ON DATABASE " + database + " FROM PUBLIC");
      if (c.exec("SELECT pg_catalog.has_database_privilege('public', pg_catalog.current_database(), 'CONNECT')")
              .text(0, 0) == "t")
        out.notes.push_back("every login of the cluster may still connect to " + database +
                            ": this login does not own it — as its owner run REVOKE CONNECT, TEMPORARY ON DATABASE " +
                            database + " FROM PUBLIC; then run init again");
    }
    hideTableStatistics(c, out);
  } catch (...) {
    (void)c.exec(std::string("SELECT pg_catalog.pg_advisory_unlock(") + kInitLock + ")");
    throw;
  }
  (void)c.exec(std::string("SELECT pg_catalog.pg_advisory_unlock(") + kInitLock + ")");
  return out;
}

const char* toString(LabRole role) {
  return nameIn(kLabRoleNames, role);
}

LabRole labRoleFromString(const std::string& text) {
  return parseName(kLabRoleNames, text, "role");
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
    if (exists) {
      // One login, one role: a technician that were a curator too would review its own captures.
      for (const LabRole other : {LabRole::Technician, LabRole::Curator, LabRole::Reader}) {
        if (other == role) continue;
        const std::string otherGroup = std::string("leafdig_") + toString(other) + "s";
        if (c.exec("SELECT 1 FROM pg_catalog.pg_auth_members m JOIN pg_catalog.pg_roles g ON g.oid = m.roleid "
                   "JOIN pg_catalog.pg_roles u ON u.oid = m.member WHERE g.rolname = $1 AND u.rolname = $2",
                   {otherGroup, login})
                .rows() > 0)
          throw StoreError(StoreErrorKind::Input,
                           "the login '" + login + "' is already a " + toString(other) + " on " + c.where() +
                               ": one login holds one role, so nobody reviews their own capture",
                           std::string("give the ") + toString(role) + " a login of its own (--login another name)");
      }
    }
    if (password) {
      // The verifier is computed here: the password itself never reaches the server's logs.
      const std::string verifier = c.quoteLiteral(c.encryptPassword(*password, login));
      (void)c.exec((exists ? "ALTER ROLE " : "CREATE ROLE ") + ident + " LOGIN PASSWORD " + verifier);
      out.created = !exists;
    }
    (void)c.exec("GRANT " + c.quoteIdentifier(group) + " TO " + ident);
    // This lab's login: it may connect here (PUBLIC may not, since schema 10's init), with a
    // bounded number of connections, and a transaction or statement it leaves running ends.
    const std::string database = c.quoteIdentifier(c.exec("SELECT pg_catalog.current_database()").text(0, 0));
    (void)c.exec("GRANT CONNECT ON DATABASE " + database + " TO " + ident);
    (void)c.exec("ALTER ROLE " + ident + " CONNECTION LIMIT " + std::to_string(kLoginConnectionLimit));
    (void)c.exec("ALTER ROLE " + ident + " IN DATABASE " + database +
                 " SET idle_in_transaction_session_timeout = " + c.quoteLiteral(kIdleInTransactionTimeout));
    (void)c.exec("ALTER ROLE " + ident + " IN DATABASE " + database +
                 " SET statement_timeout = " + c.quoteLiteral(kStatementTimeout));
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

// The session columns; a server of schema 2 (before plant sessions) holds leaf sessions only.
std::string sessionColumns(int schemaVersion, bool genesisForms) {
  return std::string(
             "SELECT id, station_session_id, project, plant, leaf_position, operator, station, status, mode, "
             "capture_order, settings_json, created_utc, head_seq, head_hash, leaf_type, measured_area_mm2, ") +
         (schemaVersion >= 3 ? "kind" : "'leaf'") + (genesisForms ? ", genesis_form" : ", 1") +
         " FROM leafdig.sessions ";
}

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
  s.kind = r.text(i, 16);
  s.genesisForm = static_cast<int>(r.int64(i, 17));
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
  schemaVersion_ = std::stoi(v.text(0, 0));
  login_ = conn_->exec("SELECT session_user").text(0, 0);
  genesisForms_ = pg::hasGenesisForms(*conn_);
  if (schemaVersion_ > kLabSchemaVersion)
    throw StoreError(StoreErrorKind::TooNew,
                     "the lab server " + conn_->where() + " has schema version " + v.text(0, 0) +
                         "; this leafdig knows up to " + std::to_string(kLabSchemaVersion),
                     "install a newer leafdig");
}

LabStore::~LabStore() = default;

std::optional<LabRole> LabStore::role() const {
  for (const auto& [role, word] : kLabRoleNames) {
    const std::string group = std::string("leafdig_") + std::string(word) + "s";
    if (conn_
            ->exec("SELECT pg_has_role(session_user, oid, 'MEMBER') FROM pg_catalog.pg_roles WHERE rolname = $1",
                   {group})
            .text(0, 0) == "t")
      return role;
  }
  return std::nullopt;
}

bool LabStore::passwordChecked() const {
  return conn_->usedPassword();
}

std::string LabStore::describe() const {
  return conn_->where();
}

std::vector<SessionInfo> LabStore::sessions() const {
  const auto r = conn_->exec(sessionColumns(schemaVersion_, genesisForms_) + "ORDER BY id");
  std::vector<SessionInfo> out;
  out.reserve(static_cast<std::size_t>(r.rows()));
  for (int i = 0; i < r.rows(); ++i) out.push_back(sessionAt(r, i));
  return out;
}

std::optional<SessionInfo> LabStore::session(std::int64_t id) const {
  const auto r = conn_->exec(sessionColumns(schemaVersion_, genesisForms_) + "WHERE id = $1", {std::to_string(id)});
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
  ChainReport r = verifyChain(s->stationSessionId, g.text(0, 0), s->headSeq, s->headHash, events(session));
  r.genesisForm = s->genesisForm;
  if (r.ok && genesisOf(*s) != g.text(0, 0)) {
    r.ok = false;
    r.firstBadSeq = 0;
    r.problem =
        "its station, kind, creation time or settings were changed after it was written (its genesis hash "
        "differs)";
  }
  return r;
}

std::int64_t LabStore::append(std::int64_t session, const EventInput& in) {
  return appendAll(session, {in});
}

std::int64_t LabStore::appendAll(std::int64_t session, const std::vector<EventInput>& events) {
  // The chain is computed here and checked again by the server; another curator deciding
  // at the same instant makes the server refuse one of the two, which then retries once on
  // the new head (and is refused by review's rules if the session is no longer complete).
  // Several events go in one transaction: all or none.
  for (const EventInput& in : events)
    for (const std::string* text : {&in.payloadJson, &in.raw})
      if (const auto bad = badTextByte(*text))
        throw StoreError(StoreErrorKind::Input, "the event's text is not UTF-8 (byte " + std::to_string(*bad) + ")",
                         "the lab server stores text as UTF-8");
  for (int attempt = 0;; ++attempt) {
    const auto h =
        conn_->exec("SELECT station, station_session_id, head_seq, head_hash FROM leafdig.sessions WHERE id = $1",
                    {std::to_string(session)});
    if (h.rows() == 0)
      throw StoreError(StoreErrorKind::Input, "no session " + std::to_string(session) + " on " + conn_->where(),
                       "'leafdig sessions list --db …' shows the sessions this login may see");
    std::int64_t seq = h.int64(0, 2);
    std::string hash = h.text(0, 3);
    if (!events.empty() && events.front().follows && *events.front().follows != seq)
      throw StoreError(StoreErrorKind::Conflict,
                       "session " + std::to_string(session) + " on " + conn_->where() + " moved on to event " +
                           std::to_string(seq) + " while this change was worked out from event " +
                           std::to_string(*events.front().follows) + " (another curator at the same time?)",
                       "nothing was written; look at the session again (sessions show) and run the command again");
    try {
      if (events.size() > 1) conn_->begin();
      for (const EventInput& in : events) {
        const std::string utc = utcNow();
        const std::string next =
            eventHash(hash, h.int64(0, 1), seq + 1, utc, in.monoNs, in.kind, in.payloadJson, in.raw);
        (void)conn_->exec(
            "INSERT INTO leafdig.events(session_id, station, seq, utc, mono_ns, kind, payload_json, raw, prev_hash, "
            "hash) "
            "VALUES ($1, $2, $3, $4, $5, $6, $7, $8, $9, $10)",
            {std::to_string(session), h.text(0, 0), std::to_string(seq + 1), utc, std::to_string(in.monoNs), in.kind,
             in.payloadJson, in.raw, hash, next});
        ++seq;
        hash = next;
      }
      if (events.size() > 1) conn_->commit();
      return seq;
    } catch (const pg::Error& x) {
      if (events.size() > 1) conn_->rollback();
      if (x.kind() != StoreErrorKind::Conflict || attempt > 0) throw;
    } catch (...) {
      conn_->rollback();
      throw;
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
