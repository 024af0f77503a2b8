#include "leafdig/model/plant/surveyed_plant.hpp"

#include <cmath>
#include <limits>
#include <map>

#include "leaf_shaping.hpp"
#include "leafdig/model/errors.hpp"
#include "leafdig/model/mesh/mesh.hpp"
#include "leafdig/model/metrics/blade_area.hpp"

namespace leafdig::model {

namespace {

// Chord length over width of a leaf in its own frame (origin at the base).
double aspect(const MarkerSet& leafFrame) {
  const double width = bladeWidthMm(leafFrame);
  return width > 0.0 ? leafFrame.tipMm.norm() / width : 0.0;
}

struct Shape {
  const MarkerSet* leafFrame;
  std::string source;
};

// The library leaf of the quick leaf's type nearest its aspect, else the fallback (the last
// of `frames`).
Shape shapeFor(const SurveyedLeaf& leaf, const std::vector<MarkerSet>& frames, const std::vector<LibraryLeaf>& library,
               const std::string& fallbackSource) {
  const double want = leaf.pose->lengthMm / leaf.pose->widthMm.value_or(leaf.pose->lengthMm);
  const MarkerSet* best = nullptr;
  std::string source;
  double gap = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < library.size(); ++i) {
    if (!leaf.type.empty() && library[i].markers.leaf.type != leaf.type) continue;
    const double d = std::abs(aspect(frames[i]) - want);
    if (d < gap) {
      gap = d;
      best = &frames[i];
      source = "library: " + library[i].source;
    }
  }
  if (best) return {best, source};
  return {&frames.back(),
          fallbackSource + (leaf.type.empty() ? std::string(", the library is empty")
                                              : ", no approved leaf of type \"" + leaf.type + "\" in the library")};
}

// The shape stretched in its frame so that its chord and its widest row measure the quick
// leaf's (a fixed point: the stretch moves what it measures a little off the axes).
MarkerSet stretched(const MarkerSet& leafFrame, double lengthMm, double widthMm) {
  double lengthFactor = 1.0;
  double widthFactor = 1.0;
  MarkerSet shaped = leafFrame;
  for (int k = 0; k < 4; ++k) {
    lengthFactor *= lengthMm / shaped.tipMm.norm();
    widthFactor *= widthMm / bladeWidthMm(shaped);
    shaped = detail::shapeLeaf(leafFrame, 1.0, lengthFactor, widthFactor, 0.0);
  }
  return shaped;
}

// The rigid motion laying a shaped leaf (in its frame) on a quick leaf's three points.
Eigen::Isometry3d onPoints(const MarkerSet& shaped, const SurveyedLeaf& leaf) {
  const Eigen::Vector3d a = shaped.tipMm.normalized();
  const Eigen::Vector3d b = (Eigen::Vector3d::UnitX() - Eigen::Vector3d::UnitX().dot(a) * a).normalized();
  Eigen::Matrix3d inLeaf;
  inLeaf << a, b, b.cross(a);
  const Eigen::Vector3d aw = (*leaf.tipMm - *leaf.baseMm).normalized();
  const Eigen::Vector3d side = *leaf.sideMm - *leaf.baseMm;
  Eigen::Vector3d bw = (side - side.dot(aw) * aw).normalized();
  if (bw.cross(aw).z() < 0.0) bw = -bw;  // the adaxial side up, whichever margin was touched
  Eigen::Matrix3d inPlant;
  inPlant << aw, bw, bw.cross(aw);
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() = inPlant * inLeaf.transpose();
  t.translation() = *leaf.baseMm;
  return t;
}

}  // namespace

Plant surveyedPlant(const PlantSurvey& survey, const std::vector<LibraryLeaf>& library, const LibraryLeaf& fallback) {
  Plant plant;
  plant.id = survey.plant.empty() ? "plant" : survey.plant;
  // Each axis' balls: the main stem's from the collar, a branch's from the node bearing it
  // (with the branch's first diameter), then its nodes in order.
  std::map<int, std::vector<Ball>> axes;  // by the axis' first node
  axes[1].push_back({Eigen::Vector3d::Zero(), survey.collarDiameterMm / 2});
  for (const SurveyedNode& n : survey.nodes) {
    std::vector<Ball>& balls = axes[n.link.axis];
    if (balls.empty())
      balls.push_back({survey.nodes.at(static_cast<std::size_t>(n.link.parent) - 1).pointMm, n.diameterMm / 2});
    balls.push_back({n.pointMm, n.diameterMm / 2});
  }
  plant.stemBaseDiameterMm = survey.collarDiameterMm;
  for (const SurveyedNode& n : survey.nodes)
    if (n.link.axis == 1) {
      plant.stemHeightMm = n.heightMm;
      plant.stemTopDiameterMm = n.diameterMm;
    }
  if (!survey.nodes.empty()) {
    for (const auto& [first, balls] : axes) {
      Vein axis{first == 1 ? "stem" : "branch-" + std::to_string(first), BallBSplineCurve::interpolate(balls)};
      if (first == 1)
        plant.stem = std::move(axis);
      else
        plant.branches.push_back(std::move(axis));
    }
  }

  std::vector<MarkerSet> frames;  // the library's leaves (and the fallback, last) in their own frames, once
  bool framed = false;
  for (const SurveyedLeaf& s : survey.leaves) {
    if (!s.pose || !s.baseMm || !s.tipMm) continue;  // no points: no leaf to draw
    PlacedLeaf leaf;
    leaf.rank = s.node;
    leaf.insertionHeightMm = survey.nodes.at(static_cast<std::size_t>(s.node) - 1).heightMm;
    leaf.azimuthDeg = s.pose->azimuthDeg;
    leaf.inclinationDeg = s.pose->inclinationDeg;
    leaf.rollDeg = s.pose->rollDeg.value_or(0.0);
    try {
      if (s.kind == LeafKind::Full && s.markers) {
        leaf.source = "digitized";
        leaf.model = buildLeafModel(*s.markers);
        leaf.placement = leafFrameFromDigitizer(leaf.model).inverse();
        leaf.widthMm = bladeWidthMm(*s.markers);
      } else if (s.kind == LeafKind::Quick && s.sideMm && s.pose->widthMm) {
        if (!framed) {
          for (const LibraryLeaf& l : library) frames.push_back(detail::toLeafFrame(l.markers));
          frames.push_back(detail::toLeafFrame(fallback.markers));
          framed = true;
        }
        const Shape shape = shapeFor(s, frames, library, fallback.source);
        const MarkerSet shaped = stretched(*shape.leafFrame, s.pose->lengthMm, *s.pose->widthMm);
        leaf.source = shape.source;
        leaf.shapeDigitized = false;
        leaf.lengthFactor = shaped.tipMm.norm() / shape.leafFrame->tipMm.norm();
        leaf.widthFactor = bladeWidthMm(shaped) / bladeWidthMm(*shape.leafFrame);
        leaf.placement = onPoints(shaped, s);
        leaf.model = transformed(buildLeafModel(shaped), leaf.placement);
        leaf.widthMm = bladeWidthMm(shaped);
      } else {
        continue;
      }
    } catch (const InputError& e) {
      throw InputError("node " + std::to_string(s.node) + "'s leaf: " + e.what());
    }
    leaf.base = leaf.model.markers.rows.back().pointsMm[kMidribColumn];
    leaf.tip = leaf.model.markers.tipMm;
    leaf.lengthMm = midribLengthMm(leaf.model);
    plant.leaves.push_back(std::move(leaf));
  }
  return plant;
}

void addDrawnAreas(PlantSurvey& survey, const std::vector<LibraryLeaf>& library, const LibraryLeaf& fallback) {
  if (!hasQuickLeaf(survey)) return;
  const Plant drawn = surveyedPlant(survey, library, fallback);
  for (const PlacedLeaf& placed : drawn.leaves) {
    if (placed.shapeDigitized) continue;
    for (SurveyedLeaf& leaf : survey.leaves)
      if (leaf.node == placed.rank && leaf.kind == LeafKind::Quick) {
        leaf.areaMm2 = convergedBladeArea(placed.model.blade, Eigen::Vector3d::UnitZ()).areaMm2;
        leaf.areaShape = placed.source;
      }
  }
}

}  // namespace leafdig::model
