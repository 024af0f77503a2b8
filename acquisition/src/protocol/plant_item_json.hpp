// How a plant session's item travels in event payloads (the capture session and the curator's
// correction share it; item_json.hpp is the leaf's).
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "item_json.hpp"
#include "leafdig/acquisition/protocol/plant_engine.hpp"
#include "leafdig/db/event_rules.hpp"

namespace leafdig::acquisition::detail {

// A full leaf's item travels with its node in `what`: "node3.marker".
inline std::string leafWhat(int node, const Item& i) {
  return "node" + std::to_string(node) + "." + toString(i.what);
}

inline nlohmann::json plantItemJson(const PlantItem& i) {
  nlohmann::json j{{"what", toString(i.what)}, {"row", nullable(i.index)}, {"col", nullable(i.part)}};
  if (isStylusItem(i.what))
    j["position_mm"] = {i.positionMm[0], i.positionMm[1], i.positionMm[2]};
  else
    j["value_mm"] = i.valueMm;
  if (!i.flag.empty()) j["flag"] = i.flag;
  if (i.frame != 0) j["frame"] = i.frame;  // the transmitter position it was taken from (absent: the first)
  return j;
}

inline PlantItem plantItemFrom(const nlohmann::json& j, const std::string& raw) {
  PlantItem i;
  i.what = plantWhatFromString(j.at("what").get<std::string>());
  i.index = j.value("row", nlohmann::json(nullptr)).is_null() ? 0 : j.at("row").get<int>();
  i.part = j.value("col", nlohmann::json(nullptr)).is_null() ? 0 : j.at("col").get<int>();
  if (j.contains("position_mm"))
    for (std::size_t k = 0; k < 3; ++k) i.positionMm[k] = j.at("position_mm").at(k).get<double>();
  if (j.contains("value_mm")) i.valueMm = j.at("value_mm").get<double>();
  i.flag = j.value("flag", std::string());
  i.frame = j.value("frame", 0);
  i.raw = raw;
  return i;
}

// What an `accepted` event puts in the projection: the store's own reading of its payload.
inline std::optional<db::Projection> projectionOf(const std::string& payloadJson, const std::string& raw) {
  db::Event e;
  e.kind = "accepted";
  e.payloadJson = payloadJson;
  e.raw = raw;
  return db::changeOf(e).projection;
}

// The key of an item currently held: which event accepted it is kept under this.
inline std::string keyOf(const PlantItem& i) {
  return std::string(toString(i.what)) + ":" + std::to_string(i.index) + ":" + std::to_string(i.part);
}
inline std::string keyOf(int node, const Item& i) {
  return leafWhat(node, i) + ":" + std::to_string(i.row) + ":" + std::to_string(i.col);
}

}  // namespace leafdig::acquisition::detail
