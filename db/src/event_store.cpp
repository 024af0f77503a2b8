// The hash chain's rules and what each event kind changes (docs/schema.md), shared by the
// station's SQLite file and the lab server.
#include "leafdig/db/event_store.hpp"

#include <openssl/evp.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <map>
#include <nlohmann/json.hpp>

#include "leafdig/db/event_rules.hpp"

namespace leafdig::db {

std::string sha256Hex(const std::string& data) {
  unsigned char md[EVP_MAX_MD_SIZE];
  unsigned int n = 0;
  EVP_Digest(data.data(), data.size(), md, &n, EVP_sha256(), nullptr);
  static const char* hex = "0123456789abcdef";
  std::string out;
  for (unsigned int i = 0; i < n; ++i) {
    out += hex[md[i] >> 4];
    out += hex[md[i] & 15];
  }
  return out;
}

std::string eventHash(const std::string& prev, std::int64_t session, std::int64_t seq, const std::string& utc,
                      std::int64_t mono, const std::string& kind, const std::string& payload, const std::string& raw) {
  std::string s = prev;
  s += '\n' + std::to_string(session) + '\n' + std::to_string(seq) + '\n' + utc + '\n' + std::to_string(mono) + '\n' +
       kind + '\n' + std::to_string(payload.size()) + ':' + payload + '\n' + std::to_string(raw.size()) + ':' + raw;
  return sha256Hex(s);
}

std::string genesisHash(std::int64_t stationSessionId, const std::string& createdUtc, const std::string& settingsJson) {
  return sha256Hex("leafdig session " + std::to_string(stationSessionId) + " " + createdUtc + " " + settingsJson);
}

std::string genesisHash(const std::string& station, const std::string& kind, std::int64_t stationSessionId,
                        const std::string& createdUtc, const std::string& settingsJson) {
  // Each field with its length: no station or kind text can be made to read as another split.
  const auto field = [](const std::string& v) { return std::to_string(v.size()) + ":" + v + "\n"; };
  return sha256Hex("leafdig session/2\n" + field(station) + field(kind) + field(std::to_string(stationSessionId)) +
                   field(createdUtc) + field(settingsJson));
}

std::string genesisOf(const SessionInfo& s) {
  const std::int64_t id = s.stationSessionId > 0 ? s.stationSessionId : s.id;
  return s.genesisForm >= 2 ? genesisHash(s.station, s.kind, id, s.createdUtc, s.settingsJson)
                            : genesisHash(id, s.createdUtc, s.settingsJson);
}

ChainReport verifyChain(std::int64_t stationSessionId, const std::string& genesis, std::int64_t headSeq,
                        const std::string& headHash, const std::vector<Event>& events) {
  ChainReport r;
  std::string prev = genesis;
  std::int64_t expected = 1;
  for (const Event& e : events) {
    ++r.events;
    const auto fail = [&](const std::string& why) {
      r.ok = false;
      r.firstBadSeq = e.seq;
      r.problem = why;
    };
    if (e.seq != expected)
      fail("event " + std::to_string(expected) + " is missing");
    else if (e.prevHash != prev)
      fail("event " + std::to_string(e.seq) + " does not follow the previous one");
    else if (eventHash(prev, stationSessionId, e.seq, e.utc, e.monoNs, e.kind, e.payloadJson, e.raw) != e.hash)
      fail("event " + std::to_string(e.seq) + " was changed after it was written");
    if (!r.ok) return r;
    prev = e.hash;
    ++expected;
  }
  if (expected - 1 != headSeq || prev != headHash) {
    r.ok = false;
    r.firstBadSeq = expected;
    r.problem = "the log ends at event " + std::to_string(expected - 1) + " but the session recorded " +
                std::to_string(headSeq) + " events: events were removed";
  }
  return r;
}

namespace {
std::atomic<bool> gInterrupt{false};
static_assert(std::atomic<bool>::is_always_lock_free, "requestInterrupt is called from signal handlers");
}  // namespace

void requestInterrupt() noexcept {
  gInterrupt.store(true, std::memory_order_relaxed);
}
void clearInterrupt() noexcept {
  gInterrupt.store(false, std::memory_order_relaxed);
}
bool interruptRequested() noexcept {
  return gInterrupt.load(std::memory_order_relaxed);
}

std::string utcNow() {
  const auto now = std::chrono::system_clock::now();
  const std::time_t t = std::chrono::system_clock::to_time_t(now);
  const auto ms = std::chrono::duration_cast<std::chrono::milliseconds>(now.time_since_epoch()).count() % 1000;
  std::tm tm{};
  ::gmtime_r(&t, &tm);
  char buf[96];
  std::snprintf(buf, sizeof buf, "%04d-%02d-%02dT%02d:%02d:%02d.%03lldZ", tm.tm_year + 1900, tm.tm_mon + 1, tm.tm_mday,
                tm.tm_hour, tm.tm_min, tm.tm_sec, static_cast<long long>(ms));
  return buf;
}

void checkStationId(const std::string& id) {
  const auto refuse = [&](const std::string& why) {
    throw StoreError(StoreErrorKind::Input, "the station id '" + id + "' " + why,
                     "name the station with --station (or [station] id= in the settings file): 1 to 64 letters, "
                     "digits, '.', '_' or '-', starting with a letter or digit");
  };
  if (id.empty()) refuse("is empty");
  if (id.size() > 64) refuse("is longer than 64 characters");
  if (std::isalnum(static_cast<unsigned char>(id[0])) == 0) refuse("does not start with a letter or digit");
  for (const char c : id)
    if (std::isalnum(static_cast<unsigned char>(c)) == 0 && c != '.' && c != '_' && c != '-')
      refuse(std::string("holds '") + c + "'");
}

std::optional<std::size_t> badTextByte(const std::string& s) {
  std::size_t i = 0;
  while (i < s.size()) {
    const auto c = static_cast<unsigned char>(s[i]);
    if (c == 0) return i;
    std::size_t n = 0;
    std::uint32_t cp = 0;
    if (c < 0x80) {
      ++i;
      continue;
    }
    if ((c & 0xE0) == 0xC0) {
      n = 1;
      cp = c & 0x1F;
    } else if ((c & 0xF0) == 0xE0) {
      n = 2;
      cp = c & 0x0F;
    } else if ((c & 0xF8) == 0xF0) {
      n = 3;
      cp = c & 0x07;
    } else {
      return i;
    }
    for (std::size_t k = 1; k <= n; ++k) {
      if (i + k >= s.size()) return i;
      const auto d = static_cast<unsigned char>(s[i + k]);
      if ((d & 0xC0) != 0x80) return i;
      cp = (cp << 6) | (d & 0x3F);
    }
    // Overlong forms, surrogates and code points past U+10FFFF are not UTF-8.
    if ((n == 1 && cp < 0x80) || (n == 2 && cp < 0x800) || (n == 3 && cp < 0x10000) || cp > 0x10FFFF ||
        (cp >= 0xD800 && cp <= 0xDFFF))
      return i;
    i += n + 1;
  }
  return std::nullopt;
}

std::string EventStore::signature(const std::string& who) const {
  const auto writer = login();
  if (!writer) return who;
  const bool blank = std::all_of(who.begin(), who.end(), [](unsigned char c) { return std::isspace(c) != 0; });
  const std::string tail = " (" + *writer + ")";
  if (blank || who == *writer) return *writer;
  if (who.size() > tail.size() && who.compare(who.size() - tail.size(), tail.size(), tail) == 0) return who;
  return who + tail;
}

std::int64_t EventStore::setStatus(std::int64_t session, const std::string& status, const std::string& who,
                                   const std::string& why) {
  if (std::find(kSessionStatuses.begin(), kSessionStatuses.end(), status) == kSessionStatuses.end())
    throw StoreError(StoreErrorKind::Input, "unknown session status '" + status + "'",
                     "use open, complete, approved, rejected or abandoned");
  EventInput ev;
  ev.kind = "status";
  ev.payloadJson = nlohmann::json{{"status", status}, {"who", signature(who)}, {"why", why}}.dump();
  ev.setsStatus = status;  // the event and the session's status change together
  return append(session, ev);
}

namespace {

using nlohmann::json;

[[noreturn]] void unreadable(const Event& e, const std::string& why) {
  throw StoreError(StoreErrorKind::Input,
                   "event " + std::to_string(e.seq) + " (" + e.kind + ") of session " + std::to_string(e.session) +
                       " cannot be read: " + why,
                   "the event is kept as it is; report it with the session's export (docs/schema.md lists the "
                   "payload of each kind)");
}

std::optional<int> optionalIndex(const json& j, const char* key) {
  if (!j.contains(key) || j.at(key).is_null()) return std::nullopt;
  return j.at(key).get<int>();
}

// An item of an `accepted`-like payload as a projection row.
Projection projectionOfItem(const json& item, const std::string& raw) {
  Projection p;
  p.what = item.at("what").get<std::string>();
  p.row = optionalIndex(item, "row");
  p.col = optionalIndex(item, "col");
  if (item.contains("position_mm")) {
    p.kind = Projection::Kind::Marker;
    for (std::size_t k = 0; k < 3; ++k) p.positionMm[k] = item.at("position_mm").at(k).get<double>();
  } else {
    p.kind = Projection::Kind::Thickness;
    p.valueMm = item.at("value_mm").get<double>();
    p.raw = raw;
  }
  return p;
}

}  // namespace

EventInput changeOf(const Event& e) {
  EventInput in;
  in.kind = e.kind;
  in.payloadJson = e.payloadJson;
  in.raw = e.raw;
  in.monoNs = e.monoNs;
  if (const auto problem = eventProblem(e.kind, e.payloadJson, e.raw)) unreadable(e, *problem);
  const bool carriesItem = e.kind == "accepted" || e.kind == "retake_cancelled";
  const bool retracts = e.kind == "undone" || e.kind == "retake";
  if (!carriesItem && !retracts && e.kind != "corrected" && e.kind != "status") return in;
  try {
    const json p = json::parse(e.payloadJson);
    if (carriesItem) in.projection = projectionOfItem(p, e.raw);
    if (retracts) in.retracts = p.at("seq").get<std::int64_t>();
    if (e.kind == "corrected") {
      in.retracts = p.at("seq").get<std::int64_t>();
      in.projection = projectionOfItem(p.at("corrected"), e.raw);
    }
    if (e.kind == "status") in.setsStatus = p.at("status").get<std::string>();
  } catch (const json::exception& x) {
    unreadable(e, x.what());
  }
  return in;
}

Projected project(const std::vector<Event>& events) {
  std::map<std::int64_t, MarkerRow> markers;
  std::map<std::int64_t, ThicknessRow> thickness;
  Projected out;
  for (const Event& e : events) {
    const EventInput c = changeOf(e);
    if (c.retracts) {
      markers.erase(*c.retracts);
      thickness.erase(*c.retracts);
    }
    if (c.projection) {
      const Projection& p = *c.projection;
      if (p.kind == Projection::Kind::Marker)
        markers[e.seq] = MarkerRow{e.seq, p.what, p.row, p.col, p.positionMm};
      else
        thickness[e.seq] = ThicknessRow{e.seq, p.what, p.row, p.col, p.valueMm, p.raw};
    }
    if (c.setsStatus) out.status = c.setsStatus;
  }
  for (auto& [seq, m] : markers) out.markers.push_back(std::move(m));
  for (auto& [seq, t] : thickness) out.thickness.push_back(std::move(t));
  return out;
}

namespace {

std::string itemName(const std::string& what, const std::optional<int>& row, const std::optional<int>& col) {
  std::string out = what;
  if (row) out += " row " + std::to_string(*row);
  if (col) out += " col " + std::to_string(*col);
  return out;
}

std::string millimetres(const std::array<double, 3>& p) {
  char buf[128];
  std::snprintf(buf, sizeof buf, "(%.3f, %.3f, %.3f) mm", p[0], p[1], p[2]);
  return buf;
}

std::string millimetres(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.4f mm", v);
  return buf;
}

constexpr const char* kEdited = " - the file was changed after leafdig wrote it";

// The first difference between the rows a table holds and the rows its events give, by seq.
template <typename Row, typename Describe, typename Same>
std::optional<ProjectionMismatch> compareRows(const char* table, const std::vector<Row>& stored,
                                              const std::vector<Row>& fromEvents, Describe describe, Same same) {
  std::map<std::int64_t, const Row*> a, b;
  for (const Row& r : stored) a[r.seq] = &r;
  for (const Row& r : fromEvents) b[r.seq] = &r;
  for (const auto& [seq, row] : b) {
    const auto at = a.find(seq);
    if (at == a.end())
      return ProjectionMismatch{seq, std::string("the ") + table + " table lacks " +
                                         itemName(row->what, row->row, row->col) + " of event " + std::to_string(seq) +
                                         kEdited};
    if (!same(*at->second, *row))
      return ProjectionMismatch{seq, std::string("the ") + table + " table has " +
                                         itemName(at->second->what, at->second->row, at->second->col) + " of event " +
                                         std::to_string(seq) + " as " + describe(*at->second) +
                                         ", but its event says " + itemName(row->what, row->row, row->col) + " " +
                                         describe(*row) + kEdited};
  }
  for (const auto& [seq, row] : a)
    if (b.find(seq) == b.end())
      return ProjectionMismatch{seq, std::string("the ") + table + " table holds " +
                                         itemName(row->what, row->row, row->col) + " for event " + std::to_string(seq) +
                                         ", which puts no such item in" + kEdited};
  return std::nullopt;
}

}  // namespace

std::optional<ProjectionMismatch> projectionProblem(const std::vector<Event>& events,
                                                    const std::vector<MarkerRow>& markers,
                                                    const std::vector<ThicknessRow>& thickness,
                                                    const std::string& status) {
  Projected p;
  try {
    p = project(events);
  } catch (const StoreError& e) {
    return ProjectionMismatch{0, e.what()};
  }
  if (auto m = compareRows(
          "markers", markers, p.markers, [](const MarkerRow& r) { return millimetres(r.positionMm); },
          [](const MarkerRow& x, const MarkerRow& y) {
            return x.what == y.what && x.row == y.row && x.col == y.col && x.positionMm == y.positionMm;
          }))
    return m;
  if (auto t = compareRows(
          "thickness_readings", thickness, p.thickness, [](const ThicknessRow& r) { return millimetres(r.valueMm); },
          [](const ThicknessRow& x, const ThicknessRow& y) {
            return x.what == y.what && x.row == y.row && x.col == y.col && x.valueMm == y.valueMm && x.raw == y.raw;
          }))
    return t;
  const std::string expected = p.status.value_or("open");
  if (status != expected) {
    std::int64_t seq = 0;
    for (const Event& e : events)
      if (e.kind == "status") seq = e.seq;
    return ProjectionMismatch{
        seq, "the session's status is '" + status + "' but its events say '" + expected + "'" + kEdited};
  }
  return std::nullopt;
}

}  // namespace leafdig::db
