// What reviewing, exporting and syncing need of a store of capture sessions, wherever it
// lives: the station's SQLite file (db::Store, store.hpp) or the lab's PostgreSQL server
// (db::LabStore, lab.hpp). Plain data types at the boundary; the hash chain's rules
// (docs/schema.md) in one place for both.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace leafdig::db {

// Refused: the server (or a station login) may not do this; Conflict: the station's copy of
// a session and the server's differ (docs/lab.md); Tampered: a station file holds what
// leafdig never writes (an extra trigger or view, a changed table, a projection that is not
// its events'); Interrupted: a signal stopped a statement (requestInterrupt).
enum class StoreErrorKind {
  NotLeafdig,
  TooNew,
  Corrupt,
  DiskFull,
  Busy,
  Io,
  Input,
  Refused,
  Conflict,
  Unreachable,
  Tampered,
  Interrupted
};

class StoreError : public std::runtime_error {
 public:
  StoreError(StoreErrorKind kind, const std::string& what, std::string remedy)
      : std::runtime_error(what), kind_(kind), remedy_(std::move(remedy)) {}
  [[nodiscard]] StoreErrorKind kind() const noexcept { return kind_; }
  [[nodiscard]] const std::string& remedy() const noexcept { return remedy_; }

 private:
  StoreErrorKind kind_;
  std::string remedy_;
};

// What an event changes in the projections (applied in the event's own transaction).
struct Projection {
  enum class Kind { Marker, Thickness };
  Kind kind = Kind::Marker;
  std::optional<int> row, col;         // 1-based as in docs/method.md §1; absent for the tip / d
  std::string what;                    // "tip", "marker", "midrib_thickness", …
  std::array<double, 3> positionMm{};  // markers
  double valueMm = 0;                  // thickness readings
  std::string raw;                     // device text it came from
};

struct EventInput {
  std::string kind;  // "accepted", "rejected", "undone", "prompt", "status", …
  std::string payloadJson = "{}";
  std::string raw;          // raw device bytes/lines (printable form)
  std::int64_t monoNs = 0;  // monotonic capture time
  std::optional<Projection> projection;
  std::optional<std::int64_t> retracts;   // seq whose projection rows this event removes (undo)
  std::optional<std::string> setsStatus;  // the session's new status, in the same transaction
  // The session's last event when this one was worked out (a curator's correction replays the
  // session first): written only if the session still ends there, else StoreError(Conflict)
  // and nothing is written — two corrections at once never both land on one item.
  std::optional<std::int64_t> follows;
};

struct Event {
  std::int64_t session = 0, seq = 0;
  std::string utc;
  std::int64_t monoNs = 0;
  std::string kind, payloadJson, raw, prevHash, hash;
};

// A session's statuses: what the schemas' CHECK holds (released migrations keep their own SQL),
// what setStatus takes and what `sessions list --status` offers.
inline constexpr std::array<const char*, 5> kSessionStatuses{"open", "complete", "approved", "rejected", "abandoned"};

struct SessionInfo {
  std::int64_t id = 0, leafId = 0;
  // The session's id at the station that captured it: the same as `id` in a station's file;
  // on the lab server `id` is the server's and this is the one the hash chain names.
  std::int64_t stationSessionId = 0;
  std::string project, plant;
  int leafPosition = 0;
  std::string operatorName, station, status, mode, order, settingsJson, createdUtc;
  std::int64_t headSeq = 0;
  std::string headHash;
  std::string leafType;                   // "" when not given
  std::string kind = "leaf";              // "leaf", or "plant": a whole plant (no leaf; position 0)
  std::optional<double> measuredAreaMm2;  // leaf area meter or image, when entered
  // What its genesis hash covers: 2, its station and kind besides its id, creation time and
  // settings (sessions written since station schema 3 / lab schema 10); 1, the latter only.
  int genesisForm = 1;
};

struct MarkerRow {
  std::int64_t seq = 0;
  std::string what;
  std::optional<int> row, col;
  std::array<double, 3> positionMm{};
};
struct ThicknessRow {
  std::int64_t seq = 0;
  std::string what;
  std::optional<int> row, col;
  double valueMm = 0;
  std::string raw;
};

struct ChainReport {
  bool ok = true;
  std::int64_t events = 0;
  std::optional<std::int64_t> firstBadSeq;
  std::string problem;  // empty when ok
  int genesisForm = 2;  // 1: a session written before its station was in its chain (SessionInfo)
};

// A store of sessions: reading, the chain check, and the events a curator adds (status,
// corrections) and exports. Capture itself always writes the station's file (db::Store).
//
// Thread contract: one thread at a time per object.
class EventStore {
 public:
  EventStore() = default;
  EventStore(const EventStore&) = delete;
  EventStore& operator=(const EventStore&) = delete;
  virtual ~EventStore() = default;

  // The file's path, or the server's URL without its password: for messages.
  [[nodiscard]] virtual std::string describe() const = 0;
  [[nodiscard]] virtual std::vector<SessionInfo> sessions() const = 0;
  [[nodiscard]] virtual std::optional<SessionInfo> session(std::int64_t id) const = 0;
  [[nodiscard]] virtual std::vector<Event> events(std::int64_t session, std::int64_t fromSeq = 1) const = 0;
  [[nodiscard]] virtual std::vector<MarkerRow> markers(std::int64_t session) const = 0;
  [[nodiscard]] virtual std::vector<ThicknessRow> thickness(std::int64_t session) const = 0;
  // Recomputes the chain: any edited, reordered, inserted or missing event is found.
  [[nodiscard]] virtual ChainReport verify(std::int64_t session) const = 0;
  // Appends one event (and what it changes) atomically; returns its seq once durable.
  virtual std::int64_t append(std::int64_t session, const EventInput& event) = 0;
  // Appends several events one after the other, all or none (a correction that moves other
  // points with it); returns the last one's seq. Nothing is written when `events` is empty.
  virtual std::int64_t appendAll(std::int64_t session, const std::vector<EventInput>& events) = 0;
  // Status change (open, complete, approved, rejected, abandoned) as a `status` event.
  std::int64_t setStatus(std::int64_t session, const std::string& status, const std::string& who,
                         const std::string& why);
  // A person who signs events (a curator's corrections); 0 where the store keeps none.
  virtual std::int64_t ensureOperator(const std::string& name, const std::string& role) = 0;
  // A file written from a session; 0 when this store does not record it (a read-only login).
  virtual std::int64_t recordExport(std::int64_t session, const std::string& path, const std::string& format) = 0;
  // The login this store writes as (the lab server's session user), or nothing (a station's
  // file has no logins). A review written through a login is signed by it (lab schema 10).
  [[nodiscard]] virtual std::optional<std::string> login() const { return std::nullopt; }
  // The name a review written through this store carries (lab schema 11): in a station's file,
  // `who` as given; through a login, the login itself or "NAME (login)" — `who` blank or the
  // login gives the login, another name gets the login added — so whoever reads the decision,
  // on the server or in a station's file after a pull, sees the login that wrote it.
  [[nodiscard]] std::string signature(const std::string& who) const;
};

// SHA-256 of `data` as 64 lower-case hex digits (OpenSSL).
[[nodiscard]] std::string sha256Hex(const std::string& data);
// The chain of docs/schema.md: the hash of event `seq` of the session numbered
// `stationSessionId` at its station, and the session's genesis hash.
[[nodiscard]] std::string eventHash(const std::string& prevHash, std::int64_t stationSessionId, std::int64_t seq,
                                    const std::string& utc, std::int64_t monoNs, const std::string& kind,
                                    const std::string& payload, const std::string& raw);
[[nodiscard]] std::string genesisHash(std::int64_t stationSessionId, const std::string& createdUtc,
                                      const std::string& settingsJson);
// Form 2 (docs/schema.md): the station and the session's kind are in it too.
[[nodiscard]] std::string genesisHash(const std::string& station, const std::string& kind,
                                      std::int64_t stationSessionId, const std::string& createdUtc,
                                      const std::string& settingsJson);
// A session's genesis as its form says (SessionInfo::genesisForm).
[[nodiscard]] std::string genesisOf(const SessionInfo& session);
// Checks `events` (1, 2, … in order) against the genesis and the recorded head.
[[nodiscard]] ChainReport verifyChain(std::int64_t stationSessionId, const std::string& genesis, std::int64_t headSeq,
                                      const std::string& headHash, const std::vector<Event>& events);
// Station ids go to the server: 1–64 of letters, digits, '.', '_' and '-', starting with a
// letter or digit (a host name fits). Throws StoreError(Input) saying what is wrong.
void checkStationId(const std::string& id);
// Text the server stores must be UTF-8 without NUL bytes; the first offending byte, or none.
[[nodiscard]] std::optional<std::size_t> badTextByte(const std::string& text);
// Stops every SQLite statement of this process that is running or starts later with
// StoreError(Interrupted); async-signal-safe (a signal handler calls it). clearInterrupt()
// lets statements run again.
void requestInterrupt() noexcept;
void clearInterrupt() noexcept;
[[nodiscard]] bool interruptRequested() noexcept;
// UTC now as stored: 2026-11-21T11:07:55.041Z.
[[nodiscard]] std::string utcNow();

// What a stored event changes in the projections, read back from its kind and payload
// (docs/schema.md, "Event kinds"): accepted and retake_cancelled insert their item,
// undone and retake retract the event they name, corrected does both, status sets the
// session's status. Used to take in events from the lab server and to show a server
// session's markers and readings. Throws StoreError(Input) naming the event when its
// payload does not say what its kind needs.
[[nodiscard]] EventInput changeOf(const Event& event);
struct Projected {
  std::vector<MarkerRow> markers;       // by seq, as Store::markers
  std::vector<ThicknessRow> thickness;  // by seq, as Store::thickness
  std::optional<std::string> status;    // the last status event's, if any
};
[[nodiscard]] Projected project(const std::vector<Event>& events);
// Where a store's projection tables (and its session's status) differ from what its verified
// events say — an edit by another program — naming the item and its event; nothing when they
// agree.
struct ProjectionMismatch {
  std::int64_t seq = 0;
  std::string text;
};
[[nodiscard]] std::optional<ProjectionMismatch> projectionProblem(const std::vector<Event>& events,
                                                                  const std::vector<MarkerRow>& markers,
                                                                  const std::vector<ThicknessRow>& thickness,
                                                                  const std::string& status);

}  // namespace leafdig::db
