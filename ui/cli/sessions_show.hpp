// `sessions list` and `sessions show ID [--json]`: sessions as captured and reviewed
// (sessions_show.cpp). Their JSON is also what the web review's API answers (web/web_app.cpp).
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "leafdig/db/event_store.hpp"
#include "sessions_options.hpp"

namespace leafdig::cli {

int runShow(const db::EventStore& store, const SessionsOptions& o);
// What `sessions show ID --json` prints (the history included).
[[nodiscard]] nlohmann::json sessionJson(const db::EventStore& store, std::int64_t id);

// `sessions list`'s filters (--status, --kind, --plant, --station, --since): every one given holds.
[[nodiscard]] bool listed(const db::SessionInfo& s, const SessionsOptions& o);
// What `plant surveys PLANT --json` prints: the plant and every dated survey of it.
[[nodiscard]] nlohmann::json plantSurveysJson(const db::EventStore& store, const std::string& plant);

// What `sessions list --json` prints of these sessions (each decided one's decision included).
[[nodiscard]] nlohmann::json sessionListJson(const db::EventStore& store, const std::vector<db::SessionInfo>& sessions);

}  // namespace leafdig::cli
