// The Store's records (store.hpp): operators, projects, plants, leaves, devices and sessions;
// events appended in one transaction with their projection, read back and verified; exports.
#include <SQLiteCpp/SQLiteCpp.h>
#include <sqlite3.h>

#include <algorithm>
#include <cstdio>
#include <ctime>
#include <nlohmann/json.hpp>

#include "leafdig/db/store.hpp"
#include "schema.hpp"
#include "store_impl.hpp"

namespace leafdig::db {

using detail::OperationClock;
using detail::rethrow;

namespace {
std::int64_t upsertId(SQLite::Database& db, const std::string& select, const std::string& insert,
                      const std::vector<std::string>& args) {
  SQLite::Statement q(db, select);
  for (int i = 0; i < q.getBindParameterCount(); ++i) q.bind(i + 1, args[static_cast<std::size_t>(i)]);
  if (q.executeStep()) return q.getColumn(0).getInt64();
  SQLite::Statement ins(db, insert);
  for (std::size_t i = 0; i < args.size(); ++i) ins.bind(static_cast<int>(i + 1), args[i]);
  ins.exec();
  return db.getLastInsertRowid();
}
}  // namespace

std::int64_t Store::ensureOperator(const std::string& name, const std::string& role) {
  try {
    const auto id = upsertId(*impl_->db, "SELECT id FROM operators WHERE name=?1",
                             "INSERT INTO operators(name, role) VALUES (?1, ?2)", {name, role});
    return id;
  } catch (const SQLite::Exception& e) {
    rethrow(e, path_, "cannot record operator '" + name + "' in");
  }
}

std::int64_t Store::ensureProject(const std::string& name) {
  try {
    return upsertId(*impl_->db, "SELECT id FROM projects WHERE name=?1", "INSERT INTO projects(name) VALUES (?1)",
                    {name});
  } catch (const SQLite::Exception& e) {
    rethrow(e, path_, "cannot record project in");
  }
}

std::int64_t Store::ensurePlant(std::int64_t projectId, const std::string& name) {
  try {
    return upsertId(*impl_->db, "SELECT id FROM plants WHERE project_id=?1 AND name=?2",
                    "INSERT INTO plants(project_id, name) VALUES (?1, ?2)", {std::to_string(projectId), name});
  } catch (const SQLite::Exception& e) {
    rethrow(e, path_, "cannot record plant in");
  }
}

std::int64_t Store::ensureLeaf(std::int64_t plantId, int position, const std::string& type,
                               std::optional<double> area) {
  try {
    SQLite::Statement q(*impl_->db, "SELECT id FROM leaves WHERE plant_id=?1 AND position=?2");
    q.bind(1, plantId);
    q.bind(2, position);
    if (q.executeStep()) {
      // A leaf measured again (or typed later): what is given now is kept.
      const std::int64_t id = q.getColumn(0).getInt64();
      if (!type.empty() || area) {
        SQLite::Statement up(*impl_->db,
                             "UPDATE leaves SET type=CASE WHEN ?2 = '' THEN type ELSE ?2 END, "
                             "measured_area_mm2=COALESCE(?3, measured_area_mm2) WHERE id=?1");
        up.bind(1, id);
        up.bind(2, type);
        if (area)
          up.bind(3, *area);
        else
          up.bind(3);
        up.exec();
      }
      return id;
    }
    SQLite::Statement ins(*impl_->db,
                          "INSERT INTO leaves(plant_id, position, type, measured_area_mm2) VALUES (?1, ?2, ?3, ?4)");
    ins.bind(1, plantId);
    ins.bind(2, position);
    ins.bind(3, type);
    if (area)
      ins.bind(4, *area);
    else
      ins.bind(4);
    ins.exec();
    return impl_->db->getLastInsertRowid();
  } catch (const SQLite::Exception& e) {
    rethrow(e, path_, "cannot record leaf in");
  }
}

std::int64_t Store::ensureDevice(const std::string& kind, const std::string& port, const std::string& description) {
  try {
    return upsertId(*impl_->db, "SELECT id FROM devices WHERE kind=?1 AND port=?2",
                    "INSERT INTO devices(kind, port, description) VALUES (?1, ?2, ?3)", {kind, port, description});
  } catch (const SQLite::Exception& e) {
    rethrow(e, path_, "cannot record device in");
  }
}

std::int64_t Store::createSession(std::int64_t leafId, std::int64_t operatorId, const std::string& station,
                                  const std::string& mode, const std::string& order, const std::string& settingsJson) {
  return insertSession(leafId, 0, operatorId, station, mode, order, settingsJson);
}

std::int64_t Store::createPlantSession(std::int64_t plantId, std::int64_t operatorId, const std::string& station,
                                       const std::string& mode, const std::string& order,
                                       const std::string& settingsJson) {
  return insertSession(0, plantId, operatorId, station, mode, order, settingsJson);
}

std::int64_t Store::insertSession(std::int64_t leafId, std::int64_t plantId, std::int64_t operatorId,
                                  const std::string& station, const std::string& mode, const std::string& order,
                                  const std::string& settingsJson) {
  try {
    SQLite::Transaction tx(*impl_->db, SQLite::TransactionBehavior::IMMEDIATE);
    const std::string created = utcNow();
    // A leaf session's plant is its leaf's; a plant session has no leaf.
    SQLite::Statement ins(*impl_->db,
                          "INSERT INTO sessions(kind, plant_id, leaf_id, operator_id, station, mode, capture_order, "
                          "settings_json, created_utc, genesis_hash, head_hash, genesis_form) VALUES (CASE WHEN ?1 IS "
                          "NULL THEN 'plant' ELSE 'leaf' END, coalesce((SELECT plant_id FROM leaves WHERE id = ?1), "
                          "?8), ?1, ?2, ?3, ?4, ?5, ?6, ?7, '', '', 2)");
    if (leafId > 0)
      ins.bind(1, leafId);
    else
      ins.bind(1);
    ins.bind(2, operatorId);
    ins.bind(3, station);
    ins.bind(4, mode);
    ins.bind(5, order);
    ins.bind(6, settingsJson);
    ins.bind(7, created);
    if (plantId > 0)
      ins.bind(8, plantId);
    else
      ins.bind(8);
    ins.exec();
    const std::int64_t id = impl_->db->getLastInsertRowid();
    const std::string genesis = genesisHash(station, leafId > 0 ? "leaf" : "plant", id, created, settingsJson);
    SQLite::Statement up(*impl_->db, "UPDATE sessions SET genesis_hash=?1, head_hash=?1 WHERE id=?2");
    up.bind(1, genesis);
    up.bind(2, id);
    up.exec();
    tx.commit();
    return id;
  } catch (const SQLite::Exception& e) {
    rethrow(e, path_, "cannot create a session in");
  }
}

namespace {

struct Head {
  std::int64_t seq = 0;
  std::string hash;
};

Head headOf(SQLite::Database& db, std::int64_t session, const std::string& path) {
  SQLite::Statement head(db, "SELECT head_seq, head_hash FROM sessions WHERE id=?1");
  head.bind(1, session);
  if (!head.executeStep())
    throw StoreError(StoreErrorKind::Input, "no session " + std::to_string(session) + " in " + path,
                     "'leafdig sessions list' shows the sessions");
  return {head.getColumn(0).getInt64(), head.getColumn(1).getString()};
}

// One event row, what it changes in the projections, and the session's head, inside the
// caller's transaction.
void writeEvent(SQLite::Database& db, std::int64_t session, const Event& e, const EventInput& change) {
  SQLite::Statement ins(db,
                        "INSERT INTO events(session_id, seq, utc, mono_ns, kind, payload_json, raw, prev_hash, hash) "
                        "VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9)");
  ins.bind(1, session);
  ins.bind(2, e.seq);
  ins.bind(3, e.utc);
  ins.bind(4, e.monoNs);
  ins.bind(5, e.kind);
  ins.bind(6, e.payloadJson);
  ins.bind(7, e.raw);
  ins.bind(8, e.prevHash);
  ins.bind(9, e.hash);
  ins.exec();
  // Retracting first: a correction takes its item's old row out and puts the new one in.
  if (change.retracts) {
    for (const char* sql : {"DELETE FROM markers WHERE session_id=?1 AND seq=?2",
                            "DELETE FROM thickness_readings WHERE session_id=?1 AND seq=?2"}) {
      SQLite::Statement del(db, sql);
      del.bind(1, session);
      del.bind(2, *change.retracts);
      del.exec();
    }
  }
  if (change.projection) {
    const Projection& p = *change.projection;
    const bool marker = p.kind == Projection::Kind::Marker;
    SQLite::Statement pr(db, marker ? "INSERT INTO markers(session_id, seq, what, row, col, x_mm, y_mm, z_mm) "
                                      "VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8)"
                                    : "INSERT INTO thickness_readings(session_id, seq, what, row, col, value_mm, raw) "
                                      "VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7)");
    pr.bind(1, session);
    pr.bind(2, e.seq);
    pr.bind(3, p.what);
    if (p.row)
      pr.bind(4, *p.row);
    else
      pr.bind(4);
    if (p.col)
      pr.bind(5, *p.col);
    else
      pr.bind(5);
    if (marker) {
      pr.bind(6, p.positionMm[0]);
      pr.bind(7, p.positionMm[1]);
      pr.bind(8, p.positionMm[2]);
    } else {
      pr.bind(6, p.valueMm);
      pr.bind(7, p.raw);
    }
    pr.exec();
  }
  SQLite::Statement up(db, change.setsStatus ? "UPDATE sessions SET head_seq=?1, head_hash=?2, status=?4 WHERE id=?3"
                                             : "UPDATE sessions SET head_seq=?1, head_hash=?2 WHERE id=?3");
  up.bind(1, e.seq);
  up.bind(2, e.hash);
  up.bind(3, session);
  if (change.setsStatus) up.bind(4, *change.setsStatus);
  up.exec();
}

}  // namespace

std::int64_t Store::append(std::int64_t session, const EventInput& ev) {
  return appendAll(session, {ev});
}

std::int64_t Store::appendAll(std::int64_t session, const std::vector<EventInput>& events) {
  OperationClock clock(impl_->budget);
  try {
    SQLite::Transaction tx(*impl_->db, SQLite::TransactionBehavior::IMMEDIATE);
    Head head = headOf(*impl_->db, session, path_);
    if (!events.empty() && events.front().follows && *events.front().follows != head.seq)
      throw StoreError(StoreErrorKind::Conflict,
                       "session " + std::to_string(session) + " in " + path_ + " moved on to event " +
                           std::to_string(head.seq) + " while this change was worked out from event " +
                           std::to_string(*events.front().follows) + " (another correction at the same time?)",
                       "nothing was written; look at the session again (sessions show) and run the command again");
    for (const EventInput& ev : events) {
      Event e;
      e.session = session;
      e.seq = head.seq + 1;
      e.utc = utcNow();
      e.monoNs = ev.monoNs;
      e.kind = ev.kind;
      e.payloadJson = ev.payloadJson;
      e.raw = ev.raw;
      e.prevHash = head.hash;
      e.hash = eventHash(e.prevHash, session, e.seq, e.utc, e.monoNs, e.kind, e.payloadJson, e.raw);
      writeEvent(*impl_->db, session, e, ev);
      head = {e.seq, e.hash};
    }
    tx.commit();  // synchronous=FULL: durable when this returns
    return head.seq;
  } catch (const SQLite::Exception& e) {
    rethrow(e, path_, "cannot record an event in");
  }
}

void Store::import(std::int64_t session, const std::vector<Event>& events) {
  OperationClock clock(impl_->budget);
  try {
    SQLite::Transaction tx(*impl_->db, SQLite::TransactionBehavior::IMMEDIATE);
    Head head = headOf(*impl_->db, session, path_);
    for (const Event& e : events) {
      const auto conflict = [&](const std::string& why) {
        throw StoreError(
            StoreErrorKind::Conflict,
            "session " + std::to_string(session) + " in " + path_ + ", event " + std::to_string(e.seq) + ": " + why,
            "nothing was taken in; the station's copy and the other differ from this event on "
            "(docs/lab.md, \"Conflicts\")");
      };
      if (e.seq != head.seq + 1) conflict("it does not follow the station's last event " + std::to_string(head.seq));
      if (e.prevHash != head.hash)
        conflict("it follows another event " + std::to_string(head.seq) + " than the station's");
      if (eventHash(e.prevHash, session, e.seq, e.utc, e.monoNs, e.kind, e.payloadJson, e.raw) != e.hash)
        conflict("its content does not hash to its hash");
      writeEvent(*impl_->db, session, e, changeOf(e));
      head = {e.seq, e.hash};
    }
    tx.commit();
  } catch (const SQLite::Exception& e) {
    rethrow(e, path_, "cannot take in events into");
  }
}

std::vector<Event> Store::events(std::int64_t session, std::int64_t fromSeq) const {
  OperationClock clock(impl_->budget);
  std::vector<Event> out;
  try {
    SQLite::Statement q(*impl_->db,
                        "SELECT seq, utc, mono_ns, kind, payload_json, raw, prev_hash, hash FROM events "
                        "WHERE session_id=?1 AND seq>=?2 ORDER BY seq");
    q.bind(1, session);
    q.bind(2, fromSeq);
    while (q.executeStep()) {
      Event e;
      e.session = session;
      e.seq = q.getColumn(0).getInt64();
      e.utc = q.getColumn(1).getString();
      e.monoNs = q.getColumn(2).getInt64();
      e.kind = q.getColumn(3).getString();
      e.payloadJson = q.getColumn(4).getString();
      e.raw = q.getColumn(5).getString();
      e.prevHash = q.getColumn(6).getString();
      e.hash = q.getColumn(7).getString();
      out.push_back(std::move(e));
    }
  } catch (const SQLite::Exception& e) {
    rethrow(e, path_, "cannot read events from");
  }
  return out;
}

std::vector<MarkerRow> Store::markers(std::int64_t session) const {
  OperationClock clock(impl_->budget);
  std::vector<MarkerRow> out;
  try {
    SQLite::Statement q(*impl_->db,
                        "SELECT seq, what, row, col, x_mm, y_mm, z_mm FROM markers WHERE session_id=?1 ORDER BY seq");
    q.bind(1, session);
    while (q.executeStep()) {
      MarkerRow m;
      m.seq = q.getColumn(0).getInt64();
      m.what = q.getColumn(1).getString();
      if (!q.getColumn(2).isNull()) m.row = q.getColumn(2).getInt();
      if (!q.getColumn(3).isNull()) m.col = q.getColumn(3).getInt();
      m.positionMm = {q.getColumn(4).getDouble(), q.getColumn(5).getDouble(), q.getColumn(6).getDouble()};
      out.push_back(m);
    }
  } catch (const SQLite::Exception& e) {
    rethrow(e, path_, "cannot read markers from");
  }
  return out;
}

std::vector<ThicknessRow> Store::thickness(std::int64_t session) const {
  OperationClock clock(impl_->budget);
  std::vector<ThicknessRow> out;
  try {
    SQLite::Statement q(
        *impl_->db,
        "SELECT seq, what, row, col, value_mm, raw FROM thickness_readings WHERE session_id=?1 ORDER BY seq");
    q.bind(1, session);
    while (q.executeStep()) {
      ThicknessRow t;
      t.seq = q.getColumn(0).getInt64();
      t.what = q.getColumn(1).getString();
      if (!q.getColumn(2).isNull()) t.row = q.getColumn(2).getInt();
      if (!q.getColumn(3).isNull()) t.col = q.getColumn(3).getInt();
      t.valueMm = q.getColumn(4).getDouble();
      t.raw = q.getColumn(5).getString();
      out.push_back(t);
    }
  } catch (const SQLite::Exception& e) {
    rethrow(e, path_, "cannot read thickness readings from");
  }
  return out;
}

namespace {
// Plant sessions (schema 2) have no leaf: position 0, no type or area.
constexpr const char* kSessionSelect =
    "SELECT s.id, coalesce(s.leaf_id, 0), pr.name, pl.name, coalesce(l.position, 0), o.name, s.station, s.status, "
    "s.mode, s.capture_order, s.settings_json, s.created_utc, s.head_seq, s.head_hash, coalesce(l.type, ''), "
    "l.measured_area_mm2, s.kind, s.genesis_form FROM sessions s LEFT JOIN leaves l ON l.id = s.leaf_id "
    "JOIN plants pl ON pl.id = s.plant_id JOIN projects pr ON pr.id = pl.project_id JOIN operators o ON o.id = "
    "s.operator_id ";
// Schema 2, read as it is: every session's genesis is of form 1.
constexpr const char* kSessionSelect2 =
    "SELECT s.id, coalesce(s.leaf_id, 0), pr.name, pl.name, coalesce(l.position, 0), o.name, s.station, s.status, "
    "s.mode, s.capture_order, s.settings_json, s.created_utc, s.head_seq, s.head_hash, coalesce(l.type, ''), "
    "l.measured_area_mm2, s.kind, 1 FROM sessions s LEFT JOIN leaves l ON l.id = s.leaf_id "
    "JOIN plants pl ON pl.id = s.plant_id JOIN projects pr ON pr.id = pl.project_id JOIN operators o ON o.id = "
    "s.operator_id ";
// A file of schema 1 read as it is (a reader does not upgrade): every session is a leaf's.
constexpr const char* kSessionSelect1 =
    "SELECT s.id, s.leaf_id, pr.name, pl.name, l.position, o.name, s.station, s.status, s.mode, s.capture_order, "
    "s.settings_json, s.created_utc, s.head_seq, s.head_hash, l.type, l.measured_area_mm2, 'leaf', 1 FROM sessions s "
    "JOIN leaves l ON l.id = s.leaf_id "
    "JOIN plants pl ON pl.id = l.plant_id JOIN projects pr ON pr.id = pl.project_id JOIN operators o ON o.id = "
    "s.operator_id ";
SessionInfo readSession(SQLite::Statement& q) {
  SessionInfo s;
  s.id = q.getColumn(0).getInt64();
  s.stationSessionId = s.id;
  s.leafId = q.getColumn(1).getInt64();
  s.project = q.getColumn(2).getString();
  s.plant = q.getColumn(3).getString();
  s.leafPosition = q.getColumn(4).getInt();
  s.operatorName = q.getColumn(5).getString();
  s.station = q.getColumn(6).getString();
  s.status = q.getColumn(7).getString();
  s.mode = q.getColumn(8).getString();
  s.order = q.getColumn(9).getString();
  s.settingsJson = q.getColumn(10).getString();
  s.createdUtc = q.getColumn(11).getString();
  s.headSeq = q.getColumn(12).getInt64();
  s.headHash = q.getColumn(13).getString();
  s.leafType = q.getColumn(14).getString();
  if (!q.getColumn(15).isNull()) s.measuredAreaMm2 = q.getColumn(15).getDouble();
  s.kind = q.getColumn(16).getString();
  s.genesisForm = q.getColumn(17).getInt();
  return s;
}
const char* sessionSelect(int version) {
  return version >= 3 ? kSessionSelect : version == 2 ? kSessionSelect2 : kSessionSelect1;
}
}  // namespace

std::optional<SessionInfo> Store::session(std::int64_t id) const {
  OperationClock clock(impl_->budget);
  try {
    SQLite::Statement q(*impl_->db, std::string(sessionSelect(impl_->version)) + "WHERE s.id=?1");
    q.bind(1, id);
    if (q.executeStep()) return readSession(q);
  } catch (const SQLite::Exception& e) {
    rethrow(e, path_, "cannot read sessions from");
  }
  return std::nullopt;
}

std::vector<SessionInfo> Store::sessions() const {
  OperationClock clock(impl_->budget);
  std::vector<SessionInfo> out;
  try {
    SQLite::Statement q(*impl_->db, std::string(sessionSelect(impl_->version)) + "ORDER BY s.id");
    while (q.executeStep()) out.push_back(readSession(q));
  } catch (const SQLite::Exception& e) {
    rethrow(e, path_, "cannot read sessions from");
  }
  return out;
}

ChainReport Store::verify(std::int64_t session) const {
  OperationClock clock(impl_->budget);
  std::string genesis;
  std::int64_t headSeq = 0;
  std::string headHash, status;
  // One snapshot for the row, the events and the tables: another process committing between
  // two of these reads (a curator's correction at the same time) is not a changed file.
  std::optional<SQLite::Transaction> snapshot;
  try {
    snapshot.emplace(*impl_->db);
    SQLite::Statement q(*impl_->db, "SELECT genesis_hash, head_seq, head_hash, status FROM sessions WHERE id=?1");
    q.bind(1, session);
    if (!q.executeStep()) {
      ChainReport r;
      r.ok = false;
      r.problem = "no session " + std::to_string(session);
      return r;
    }
    genesis = q.getColumn(0).getString();
    headSeq = q.getColumn(1).getInt64();
    headHash = q.getColumn(2).getString();
    status = q.getColumn(3).getString();
  } catch (const SQLite::Exception& e) {
    rethrow(e, path_, "cannot verify");
  }
  const std::vector<Event> log = events(session);
  ChainReport r = verifyChain(session, genesis, headSeq, headHash, log);
  if (!r.ok) return r;
  // The genesis must be what the session's row says it was made of: its station, kind,
  // creation time and settings (form 2), or the last two (form 1, written before schema 3).
  if (const auto info = this->session(session)) {
    r.genesisForm = info->genesisForm;
    if (genesisOf(*info) != genesis) {
      r.ok = false;
      r.firstBadSeq = 0;
      r.problem = std::string("its ") + (info->genesisForm >= 2 ? "station, kind, " : "") +
                  "creation time or settings were changed after it was written (its genesis hash differs)";
      return r;
    }
  }
  // The tables read by other tools (and by the CSV export) must be what the events say.
  if (const auto problem = projectionProblem(log, markers(session), thickness(session), status)) {
    r.ok = false;
    r.firstBadSeq = problem->seq;
    r.problem = problem->text;
  }
  return r;
}

std::int64_t Store::recordExport(std::int64_t session, const std::string& path, const std::string& format) {
  try {
    SQLite::Statement ins(*impl_->db, "INSERT INTO exports(session_id, path, format, utc) VALUES (?1, ?2, ?3, ?4)");
    ins.bind(1, session);
    ins.bind(2, path);
    ins.bind(3, format);
    ins.bind(4, utcNow());
    ins.exec();
    return impl_->db->getLastInsertRowid();
  } catch (const SQLite::Exception& e) {
    rethrow(e, path_, "cannot record an export in");
  }
}

void Store::setMaxPages(std::int64_t pages) {
  impl_->db->exec("PRAGMA max_page_count=" + std::to_string(pages > 0 ? pages : 4294967294LL));
}

std::int64_t Store::pageCount() const {
  return impl_->db->execAndGet("PRAGMA page_count").getInt64();
}

}  // namespace leafdig::db
