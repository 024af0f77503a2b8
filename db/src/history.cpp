#include "leafdig/db/history.hpp"

#include <cmath>
#include <nlohmann/json.hpp>

namespace leafdig::db {
namespace {

using nlohmann::json;

std::optional<int> intAt(const json& j, const char* key) {
  if (j.contains(key) && j.at(key).is_number_integer()) return j.at(key).get<int>();
  return std::nullopt;
}

std::optional<std::array<double, 3>> pointAt(const json& j) {
  if (!j.contains("position_mm")) return std::nullopt;
  const json& p = j.at("position_mm");
  if (!p.is_array() || p.size() != 3) return std::nullopt;
  std::array<double, 3> out{};
  for (std::size_t i = 0; i < 3; ++i) {
    if (!p[i].is_number()) return std::nullopt;
    out[i] = p[i].get<double>();
  }
  return out;
}

std::optional<double> valueAt(const json& j) {
  if (j.contains("value_mm") && j.at("value_mm").is_number()) return j.at("value_mm").get<double>();
  return std::nullopt;
}

std::string textAt(const json& j, const char* key) {
  return j.contains(key) && j.at(key).is_string() ? j.at(key).get<std::string>() : std::string();
}

}  // namespace

std::optional<double> ReviewEntry::movedMm() const {
  if (!fromMm || !toMm) return std::nullopt;
  double s = 0;
  for (std::size_t i = 0; i < 3; ++i) s += ((*toMm)[i] - (*fromMm)[i]) * ((*toMm)[i] - (*fromMm)[i]);
  return std::sqrt(s);
}

std::vector<ReviewEntry> reviewHistory(const std::vector<Event>& events) {
  std::vector<ReviewEntry> out;
  for (const Event& e : events) {
    if (e.kind != "status" && e.kind != "corrected") continue;
    const json p = json::parse(e.payloadJson, nullptr, false);
    if (!p.is_object()) continue;
    ReviewEntry r;
    r.seq = e.seq;
    r.utc = e.utc;
    r.who = textAt(p, "who");
    if (e.kind == "status") {
      r.action = textAt(p, "status");
      if (r.action == "complete" && p.contains("reopens")) {
        r.action = "reopened";
        r.reopens = textAt(p, "reopens");
      } else if (r.action != "approved" && r.action != "rejected") {
        continue;  // a capture's own status
      }
      r.why = textAt(p, "why");
    } else {
      if (!p.contains("corrected") || !p.at("corrected").is_object()) continue;
      const json& fixed = p.at("corrected");
      r.action = "corrected";
      r.why = textAt(p, "reason");
      r.what = textAt(p, "what");
      r.row = intAt(p, "row");
      r.col = intAt(p, "col");
      r.fromMm = pointAt(p);
      r.toMm = pointAt(fixed);
      r.fromValueMm = valueAt(p);
      r.toValueMm = valueAt(fixed);
    }
    out.push_back(std::move(r));
  }
  return out;
}

namespace {

json entryJson(const ReviewEntry& r) {
  json j{{"seq", r.seq}, {"utc", r.utc}, {"action", r.action}, {"who", r.who}, {"why", r.why}};
  if (r.action == "reopened") j["reopens"] = r.reopens;
  if (r.action != "corrected") return j;
  j["what"] = r.what;
  j["row"] = r.row ? json(*r.row) : json(nullptr);
  j["col"] = r.col ? json(*r.col) : json(nullptr);
  const auto value = [](const std::optional<std::array<double, 3>>& p, const std::optional<double>& v) {
    if (p) return json{{"position_mm", {(*p)[0], (*p)[1], (*p)[2]}}};
    if (v) return json{{"value_mm", *v}};
    return json(nullptr);
  };
  j["from"] = value(r.fromMm, r.fromValueMm);
  j["to"] = value(r.toMm, r.toValueMm);
  if (const auto moved = r.movedMm()) j["moved_mm"] = *moved;
  return j;
}

}  // namespace

std::string reviewEntryJson(const ReviewEntry& entry) {
  return entryJson(entry).dump();
}

std::string reviewHistoryJson(const std::vector<ReviewEntry>& history) {
  json a = json::array();
  for (const ReviewEntry& r : history) a.push_back(entryJson(r));
  return a.dump();
}

std::optional<ReviewEntry> lastDecision(const std::vector<ReviewEntry>& history) {
  for (auto it = history.rbegin(); it != history.rend(); ++it) {
    if (it->action == "reopened") return std::nullopt;  // the decision before it no longer stands
    if (it->action == "approved" || it->action == "rejected") return *it;
  }
  return std::nullopt;
}

}  // namespace leafdig::db
