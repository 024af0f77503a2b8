// Sessions written into a station's file as a capture writes them (the payloads of
// docs/schema.md), without devices: for the lab server's tests and benchmarks.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "leafdig/db/store.hpp"

namespace leafdig::test {

namespace db = leafdig::db;

// A session as a station writes it: the tip and `rows` rows of 7 markers (one undone and
// taken again), a midrib and a vein-origin reading per row, the end of the rows and the
// edge reading, then `complete` (unless `complete` is false: the session stays open, as one
// being captured). Returns the session's id in the file.
inline std::int64_t captureSession(db::Store& s, const std::string& station, int leaf, int rows = 3,
                                   const std::string& project = "tobacco-2026", const std::string& plant = "P-07",
                                   const std::string& operatorName = "ana", bool complete = true) {
  const auto op = s.ensureOperator(operatorName);
  const auto leafId = s.ensureLeaf(s.ensurePlant(s.ensureProject(project), plant), leaf, "middle", 12345.5);
  const auto id = s.createSession(leafId, op, station, "standard", "sequential", R"({"engine":{"still_mm":0.5}})");
  std::int64_t mono = 1000;
  const auto marker = [&](const std::string& what, int row, int col, double x) {
    nlohmann::json p{{"what", what},
                     {"row", row > 0 ? nlohmann::json(row) : nlohmann::json(nullptr)},
                     {"col", col > 0 ? nlohmann::json(col) : nlohmann::json(nullptr)},
                     {"position_mm", {x, 2.5 * row, 0.25 * col}}};
    db::EventInput e;
    e.kind = "accepted";
    e.payloadJson = p.dump();
    e.raw = "01   1.00   2.00   3.00\r\n";
    e.monoNs = mono += 1000;
    e.projection = db::changeOf(db::Event{0, 0, "", 0, e.kind, e.payloadJson, e.raw, "", ""}).projection;
    return s.append(id, e);
  };
  const auto reading = [&](const std::string& what, int row, int col, double mm) {
    nlohmann::json p{{"what", what}, {"row", row}, {"col", col}, {"value_mm", mm}};
    db::EventInput e;
    e.kind = "accepted";
    e.payloadJson = p.dump();
    e.raw = "+000" + std::to_string(mm) + "\r";
    e.monoNs = mono += 1000;
    e.projection = db::changeOf(db::Event{0, 0, "", 0, e.kind, e.payloadJson, e.raw, "", ""}).projection;
    return s.append(id, e);
  };
  (void)marker("tip", 0, 0, 0.0);
  for (int r = 1; r <= rows; ++r)
    for (int c = 1; c <= 7; ++c) {
      const auto seq = marker("marker", r, c, 10.0 * c);
      if (r == 2 && c == 5) {  // a slip, undone
        db::EventInput u;
        u.kind = "undone";
        u.payloadJson = nlohmann::json{{"what", "marker"}, {"row", r}, {"col", c}, {"seq", seq}}.dump();
        u.retracts = seq;
        u.monoNs = mono += 1000;
        (void)s.append(id, u);
        (void)marker("marker", r, c, 10.0 * c + 0.5);
      }
    }
  db::EventInput ended;
  ended.kind = "rows_ended";
  ended.monoNs = mono += 1000;
  (void)s.append(id, ended);
  for (int r = 1; r <= rows; ++r) {
    (void)reading("midrib_thickness", r, 4, 2.0 - 0.1 * r);
    (void)reading("vein_origin_thickness", r, 4, 1.0 - 0.05 * r);
  }
  if (complete) (void)s.setStatus(id, "complete", operatorName, "all steps captured");
  return id;
}

// A plant session as a station writes it (the payloads of docs/schema.md, "Plant sessions"):
// three landmarks and their end, the collar and its diameter, then per node its point, its
// stem reading and its leaf — node 1 none, node 2 full (tip, two rows of 7, the rows' end and
// two midrib readings), node 3 quick (three points, one undone and taken again) — then the
// plant's end and `complete` (unless `complete` is false). Returns the session's id.
inline std::int64_t capturePlantSession(db::Store& s, const std::string& station, const std::string& plant = "P-07",
                                        const std::string& project = "tobacco-2026",
                                        const std::string& operatorName = "ana", bool complete = true) {
  const auto op = s.ensureOperator(operatorName);
  const auto id = s.createPlantSession(s.ensurePlant(s.ensureProject(project), plant), op, station, "standard",
                                       "sequential", R"({"kind":"plant","engine":{"still_mm":0.5}})");
  std::int64_t mono = 1000;
  const auto append = [&](const std::string& kind, const nlohmann::json& payload, const std::string& raw) {
    db::EventInput e;
    e.kind = kind;
    e.payloadJson = payload.dump();
    e.raw = raw;
    e.monoNs = mono += 1000;
    const db::EventInput change = db::changeOf(db::Event{0, 0, "", 0, e.kind, e.payloadJson, e.raw, "", ""});
    e.projection = change.projection;
    e.retracts = change.retracts;
    return s.append(id, e);
  };
  const auto index = [](int i) { return i > 0 ? nlohmann::json(i) : nlohmann::json(nullptr); };
  const auto point = [&](const std::string& what, int row, int col, double x, double z) {
    return append("accepted",
                  {{"what", what}, {"row", index(row)}, {"col", index(col)}, {"position_mm", {x, 0.5 * row, z}}},
                  "01 " + std::to_string(x) + "\r\n");
  };
  const auto reading = [&](const std::string& what, int row, int col, double mm) {
    return append("accepted", {{"what", what}, {"row", index(row)}, {"col", index(col)}, {"value_mm", mm}},
                  "+" + std::to_string(mm) + "\r");
  };
  for (int k = 1; k <= 3; ++k) (void)point("landmark", k, 0, 100.0 * k, 20.0);
  (void)append("landmarks_ended", nlohmann::json::object(), "");
  (void)point("collar", 0, 0, 0.0, 0.0);
  (void)reading("collar_diameter", 0, 0, 14.2);
  const auto choose = [&](int node, const char* kind) {
    (void)append("leaf_chosen", {{"node", node}, {"kind", kind}, {"state", "alive"}}, "");
  };
  (void)point("point", 1, 1, 1.0, 80.0);
  (void)reading("reading", 1, 1, 12.5);
  choose(1, "none");
  (void)point("point", 2, 1, 1.5, 160.0);
  (void)reading("reading", 2, 1, 11.0);
  choose(2, "full");
  (void)point("node2.tip", 0, 0, 300.0, 260.0);
  for (int r = 1; r <= 2; ++r)
    for (int c = 1; c <= 7; ++c) (void)point("node2.marker", r, c, 100.0 + 20.0 * c, 200.0 + 10.0 * r);
  (void)append("rows_ended", {{"node", 2}}, "");
  for (int r = 1; r <= 2; ++r) (void)reading("node2.midrib_thickness", r, 4, 1.8 - 0.1 * r);
  (void)point("point", 3, 1, 2.0, 240.0);
  (void)reading("reading", 3, 1, 9.5);
  choose(3, "quick");
  (void)point("quick_point", 3, 1, 20.0, 250.0);
  const auto slip = point("quick_point", 3, 2, 999.0, 250.0);
  (void)append("undone", {{"what", "quick_point"}, {"row", 3}, {"col", 2}, {"seq", slip}}, "");
  (void)point("quick_point", 3, 2, 180.0, 330.0);
  (void)point("quick_point", 3, 3, 110.0, 290.0);
  (void)append("plant_ended", nlohmann::json::object(), "");
  if (complete) (void)s.setStatus(id, "complete", operatorName, "all steps captured");
  return id;
}

}  // namespace leafdig::test
