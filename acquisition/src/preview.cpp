#include "leafdig/acquisition/preview.hpp"

#include <Eigen/Geometry>

#include "leafdig/model/errors.hpp"
#include "leafdig/model/mesh/mesh_method.hpp"

namespace leafdig::acquisition {
namespace {

namespace m = leafdig::model;

Eigen::Vector3d vec(const Vec3& v) {
  return {v[0], v[1], v[2]};
}

// The marker set of the complete rows; thicknesses that were not measured are filled with
// `provisional` when given, else left absent.
m::MarkerSet markerSet(const std::vector<Item>& items, const Settings& settings,
                       const ProvisionalThickness* provisional, bool& usedProvisional) {
  const Eigen::Isometry3d frame = boardFrame(items);
  m::MarkerSet set;
  if (const Item* tip = findItem(items, What::Tip, 0, 0)) set.tipMm = frame * vec(tip->positionMm);
  const int rows = completeRows(items);
  const auto value = [&](What w, int row, int col) -> std::optional<double> {
    if (const Item* i = findItem(items, w, row, col)) return i->valueMm;
    return std::nullopt;
  };
  for (int r = 1; r <= rows; ++r) {
    m::MarkerRow row;
    for (int c = 1; c <= 7; ++c)
      row.pointsMm[static_cast<std::size_t>(c - 1)] = frame * vec(findItem(items, What::Marker, r, c)->positionMm);
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

}  // namespace

Eigen::Isometry3d boardFrame(const std::vector<Item>& items) {
  const Item* o = findItem(items, What::Board, 0, 1);
  const Item* x = findItem(items, What::Board, 0, 2);
  const Item* y = findItem(items, What::Board, 0, 3);
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  if (!o || !x || !y) return t;
  const Eigen::Vector3d origin = vec(o->positionMm);
  const Eigen::Vector3d ex = (vec(x->positionMm) - origin).normalized();
  Eigen::Vector3d ey = vec(y->positionMm) - origin;
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
  m::MarkerSet set = markerSet(items, settings, nullptr, unused);
  if (set.rows.empty()) throw m::InputError("the capture has no complete row: it is not complete");
  set.leaf = leaf;
  (void)m::applyThicknessRule(set);  // throws naming the missing reading
  return set;
}

Preview buildPreview(const std::vector<Item>& items, const Settings& settings, const ProvisionalThickness& provisional,
                     bool meshes) {
  Preview p;
  const Item* tip = findItem(items, What::Tip, 0, 0);
  if (!tip) return p;
  bool usedProvisional = false;
  m::MarkerSet set = markerSet(items, settings, &provisional, usedProvisional);
  const Eigen::Isometry3d frame = boardFrame(items);
  try {
    if (!set.rows.empty()) {
      p.model = m::buildLeafModel(set);
      if (set.rows.size() < 2) p.model.blade = {};  // a blade needs two rows
    }
    // The midrib reaches the current row's 4th marker as soon as it is taken.
    const int next = static_cast<int>(set.rows.size()) + 1;
    if (const Item* mid = findItem(items, What::Marker, next, 4)) {
      const m::LeafThickness& t = p.model.thickness;  // from buildLeafModel above (no rows: unused)
      std::vector<m::Ball> balls;
      const double tipD = set.rows.empty() ? set.edgeThicknessMm.value_or(provisional.edgeMm) : t.tipMm;
      balls.push_back({set.tipMm, tipD / 2});
      for (std::size_t i = 0; i < set.rows.size(); ++i)
        balls.push_back({set.rows[i].pointsMm[m::kMidribColumn], t.rows[i].midribMm / 2});
      const auto measured = findItem(items, What::MidribThickness, next, 4);
      balls.push_back({frame * vec(mid->positionMm), (measured ? measured->valueMm : provisional.midribMm) / 2});
      usedProvisional = usedProvisional || !measured;
      m::Vein midrib{"midrib", m::BallBSplineCurve::interpolate(balls)};
      if (!p.model.veins.empty() && p.model.veins.front().name == "midrib")
        p.model.veins.front() = std::move(midrib);
      else
        p.model.veins.insert(p.model.veins.begin(), std::move(midrib));
    }
    for (const double e : kPreviewLevelsMm) {
      if (!meshes) break;
      m::MeshOptions o;
      o.method = m::MeshMethod::Adaptive;
      o.resolution = m::MeshResolution::preset("preview");
      o.maxErrorMm = e;
      p.levels.push_back({e, m::meshLeaf(p.model, o)});
    }
    if (!p.levels.empty()) p.mesh = p.levels.back().mesh;
  } catch (const std::exception& e) {
    // Coincident markers and the like: the operator sees the note; the capture goes on
    // (validation already refused what it can, and undo/retake fix the rest).
    p.notes.push_back(std::string("preview not built: ") + e.what());
    p.model = {};
    p.mesh = {};
    p.levels.clear();
  }
  p.model.markers = set;
  p.provisionalThickness = usedProvisional;
  return p;
}

}  // namespace leafdig::acquisition
