#include "leafdig/acquisition/session/session_log.hpp"

#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <optional>

namespace leafdig::acquisition {
namespace {

using nlohmann::json;

constexpr const CaptureKind* kKinds[] = {&kLeafCapture, &kPlantCapture};

std::string withId(std::string_view pattern, std::int64_t id) {
  std::string s(pattern);
  if (const auto at = s.find("{id}"); at != std::string::npos) s.replace(at, 4, std::to_string(id));
  return s;
}

}  // namespace

std::string stationSettingsFile() {
  const char* xdg = std::getenv("XDG_CONFIG_HOME");
  const char* home = std::getenv("HOME");
  const std::filesystem::path base =
      (xdg && *xdg) ? std::filesystem::path(xdg) : std::filesystem::path(home ? home : ".") / ".config";
  return (base / "leafdig" / "station.ini").string();
}

std::optional<std::string> stationSetting(std::string_view section, std::string_view key) {
  // The INI the Qt station writes (QSettings): "[section]" lines, then "key=value".
  std::ifstream in(stationSettingsFile());
  std::string line, current;
  const auto trim = [](const std::string& t) {
    const auto a = t.find_first_not_of(" \t\r");
    const auto b = t.find_last_not_of(" \t\r");
    return a == std::string::npos ? std::string() : t.substr(a, b - a + 1);
  };
  while (std::getline(in, line)) {
    line = trim(line);
    if (line.size() > 2 && line.front() == '[' && line.back() == ']') {
      current = line.substr(1, line.size() - 2);
      continue;
    }
    const auto eq = line.find('=');
    if (current == section && eq != std::string::npos && trim(line.substr(0, eq)) == key)
      return trim(line.substr(eq + 1));
  }
  return std::nullopt;
}

std::string thisStation() {
  // [station] id = … in the station's settings file, else the host name.
  if (const auto id = stationSetting("station", "id"); id && !id->empty()) return *id;
  char host[256] = {};
  return ::gethostname(host, sizeof host - 1) == 0 ? std::string(host) : std::string();
}

SessionParties ensureSessionParties(db::Store& store, const std::string& project, const std::string& plant,
                                    const std::string& operatorName, const std::string& station,
                                    const std::vector<std::string>& deviceSpecs, bool simulated) {
  SessionParties p;
  p.project = store.ensureProject(project);
  p.plant = store.ensurePlant(p.project, plant);
  p.operatorId = store.ensureOperator(operatorName);
  for (const std::string& spec : deviceSpecs) {
    if (spec.empty()) continue;
    const auto colon = spec.find(':');
    (void)store.ensureDevice(spec.substr(0, colon), colon == std::string::npos ? "" : spec.substr(colon + 1),
                             simulated ? "simulated" : "");
  }
  p.station = station.empty() ? thisStation() : station;
  return p;
}

db::EventInput statusEvent(const std::string& status, const std::string& who, const std::string& why,
                           std::int64_t monoNs) {
  db::EventInput ev;
  ev.kind = "status";
  ev.monoNs = monoNs;
  ev.payloadJson = json{{"status", status}, {"who", who}, {"why", why}}.dump();
  ev.setsStatus = status;  // the session row changes in the same transaction
  return ev;
}

db::EventInput pausedEvent(const std::string& reason, std::int64_t monoNs) {
  db::EventInput ev;
  ev.kind = "paused";
  ev.monoNs = monoNs;
  ev.payloadJson = json{{"reason", reason}}.dump();
  return ev;
}

db::EventInput resumedEvent(std::int64_t monoNs) {
  db::EventInput ev;
  ev.kind = "resumed";
  ev.monoNs = monoNs;
  ev.payloadJson = "{}";
  return ev;
}

db::EventInput deviceEvent(const std::string& device, const std::string& state, const std::string& message,
                           std::int64_t monoNs) {
  db::EventInput ev;
  ev.kind = "device";
  ev.monoNs = monoNs;
  ev.payloadJson = json{{"device", device}, {"state", state}, {"message", message}}.dump();
  return ev;
}

db::EventInput ignoredReadingEvent(const CaliperInput& c) {
  db::EventInput ev;
  ev.kind = "ignored_reading";
  ev.monoNs = c.tNs;
  ev.raw = c.raw;
  ev.payloadJson = json{{"value_mm", c.valueMm}, {"why", "capture paused"}}.dump();
  return ev;
}

PauseState pauseIn(const std::vector<db::Event>& events) {
  PauseState state;
  for (const db::Event& e : events) {
    if (e.kind == "paused") {
      state.paused = true;
      const json p = json::parse(e.payloadJson, nullptr, false);
      state.reason = p.is_object() && p.contains("reason") && p.at("reason").is_string()
                         ? p.at("reason").get<std::string>()
                         : std::string();
    }
    if (e.kind == "resumed") state = {};
  }
  return state;
}

SessionLog::SessionLog(db::Store& store, std::int64_t id, const CaptureKind& kind) : store_(store), id_(id) {
  auto info = store_.session(id);
  if (!info)
    throw SessionError("there is no session " + std::to_string(id) + " in " + store_.path() +
                       ": 'leafdig sessions list' shows them");
  if (info->kind != kind.word) {
    for (const CaptureKind* other : kKinds)
      if (other->word == info->kind)
        throw SessionError("session " + std::to_string(id) + " captures " + std::string(other->content) + ", not " +
                           std::string(kind.content) + ": `" + withId(other->goOn, id) + "` goes on with it");
    throw SessionError("session " + std::to_string(id) + " is a " + info->kind + " session, not " +
                       std::string(kind.content) + ": this leafdig does not capture into it");
  }
  if (info->status != "open")
    throw SessionError(std::string(kind.noun) + " " + std::to_string(id) + " is " + info->status +
                       ": only open sessions can be captured into (a curator reviews the others)");
  info_ = std::move(*info);
  // The log captured into must be intact: its pages are read and its chain recomputed.
  detail::requireChain(store_, id_, detail::kCapturedInto);
}

std::string SessionLog::status() const {
  const auto info = store_.session(id_);
  return info ? info->status : std::string();
}

namespace detail {

void requireChain(const db::EventStore& store, std::int64_t id, const std::string& doing) {
  const db::ChainReport chain = store.verify(id);
  if (!chain.ok)
    throw SessionError("session " + std::to_string(id) + " fails 'sessions verify' (event " +
                       std::to_string(chain.firstBadSeq.value_or(0)) + ": " + chain.problem + "): it cannot be " +
                       doing);
}

}  // namespace detail

}  // namespace leafdig::acquisition
