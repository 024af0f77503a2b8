#include "leafdig/acquisition/session/preview.hpp"

#include <Eigen/Geometry>

#include "leafdig/acquisition/protocol/point_rules.hpp"
#include "leafdig/model/errors.hpp"
#include "leafdig/model/mesh/mesh_method.hpp"

namespace leafdig::acquisition {
namespace m = leafdig::model;

Preview buildPreview(const std::vector<Item>& items, const Settings& settings, const ProvisionalThickness& provisional,
                     bool meshes) {
  Preview p;
  const Item* tip = findItem(items, What::Tip, 0, 0);
  if (!tip) return p;
  bool usedProvisional = false;
  m::MarkerSet set = partialMarkerSet(items, settings, &provisional, usedProvisional);
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
      balls.push_back(
          {frame * rules::toPoint(mid->positionMm), (measured ? measured->valueMm : provisional.midribMm) / 2});
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
