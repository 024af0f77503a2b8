#include "leafdig/acquisition/sim/truth.hpp"

#include <cmath>
#include <variant>

namespace leafdig::acquisition {

namespace {

Vec3 vec(const Eigen::Vector3d& p) {
  return {p.x(), p.y(), p.z()};
}

const model::PlantNode* nodeOf(const model::PlantMarkers& plant, int node) {
  return node >= 1 && node <= static_cast<int>(plant.nodes.size()) ? &plant.nodes[static_cast<std::size_t>(node - 1)]
                                                                   : nullptr;
}

}  // namespace

Vec3 leafPointTruth(const model::MarkerSet& leaf, What w, int row, int col) {
  if (w == What::Board) {
    const double x = col == 2 ? 150.0 : -150.0, y = col == 3 ? 150.0 : -150.0;
    return {x, y, -5.0};
  }
  if (w == What::Tip || row < 1 || row > static_cast<int>(leaf.rows.size())) return vec(leaf.tipMm);
  return vec(leaf.rows[static_cast<std::size_t>(row - 1)].pointsMm[static_cast<std::size_t>(col - 1)]);
}

double leafReadingTruth(const model::MarkerSet& leaf, What w, int row, int col) {
  const model::MarkerRow* r =
      row >= 1 && row <= static_cast<int>(leaf.rows.size()) ? &leaf.rows[static_cast<std::size_t>(row - 1)] : nullptr;
  switch (w) {
    case What::MidribThickness: return r && r->midribThicknessMm ? *r->midribThicknessMm : 1.2;
    case What::VeinOriginThickness: return r && r->veinOriginThicknessMm ? *r->veinOriginThicknessMm : 0.6;
    case What::EdgeThickness:
      return leaf.edgeThicknessMm                                 ? *leaf.edgeThicknessMm
             : !leaf.rows.empty() && leaf.rows[0].edgeThicknessMm ? *leaf.rows[0].edgeThicknessMm
                                                                  : 0.25;
    case What::PointThickness: {
      if (r && r->measuredThicknessMm[static_cast<std::size_t>(col - 1)])
        return *r->measuredThicknessMm[static_cast<std::size_t>(col - 1)];
      const double d = leafReadingTruth(leaf, What::EdgeThickness, 0, 0);
      const double o = leafReadingTruth(leaf, What::VeinOriginThickness, row, 4);
      const double f = std::abs(col - 4) / 3.0;
      return f * d + (1 - f) * o;
    }
    default: return 1.0;
  }
}

std::optional<Vec3> plantPointTruth(const model::PlantMarkers& plant, const PlantStep& s) {
  switch (s.what) {
    case PlantWhat::Landmark:
    case PlantWhat::LandmarkAgain:  // the same mark on the pot, wherever the transmitter is now
      if (s.index < 1 || s.index > static_cast<int>(plant.landmarksMm.size())) return std::nullopt;
      return vec(plant.landmarksMm[static_cast<std::size_t>(s.index - 1)]);
    case PlantWhat::Collar: return vec(plant.collarMm);
    case PlantWhat::Point: {
      const model::PlantNode* n = nodeOf(plant, s.index);
      if (!n) return std::nullopt;
      return vec(n->pointMm);  // a plant-markers file knows one point per node
    }
    case PlantWhat::QuickPoint: {
      const model::PlantNode* n = nodeOf(plant, s.index);
      const auto* q = n ? std::get_if<model::QuickLeaf>(&n->leaf) : nullptr;
      if (!q) return std::nullopt;
      return vec(s.part == 1 ? q->baseMm : s.part == 2 ? q->tipMm : q->sideMm);
    }
    case PlantWhat::Leaf: {
      const model::MarkerSet* leaf = plantLeafTruth(plant, s.index);
      if (!leaf) return std::nullopt;
      return leafPointTruth(*leaf, s.leaf.what, s.leaf.row, s.leaf.col);
    }
    default: return std::nullopt;
  }
}

double plantReadingTruth(const model::PlantMarkers& plant, const PlantStep& s) {
  if (s.what == PlantWhat::CollarDiameter) return plant.collarDiameterMm;
  if (s.what == PlantWhat::Leaf)
    if (const model::MarkerSet* leaf = plantLeafTruth(plant, s.index))
      return leafReadingTruth(*leaf, s.leaf.what, s.leaf.row, s.leaf.col);
  const model::PlantNode* n = nodeOf(plant, s.index);
  return n ? n->diameterMm : 0.0;
}

std::optional<NodePlace> plantPlacementTruth(const model::PlantMarkers& plant, int node, const model::NodeLink& now) {
  if (node < 1 || node > static_cast<int>(plant.nodes.size())) return std::nullopt;
  const model::NodeLink where = model::plantTopology(plant.nodes, plant.plant)[static_cast<std::size_t>(node - 1)];
  if (where.relation == '+' && (now.relation != '+' || now.parent != where.parent)) return NodePlace{where.parent, '+'};
  if (where.relation == '<' && where.order == 1 && now.order > 1) return NodePlace{where.parent, '<'};
  return std::nullopt;
}

LeafChoice plantChoiceTruth(const model::PlantMarkers& plant, int node) {
  const model::PlantNode* n = nodeOf(plant, node);
  if (!n) return {};
  LeafChoice c;
  c.state = n->state;
  if (std::holds_alternative<model::MarkerSet>(n->leaf)) c.kind = model::LeafKind::Full;
  if (const auto* quick = std::get_if<model::QuickLeaf>(&n->leaf)) {
    c.kind = model::LeafKind::Quick;
    c.type = quick->type;
  }
  if (const auto* full = std::get_if<model::MarkerSet>(&n->leaf)) c.type = full->leaf.type;
  return c;
}

const model::MarkerSet* plantLeafTruth(const model::PlantMarkers& plant, int node) {
  const model::PlantNode* n = nodeOf(plant, node);
  return n ? std::get_if<model::MarkerSet>(&n->leaf) : nullptr;
}

}  // namespace leafdig::acquisition
