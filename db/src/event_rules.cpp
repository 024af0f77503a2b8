// One definition of a valid event, on the station's side (event_rules.hpp); the server's is
// schema 10's event_state_problem and payload_problem, and tests/data/event_cases.json holds
// the cases both must decide alike.
#include "leafdig/db/event_rules.hpp"

#include <cmath>
#include <nlohmann/json.hpp>
#include <string_view>
#include <vector>

namespace leafdig::db {

namespace {

using nlohmann::json;

// The first number in `j` that is not finite or beyond the limit, as text; or nothing.
std::optional<std::string> numberOutOfRange(const json& j) {
  if (j.is_number_float()) {
    const double v = j.get<double>();
    if (!std::isfinite(v) || std::abs(v) > kMaxJsonMagnitude) return j.dump();
  } else if (j.is_number_integer() || j.is_number_unsigned()) {
    const double v = j.get<double>();
    if (std::abs(v) > kMaxJsonMagnitude) return j.dump();
  } else if (j.is_structured()) {
    for (const json& x : j)
      if (auto bad = numberOutOfRange(x)) return bad;
  }
  return std::nullopt;
}

// Keys of `j` outside `allowed`, comma-separated in order, or "".
std::string unknownKeys(const json& j, const std::vector<std::string_view>& allowed) {
  std::string out;
  for (const auto& [k, v] : j.items()) {
    bool known = false;
    for (std::string_view a : allowed) known = known || k == a;
    if (!known) out += (out.empty() ? "" : ", ") + k.substr(0, 40);
  }
  return out;
}

const std::vector<std::string_view>& itemKeys() {
  static const std::vector<std::string_view> keys{"what", "row", "col", "position_mm", "value_mm", "flag", "frame"};
  return keys;
}

// An item's place, as the server's item_key compares it.
std::string placeOf(const json& item) {
  const auto text = [&](const char* k) {
    if (!item.contains(k) || item.at(k).is_null()) return std::string();
    return item.at(k).is_string() ? item.at(k).get<std::string>() : item.at(k).dump();
  };
  return text("what") + "|" + text("row") + "|" + text("col");
}

std::optional<std::string> itemProblem(const json& item) {
  if (!item.is_object()) return "its item is not a JSON object";
  if (!item.contains("what") || !item.at("what").is_string()) return "its item names no what";
  if (item.contains("position_mm")) {
    const json& p = item.at("position_mm");
    if (!p.is_array() || p.size() != 3) return "its position_mm is not three numbers";
    for (const json& v : p)
      if (!v.is_number() || std::abs(v.get<double>()) > kMaxItemCoordinateMm)
        return "its position_mm " + v.dump() + " is not a number within ±10000 mm";
  }
  if (item.contains("value_mm")) {
    const json& v = item.at("value_mm");
    if (!v.is_number() || !(v.get<double>() > 0) || v.get<double>() > kMaxItemValueMm)
      return "its value_mm " + v.dump() + " is not a number above 0 and at most 100 mm";
  }
  return std::nullopt;
}

}  // namespace

std::optional<std::string> eventProblem(const std::string& kind, const std::string& payloadJson,
                                        const std::string& raw) {
  if (payloadJson.size() > kMaxPayloadBytes)
    return "its payload is " + std::to_string(payloadJson.size()) + " bytes: at most 65536 are taken";
  if (raw.size() > kMaxRawBytes)
    return "its raw text is " + std::to_string(raw.size()) + " bytes: at most 262144 are taken";
  json p;
  try {
    p = json::parse(payloadJson);
  } catch (const json::exception& e) {
    // nlohmann refuses a number beyond a double ("number overflow") here, as the server's range check does.
    return std::string("its payload is not JSON that leafdig reads (") + e.what() + ")";
  }
  if (!p.is_object()) return "its payload is not a JSON object";
  if (const auto bad = numberOutOfRange(p)) return "its payload holds a number beyond ±1e15 (" + *bad + ")";
  std::string extra;
  const bool putsItem = kind == "accepted" || kind == "retake_cancelled";
  const bool takesItem = kind == "undone" || kind == "retake";
  if (putsItem) {
    extra = unknownKeys(p, itemKeys());
  } else if (takesItem) {
    extra = unknownKeys(p, {"what", "row", "col", "position_mm", "value_mm", "flag", "frame", "seq"});
  } else if (kind == "corrected") {
    extra = unknownKeys(
        p, {"what", "row", "col", "position_mm", "value_mm", "flag", "frame", "seq", "corrected", "reason", "who"});
    if (extra.empty() && p.contains("corrected") && p.at("corrected").is_object())
      extra = unknownKeys(p.at("corrected"), itemKeys());
  } else if (kind == "status") {
    extra = unknownKeys(p, {"status", "who", "why", "reopens"});
    // A curator's reopening (docs/schema.md, "Event kinds"): back to complete, naming the
    // decision it reopens, signed and with a reason.
    const auto text = [&p](const char* key) { return p.contains(key) && p.at(key).is_string(); };
    if (extra.empty() && p.contains("reopens") &&
        !(text("status") && p.at("status") == "complete" && text("reopens") &&
          (p.at("reopens") == "approved" || p.at("reopens") == "rejected") && text("who") && text("why") &&
          p.at("why").get<std::string>().find_first_not_of(" \t\r\n") != std::string::npos))
      return "a reopening sets the status complete, names the decision it reopens (approved or rejected) and says "
             "who and why";
  }
  if (!extra.empty()) return "its payload has keys leafdig does not write (" + extra + ")";
  if (putsItem || takesItem || kind == "corrected") {
    if (const auto bad = itemProblem(p)) return bad;
  }
  if (takesItem || kind == "corrected") {
    if (!p.contains("seq") || !p.at("seq").is_number_integer() || p.at("seq").get<std::int64_t>() < 1)
      return "its payload does not name an earlier event (seq)";
  }
  if (kind == "corrected") {
    if (!p.contains("corrected")) return "its payload lacks the corrected item";
    if (const auto bad = itemProblem(p.at("corrected"))) return "its corrected item: " + bad->substr(4);
    if (placeOf(p.at("corrected")) != placeOf(p)) return "its corrected item is not the item it names (what, row, col)";
    if (!p.contains("reason") || !p.at("reason").is_string() || !p.contains("who") || !p.at("who").is_string())
      return "its payload lacks the reason or who corrected";
  }
  return std::nullopt;
}

std::optional<std::string> settingsProblem(const std::string& settingsJson) {
  if (settingsJson.size() > kMaxSettingsBytes)
    return "its settings are " + std::to_string(settingsJson.size()) + " bytes: at most 4194304 are taken";
  json p;
  try {
    p = json::parse(settingsJson);
  } catch (const json::exception& e) {
    return std::string("its settings are not JSON that leafdig reads (") + e.what() + ")";
  }
  if (!p.is_object()) return "its settings are not a JSON object";
  if (const auto bad = numberOutOfRange(p)) return "its settings hold a number beyond ±1e15 (" + *bad + ")";
  return std::nullopt;
}

}  // namespace leafdig::db
