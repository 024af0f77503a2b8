#include "leafdig/acquisition/review/provenance.hpp"

#include <nlohmann/json.hpp>

#include "leafdig/acquisition/review/review.hpp"
#include "leafdig/db/history.hpp"

namespace leafdig::acquisition {

namespace {

// One line of printable text: a station file edited with sqlite3 may hold a name with a line
// break or a tab, which would start a line of its own in a comment-bearing format.
std::string printable(const std::string& text) {
  std::string out = text;
  for (char& ch : out) {
    const auto c = static_cast<unsigned char>(ch);
    if (c < 0x20 || c == 0x7f) ch = ' ';
  }
  return out;
}

}  // namespace

model::Provenance sessionProvenance(const db::EventStore& store, const db::SessionInfo& info) {
  const std::vector<db::ReviewEntry> history = db::reviewHistory(store.events(info.id));
  const std::optional<db::ReviewEntry> decision = db::lastDecision(history);
  int corrections = 0;
  for (const db::ReviewEntry& r : history) corrections += r.action == "corrected";
  model::Provenance p{{"session", std::to_string(info.id)},
                      {"station", printable(info.station)},
                      {"station_session", std::to_string(info.stationSessionId)},
                      {"status", printable(info.status)},
                      {"operator", printable(info.operatorName)},
                      {"decision", decision ? printable(decision->action) : "none"}};
  if (decision) {
    p.emplace_back("curator", printable(decision->who));
    p.emplace_back("decided_utc", printable(decision->utc));
  }
  p.emplace_back("corrections", std::to_string(corrections));
  // The field check its stylus samples went through (issue 50), when there was one.
  if (const std::optional<FieldApplied> field = sessionField(info))
    p.emplace_back("field_calibration", printable(field->words()));
  // The stylus' tip calibration, when one applied.
  if (const std::optional<TipApplied> tip = sessionTip(info))
    p.emplace_back("tip_calibration", printable(tip->words()));
  return p;
}

std::string provenanceComments(const model::Provenance& p, const std::string& prefix) {
  std::string out;
  for (const auto& [key, value] : p) {
    // A spreadsheet still splits a CSV comment line into cells: a comma, semicolon or quote in a
    // name would start a cell of its own, which could hold a formula. One cell, the whole line.
    std::string v = value;
    for (char& ch : v)
      if (ch == ',' || ch == ';' || ch == '"') ch = ' ';
    out += prefix + key + ": " + v + "\n";
  }
  return out;
}

std::string provenanceJson(const model::Provenance& p) {
  nlohmann::ordered_json j = nlohmann::ordered_json::object();
  for (const auto& [key, value] : p) j[key] = value;
  return j.dump();
}

}  // namespace leafdig::acquisition
