// How an item travels in event payloads and projections (session and review share it).
#pragma once

#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <tuple>

#include "leafdig/acquisition/protocol/engine.hpp"
#include "leafdig/db/store.hpp"
#include "leafdig/model/limits.hpp"

namespace leafdig::acquisition::detail {

using Key = std::tuple<int, int, int>;

inline Key keyOf(const Item& i) {
  return {static_cast<int>(i.what), i.row, i.col};
}

inline nlohmann::json nullable(int v) {
  return v > 0 ? nlohmann::json(v) : nlohmann::json(nullptr);
}

inline nlohmann::json itemJson(const Item& i) {
  nlohmann::json j{{"what", toString(i.what)}, {"row", nullable(i.row)}, {"col", nullable(i.col)}};
  if (isStylusItem(i.what))
    j["position_mm"] = {i.positionMm[0], i.positionMm[1], i.positionMm[2]};
  else
    j["value_mm"] = i.valueMm;
  if (!i.flag.empty()) j["flag"] = i.flag;
  if (i.frame > 0) j["frame"] = i.frame;  // taken after a move of the transmitter
  return j;
}

inline Item itemFrom(const nlohmann::json& j, const std::string& raw) {
  Item i;
  i.what = whatFromString(j.at("what").get<std::string>());
  i.row = j.value("row", nlohmann::json(nullptr)).is_null() ? 0 : j.at("row").get<int>();
  i.col = j.value("col", nlohmann::json(nullptr)).is_null() ? 0 : j.at("col").get<int>();
  if (j.contains("position_mm"))
    for (std::size_t k = 0; k < 3; ++k) i.positionMm[k] = j.at("position_mm").at(k).get<double>();
  if (j.contains("value_mm")) i.valueMm = j.at("value_mm").get<double>();
  i.flag = j.value("flag", std::string());
  i.frame = j.value("frame", 0);
  if (i.frame < 0 || i.frame > 999)
    throw std::invalid_argument("its frame " + std::to_string(i.frame) + " is not 0–999");
  // Where each item may stand (the engine's steps): nothing an event says indexes outside a leaf.
  const int maxRow = static_cast<int>(model::kMaxRows);
  const auto at = [&](int rowLo, int rowHi, int colLo, int colHi) {
    if (i.row < rowLo || i.row > rowHi || i.col < colLo || i.col > colHi)
      throw std::invalid_argument(std::string("its ") + toString(i.what) + " stands at row " + std::to_string(i.row) +
                                  " col " + std::to_string(i.col) + ", where no " + toString(i.what) + " is taken");
  };
  switch (i.what) {
    case What::Board: at(0, 0, 1, 3); break;
    case What::BoardAgain: at(1, 999, 1, 3); break;
    case What::Tip:
    case What::EdgeThickness: at(0, 0, 0, 0); break;
    case What::Marker:
    case What::PointThickness: at(1, maxRow, 1, 7); break;
    case What::MidribThickness:
    case What::VeinOriginThickness: at(1, maxRow, 4, 4); break;
    case What::Done: throw std::invalid_argument("it names no item");
  }
  i.raw = raw;
  return i;
}

inline db::Projection projectionOf(const Item& i) {
  db::Projection p;
  p.kind = isStylusItem(i.what) ? db::Projection::Kind::Marker : db::Projection::Kind::Thickness;
  if (i.row > 0) p.row = i.row;
  if (i.col > 0) p.col = i.col;
  p.what = toString(i.what);
  p.positionMm = i.positionMm;
  p.valueMm = i.valueMm;
  p.raw = i.raw;
  return p;
}

}  // namespace leafdig::acquisition::detail
