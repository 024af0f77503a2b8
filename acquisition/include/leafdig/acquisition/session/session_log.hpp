// What every capture session does with the store, whatever it captures: the leaf's session
// (session.hpp) and the plant's (plant_session.hpp) each hold a SessionLog, and a new kind of
// capture holds one too (docs/architecture.md, "Adding a kind of capture"). What stays each
// kind's own is its protocol: the decisions its engine makes, the events they are written as and
// how they replay.
//
// Thread contract: one thread owns a SessionLog (and its Store), as it owns the session.
#pragma once

#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "leafdig/acquisition/protocol/items.hpp"
#include "leafdig/db/store.hpp"

namespace leafdig::acquisition {

// This station's id: the one a new session records (SessionSetup::station default) and
// whose interrupted sessions a front end offers to resume. `[station] id = …` in the
// settings file (stationSettingsFile()), else the host name; empty if neither is known.
// `--station` on the command line overrides it (SessionSetup::station).
[[nodiscard]] std::string thisStation();
// $XDG_CONFIG_HOME/leafdig/station.ini (~/.config/leafdig/station.ini), shared with the Qt
// station's settings.
[[nodiscard]] std::string stationSettingsFile();
// One value of the station's settings file ("[section]", then "key=value"), as written there;
// nothing when the file, the section or the key is not there. The CLI reads the settings the
// station's dialog writes through it (thisStation's id, the field check's age).
[[nodiscard]] std::optional<std::string> stationSetting(std::string_view section, std::string_view key);

class SessionError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

namespace detail {
// The one check before a stored session is trusted: its chain recomputed (capture into it,
// review, correction and export share it, so the words are the same everywhere). Throws
// SessionError "session N fails 'sessions verify' (event K: what): it cannot be <doing>".
void requireChain(const db::EventStore& store, std::int64_t id, const std::string& doing);
// What a session that does not verify cannot be when a capture would go on with it.
inline constexpr const char* kCapturedInto =
    "captured into: nothing is added to it; 'leafdig sessions verify' shows it to a curator";
}  // namespace detail

// A kind of capture as the store names it ("leaf", "plant") and how a front end goes on with
// an open session of it: the words a refusal gives.
struct CaptureKind {
  std::string_view word;     // sessions.kind
  std::string_view noun;     // "session", "plant session"
  std::string_view goOn;     // the command that goes on with an open session of this kind, "{id}" for its id
  std::string_view content;  // what one session captures: "one leaf", "a whole plant"
};
inline constexpr CaptureKind kLeafCapture{"leaf", "session", "leafdig sessions resume {id}", "one leaf"};
inline constexpr CaptureKind kPlantCapture{"plant", "plant session", "leafdig plant capture --resume {id}",
                                           "a whole plant"};

// The project, plant, operator and devices a new session names, made where the store lacks
// them (a device spec is "kind:port…"; simulated devices are recorded as such).
struct SessionParties {
  std::int64_t project = 0, plant = 0, operatorId = 0;
  std::string station;  // the setup's, else this station's (thisStation())
};
[[nodiscard]] SessionParties ensureSessionParties(db::Store& store, const std::string& project,
                                                  const std::string& plant, const std::string& operatorName,
                                                  const std::string& station,
                                                  const std::vector<std::string>& deviceSpecs, bool simulated);

// The events every kind writes the same way (docs/schema.md).
[[nodiscard]] db::EventInput statusEvent(const std::string& status, const std::string& who, const std::string& why,
                                         std::int64_t monoNs);
[[nodiscard]] db::EventInput pausedEvent(const std::string& reason, std::int64_t monoNs);
[[nodiscard]] db::EventInput resumedEvent(std::int64_t monoNs);
[[nodiscard]] db::EventInput deviceEvent(const std::string& device, const std::string& state,
                                         const std::string& message, std::int64_t monoNs);
// A caliper reading taken while the capture is paused: kept (its raw text), changing nothing.
[[nodiscard]] db::EventInput ignoredReadingEvent(const CaliperInput& c);

// An operator's pause as a log holds it: the last `paused` not followed by `resumed`.
struct PauseState {
  bool paused = false;
  std::string reason;
};
[[nodiscard]] PauseState pauseIn(const std::vector<db::Event>& events);

class SessionLog {
 public:
  // The stored session `id` of `kind`, open and intact: SessionError in words when there is no
  // such session, it captures another kind (naming the command that goes on with it), it is not
  // open, or its chain does not verify.
  SessionLog(db::Store& store, std::int64_t id, const CaptureKind& kind);

  [[nodiscard]] std::int64_t id() const { return id_; }
  [[nodiscard]] const db::SessionInfo& info() const { return info_; }
  [[nodiscard]] db::Store& store() const { return store_; }
  [[nodiscard]] std::vector<db::Event> events() const { return store_.events(id_); }
  // The session's status as the store has it now.
  [[nodiscard]] std::string status() const;
  // Appends one event; db::StoreError when the store refuses it (nothing written).
  std::int64_t append(const db::EventInput& ev) { return store_.append(id_, ev); }

 private:
  db::Store& store_;
  std::int64_t id_ = 0;
  db::SessionInfo info_;
};

}  // namespace leafdig::acquisition
