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

}  // namespace leafdig::test
