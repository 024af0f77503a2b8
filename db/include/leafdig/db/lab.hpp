// The lab's shared store: a PostgreSQL server that every station pushes its sessions to and
// curators review on (docs/lab.md; its schema, roles and policies: docs/server-schema.md).
// Stations keep capturing offline into their own SQLite files; `push` sends what the server
// lacks, `pull` brings the curators' decisions back. libpq underneath (db/src/pg.hpp).
//
// Thread contract: a LabStore is one connection, used by one thread at a time; push and
// pull open their own.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "leafdig/db/event_store.hpp"
#include "leafdig/db/server_url.hpp"
#include "leafdig/db/store.hpp"
#include "leafdig/names/name_table.hpp"

namespace leafdig::db {

namespace pg {
class Connection;
}

// Creates the schema (or migrates it to this leafdig's version) and the three group roles
// leafdig_technicians, leafdig_curators and leafdig_readers. Run by the lab's administrator
// (a superuser, or a role with CREATEROLE that owns the database). Idempotent.
struct ServerInit {
  int fromVersion = 0, toVersion = 0;
  std::vector<std::string> rolesCreated;
  // What init could not do itself and the database's owner should (docs/lab.md, "Limits").
  std::vector<std::string> notes;
};
// Each login added by add-user: at most this many connections at once, a transaction left idle
// ended after a minute, a statement stopped after five (docs/lab.md, "Limits").
inline constexpr int kLoginConnectionLimit = 8;
inline constexpr const char* kIdleInTransactionTimeout = "60s";
inline constexpr const char* kStatementTimeout = "300s";
ServerInit initServer(const std::string& url, double lockWaitSeconds = 30);
inline constexpr int kLabSchemaVersion = 12;

enum class LabRole { Technician, Curator, Reader };
// Its words in files, options and messages (the CLI's choices and the station's lists too).
inline constexpr NameTable<LabRole, 3> kLabRoleNames{
    {{LabRole::Technician, "technician"}, {LabRole::Curator, "curator"}, {LabRole::Reader, "reader"}}};

[[nodiscard]] const char* toString(LabRole role);
[[nodiscard]] LabRole labRoleFromString(const std::string& text);  // throws UnknownName
// Puts a login in its group; a technician is bound to exactly one station. An existing
// login keeps its password unless one is given; a new login needs one. Throws StoreError.
struct AddedUser {
  bool created = false;
  std::string login;
  LabRole role = LabRole::Reader;
  std::string station;
};
AddedUser addUser(const std::string& url, const std::string& login, LabRole role, const std::string& station,
                  const std::optional<std::string>& password);

// The server seen as a store of sessions (sessions list/show/verify/approve/reject/export
// and the station's review view with --db postgresql://…). A session's `id` is the
// server's; `station` and `stationSessionId` name it at its station. Markers and readings
// are read back from the events (db::project). What the login may see and do is the
// server's to decide: a refusal is a StoreError of kind Refused, in the server's words.
class LabStore final : public EventStore {
 public:
  explicit LabStore(const std::string& url);
  ~LabStore() override;

  [[nodiscard]] std::string describe() const override;
  [[nodiscard]] std::vector<SessionInfo> sessions() const override;
  [[nodiscard]] std::optional<SessionInfo> session(std::int64_t id) const override;
  [[nodiscard]] std::vector<Event> events(std::int64_t session, std::int64_t fromSeq = 1) const override;
  [[nodiscard]] std::vector<MarkerRow> markers(std::int64_t session) const override;
  [[nodiscard]] std::vector<ThicknessRow> thickness(std::int64_t session) const override;
  [[nodiscard]] ChainReport verify(std::int64_t session) const override;
  std::int64_t append(std::int64_t session, const EventInput& event) override;
  std::int64_t appendAll(std::int64_t session, const std::vector<EventInput>& events) override;
  std::int64_t ensureOperator(const std::string& name, const std::string& role) override;
  std::int64_t recordExport(std::int64_t session, const std::string& path, const std::string& format) override;
  [[nodiscard]] std::optional<std::string> login() const override { return login_; }
  // The login's group on the server (none: a login in no leafdig group), asked of the server.
  [[nodiscard]] std::optional<LabRole> role() const;
  // Whether the server checked a password to let this connection in (the web review refuses a
  // login the server let in on `trust`: its password would prove nothing).
  [[nodiscard]] bool passwordChecked() const;

 private:
  std::unique_ptr<pg::Connection> conn_;
  int schemaVersion_ = 0;
  std::string login_;
  bool genesisForms_ = false;  // the server knows a genesis that covers the station (lab schema 10)
};

// Opens a station's SQLite file, or the lab server for a postgresql:// URL.
[[nodiscard]] std::unique_ptr<EventStore> openEventStore(const std::string& pathOrUrl, bool readOnly);

struct SyncOptions {
  std::optional<std::string> station;  // only this station's sessions (default: every one in the file)
  std::size_t eventsPerTransaction = 2000;
  std::function<void(const std::string&)> progress;  // one line per session that moved
  // Pull: given a session and every event it would hold once the pulled ones are in, throws
  // (any exception, with words) when they do not replay; the session is then refused whole.
  // The CLI and the station pass acquisition::requireReplays.
  std::function<void(const SessionInfo&, const std::vector<Event>&)> replays;
};
// One session that could not be sent or taken in, and why (the server's or our words).
struct SyncProblem {
  std::string station;
  std::int64_t stationSessionId = 0;
  std::string problem, remedy;
};
struct PushReport {
  std::int64_t sessionsSeen = 0, sessionsNew = 0, sessionsUpToDate = 0, sessionsBehind = 0;
  std::int64_t eventsSent = 0, transactions = 0;
  std::vector<SyncProblem> problems;
};
// Sends every event the server lacks, session by session in order, in transactions of at
// most eventsPerTransaction events (each one durable on the server when committed):
// idempotent, and a push cut anywhere continues where the server stands. A session that
// cannot go (refused, diverged, not UTF-8) is reported and the others still go. Throws
// StoreError(Unreachable) when the server cannot be reached or the connection is lost
// (what was committed stays; run it again).
PushReport push(Store& local, const std::string& url, const SyncOptions& options = {});
struct PullReport {
  std::int64_t sessionsSeen = 0, sessionsUpdated = 0, eventsTaken = 0;
  std::vector<SyncProblem> problems;
};
// Takes in, for each of the file's sessions on the server, the events the server has
// beyond the station's (a curator's corrections and decision), verbatim and checked.
PullReport pull(Store& local, const std::string& url, const SyncOptions& options = {});

}  // namespace leafdig::db
