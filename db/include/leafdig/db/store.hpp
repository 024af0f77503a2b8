// The SQLite store: one file per station, an append-only hash-chained event log per
// session, projections (markers, thickness readings) kept in the same transactions, and
// the entities of SPEC §4. Plain data types at the boundary; no other leafdig module.
//
// Thread contract: a Store is one SQLite connection, used by one thread at a time. Several
// Stores (threads or processes) may open the same file: WAL lets readers and one writer
// proceed without blocking each other.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace leafdig::db {

inline constexpr int kSchemaVersion = 1;
inline constexpr std::int32_t kApplicationId = 0x4C454146;  // "LEAF"

enum class StoreErrorKind { NotLeafdig, TooNew, Corrupt, DiskFull, Busy, Io, Input };

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
  std::optional<int> row, col;         // 1-based as in SPEC §1; absent for the tip / d
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
};

struct Event {
  std::int64_t session = 0, seq = 0;
  std::string utc;
  std::int64_t monoNs = 0;
  std::string kind, payloadJson, raw, prevHash, hash;
};

struct SessionInfo {
  std::int64_t id = 0, leafId = 0;
  std::string project, plant;
  int leafPosition = 0;
  std::string operatorName, station, status, mode, order, settingsJson, createdUtc;
  std::int64_t headSeq = 0;
  std::string headHash;
  std::string leafType;                   // "" when not given
  std::optional<double> measuredAreaMm2;  // leaf area meter or image, when entered
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
};

class Store {
 public:
  // Opens (creating when missing) and migrates. A file that is not a leafdig database, is
  // corrupt, or was written by a newer leafdig is refused with StoreError and not modified.
  // A writer checks the pages capture touches (the small tables, the right edge of the
  // event log); checkPages() checks them all.
  explicit Store(const std::string& path, bool readOnly = false);
  Store(const Store&) = delete;
  Store& operator=(const Store&) = delete;
  ~Store();

  // $XDG_DATA_HOME/leafdig/station.sqlite (or ~/.local/share/leafdig/station.sqlite).
  [[nodiscard]] static std::string defaultPath();
  [[nodiscard]] const std::string& path() const { return path_; }
  [[nodiscard]] int schemaVersion() const;

  std::int64_t ensureOperator(const std::string& name, const std::string& role = "technician");
  std::int64_t ensureProject(const std::string& name);
  std::int64_t ensurePlant(std::int64_t projectId, const std::string& name);
  // A type or area given for an existing leaf replaces the stored one.
  std::int64_t ensureLeaf(std::int64_t plantId, int position, const std::string& type = {},
                          std::optional<double> measuredAreaMm2 = {});
  std::int64_t ensureDevice(const std::string& kind, const std::string& port, const std::string& description = {});
  std::int64_t createSession(std::int64_t leafId, std::int64_t operatorId, const std::string& station,
                             const std::string& mode, const std::string& order, const std::string& settingsJson);

  // Appends one event (and its projection change) in one transaction; returns its seq once
  // it is durable. Throws StoreError (DiskFull, Busy, Io): nothing was written then.
  std::int64_t append(std::int64_t session, const EventInput& event);
  // Status change (open, complete, approved, rejected) as an event plus the session row.
  std::int64_t setStatus(std::int64_t session, const std::string& status, const std::string& who,
                         const std::string& why);

  [[nodiscard]] std::vector<Event> events(std::int64_t session, std::int64_t fromSeq = 1) const;
  [[nodiscard]] std::vector<MarkerRow> markers(std::int64_t session) const;
  [[nodiscard]] std::vector<ThicknessRow> thickness(std::int64_t session) const;
  [[nodiscard]] std::optional<SessionInfo> session(std::int64_t id) const;
  [[nodiscard]] std::vector<SessionInfo> sessions() const;
  // Recomputes the chain: any edited, reordered, inserted or missing event is found.
  [[nodiscard]] ChainReport verify(std::int64_t session) const;
  // Checks every page of the file (SQLite's quick_check): "ok", or what is damaged. Opening
  // for writing checks only what capture touches; this is the full check.
  [[nodiscard]] std::string checkPages() const;
  std::int64_t recordExport(std::int64_t session, const std::string& path, const std::string& format);
  // Caps the file at `pages` database pages (a quota; SQLite reports "full" beyond it, as
  // for a full disk). 0 restores SQLite's default.
  void setMaxPages(std::int64_t pages);
  [[nodiscard]] std::int64_t pageCount() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  std::string path_;
};

// SHA-256 of `data` as 64 lower-case hex digits (OpenSSL).
[[nodiscard]] std::string sha256Hex(const std::string& data);

}  // namespace leafdig::db
