#include "leafdig/acquisition/protocol/marker_set.hpp"

#include "leafdig/acquisition/protocol/point_rules.hpp"
#include "leafdig/model/errors.hpp"

namespace leafdig::acquisition {
namespace m = leafdig::model;

m::MarkerSet partialMarkerSet(const std::vector<Item>& items, const Settings& settings,
                              const ProvisionalThickness* provisional, bool& usedProvisional) {
  const Eigen::Isometry3d frame = boardFrame(items);
  m::MarkerSet set;
  if (const Item* tip = findItem(items, What::Tip, 0, 0)) set.tipMm = frame * rules::toPoint(tip->positionMm);
  const int rows = completeRows(items);
  const auto value = [&](What w, int row, int col) -> std::optional<double> {
    if (const Item* i = findItem(items, w, row, col)) return i->valueMm;
    return std::nullopt;
  };
  for (int r = 1; r <= rows; ++r) {
    m::MarkerRow row;
    for (int c = 1; c <= 7; ++c)
      row.pointsMm[static_cast<std::size_t>(c - 1)] =
          frame * rules::toPoint(findItem(items, What::Marker, r, c)->positionMm);
    row.midribThicknessMm = value(What::MidribThickness, r, 4);
    if (settings.mode == Mode::Standard) row.veinOriginThicknessMm = value(What::VeinOriginThickness, r, 4);
    if (settings.mode == Mode::Full)
      for (int c = 1; c <= 7; ++c)
        row.measuredThicknessMm[static_cast<std::size_t>(c - 1)] = value(What::PointThickness, r, c);
    if (provisional) {
      if (!row.midribThicknessMm) {
        row.midribThicknessMm = provisional->midribMm;
        usedProvisional = true;
      }
      if (settings.mode == Mode::Standard && !row.veinOriginThicknessMm) {
        row.veinOriginThicknessMm = provisional->veinOriginMm;
        usedProvisional = true;
      }
      if (settings.mode == Mode::Full)
        for (int c = 1; c <= 7; ++c) {
          auto& t = row.measuredThicknessMm[static_cast<std::size_t>(c - 1)];
          if (!t) {
            t = c == 4             ? provisional->veinOriginMm
                : c == 1 || c == 7 ? provisional->edgeMm
                                   : 0.5 * (provisional->edgeMm + provisional->veinOriginMm);
            usedProvisional = true;
          }
        }
    }
    set.rows.push_back(row);
  }
  set.edgeThicknessMm = value(What::EdgeThickness, 0, 0);
  if (provisional && settings.mode != Mode::Full && !set.edgeThicknessMm) {
    set.edgeThicknessMm = provisional->edgeMm;
    usedProvisional = true;
  }
  set.mode = settings.mode;
  return set;
}

Eigen::Isometry3d boardFrame(const std::vector<Item>& items) {
  const Item* o = findItem(items, What::Board, 0, 1);
  const Item* x = findItem(items, What::Board, 0, 2);
  const Item* y = findItem(items, What::Board, 0, 3);
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  if (!o || !x || !y) return t;
  const Eigen::Vector3d origin = rules::toPoint(o->positionMm);
  const Eigen::Vector3d ex = (rules::toPoint(x->positionMm) - origin).normalized();
  Eigen::Vector3d ey = rules::toPoint(y->positionMm) - origin;
  ey = (ey - ey.dot(ex) * ex).normalized();
  Eigen::Matrix3d r;
  r.row(0) = ex;
  r.row(1) = ey;
  r.row(2) = ex.cross(ey);
  t.linear() = r;
  t.translation() = -(r * origin);
  return t;
}

model::MarkerSet toMarkerSet(const std::vector<Item>& items, const Settings& settings, const model::LeafInfo& leaf) {
  if (!findItem(items, What::Tip, 0, 0)) throw m::InputError("the capture has no tip yet: it is not complete");
  bool unused = false;
  m::MarkerSet set = partialMarkerSet(items, settings, nullptr, unused);
  if (set.rows.empty()) throw m::InputError("the capture has no complete row: it is not complete");
  set.leaf = leaf;
  (void)m::applyThicknessRule(set);  // throws naming the missing reading
  return set;
}

}  // namespace leafdig::acquisition
