#include "leafdig/model/plant/plant_survey.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <nlohmann/json.hpp>

#include "json_text.hpp"
#include "leafdig/model/errors.hpp"
#include "leafdig/model/leaf/leaf_model.hpp"
#include "leafdig/model/metrics/area_interval.hpp"
#include "leafdig/model/metrics/metrics.hpp"
#include "leafdig/model/plant/plant.hpp"

namespace leafdig::model {

using nlohmann::json;

namespace {

MarkerSet inFrame(const MarkerSet& markers, const PlantFrame& frame) {
  MarkerSet out = markers;
  out.tipMm = frame.point(markers.tipMm);
  for (MarkerRow& row : out.rows)
    for (Eigen::Vector3d& p : row.pointsMm) p = frame.point(p);
  return out;
}

std::string at(int node) {
  return "node " + std::to_string(node) + "'s leaf: ";
}

}  // namespace

bool hasQuickLeaf(const PlantSurvey& survey) {
  return std::any_of(survey.leaves.begin(), survey.leaves.end(),
                     [](const SurveyedLeaf& l) { return l.kind == LeafKind::Quick; });
}

PlantSurvey surveyPlant(const PlantMarkers& p) {
  // The plant frame's axis runs from the collar to the first node: no node, no plant yet.
  if (p.nodes.empty()) throw InputError("it has no node yet: the plant frame needs the collar and the first node");
  PlantSurvey s;
  s.plant = p.plant;
  s.date = p.date;
  s.collarDiameterMm = p.collarDiameterMm;
  s.frame = plantFrameFromLandmarks(p.landmarksMm, p.collarMm, p.nodes.front().pointMm - p.collarMm);
  const std::vector<NodeLink> links = plantTopology(p.nodes, p.plant.empty() ? "plant" : p.plant);
  std::map<int, double> lastAzimuths;  // by axis
  for (std::size_t i = 0; i < p.nodes.size(); ++i) {
    const PlantNode& n = p.nodes[i];
    const int index = static_cast<int>(i) + 1;
    SurveyedNode node;
    node.index = index;
    node.link = links[i];
    node.pointMm = s.frame.point(n.pointMm);
    node.diameterMm = n.diameterMm;
    node.heightMm = node.pointMm.z();
    const Eigen::Vector3d below = node.link.parent > 0 ? s.nodes[static_cast<std::size_t>(node.link.parent - 1)].pointMm
                                                       : Eigen::Vector3d::Zero();  // the collar, in the plant frame
    node.internodeMm = (node.pointMm - below).norm();
    s.nodes.push_back(node);

    SurveyedLeaf leaf;
    leaf.node = index;
    leaf.state = n.state;
    try {
      if (const auto* full = std::get_if<MarkerSet>(&n.leaf)) {
        leaf.kind = LeafKind::Full;
        MarkerSet m = inFrame(*full, s.frame);
        const LeafModel model = buildLeafModel(m);
        leaf.baseMm = m.rows.back().pointsMm[kMidribColumn];
        leaf.tipMm = m.tipMm;
        leaf.pose = leafPose(*leaf.baseMm, m.tipMm);
        leaf.pose->widthMm = bladeWidthMm(m);
        leaf.midribLengthMm = midribLengthMm(model);
        const LeafMetrics metrics = computeLeafMetrics(model, Eigen::Vector3d::UnitZ());
        leaf.areaMm2 = metrics.blade.areaMm2;
        if (metrics.areaInterval) {
          leaf.areaLow95Mm2 = metrics.areaInterval->low95Mm2;
          leaf.areaHigh95Mm2 = metrics.areaInterval->high95Mm2;
        }
        leaf.markers = std::move(m);
      } else if (const auto* quick = std::get_if<QuickLeaf>(&n.leaf)) {
        leaf.kind = LeafKind::Quick;
        leaf.baseMm = s.frame.point(quick->baseMm);
        leaf.tipMm = s.frame.point(quick->tipMm);
        leaf.sideMm = s.frame.point(quick->sideMm);
        leaf.type = quick->type;
        leaf.pose = leafPose(*leaf.baseMm, *leaf.tipMm, *leaf.sideMm);
      } else if (n.state != LeafState::Alive) {
        leaf.kind = LeafKind::None;
      } else {
        continue;  // no leaf at this node
      }
    } catch (const InputError& e) {
      throw InputError(at(index) + e.what());
    }
    if (leaf.pose) {
      if (const auto last = lastAzimuths.find(node.link.axis); last != lastAzimuths.end())
        leaf.divergenceDeg = divergenceDeg(last->second, leaf.pose->azimuthDeg);
      lastAzimuths[node.link.axis] = leaf.pose->azimuthDeg;
    }
    s.leaves.push_back(std::move(leaf));
  }
  return s;
}

namespace {

json optional(const std::optional<double>& v) {
  return v ? json(*v) : json();
}

json point(const Eigen::Vector3d& p) {
  return json::array({p.x(), p.y(), p.z()});
}

}  // namespace

std::string plantSurveyToJson(const PlantSurvey& s) {
  json matrix = json::array();
  const Eigen::Matrix4d m = s.frame.fromDigitizer.matrix();
  for (int r = 0; r < 4; ++r) matrix.push_back(json::array({m(r, 0), m(r, 1), m(r, 2), m(r, 3)}));
  json nodes = json::array();
  bool branched = false;
  for (const SurveyedNode& n : s.nodes) branched = branched || n.link.relation == '+';
  for (const SurveyedNode& n : s.nodes) {
    json j = {{"node", n.index},
              {"point_mm", point(n.pointMm)},
              {"diameter_mm", n.diameterMm},
              {"height_mm", n.heightMm},
              {"internode_mm", n.internodeMm}};
    if (branched) {  // a branched plant says where every node hangs
      j["parent"] = n.link.parent;
      j["relation"] = std::string(1, n.link.relation);
      j["order"] = n.link.order;
    }
    nodes.push_back(j);
  }
  json leaves = json::array();
  double sum = 0.0;
  int count = 0;
  for (const SurveyedLeaf& l : s.leaves) {
    json j = {{"node", l.node}, {"kind", toString(l.kind)}, {"state", toString(l.state)}};
    j["azimuth_deg"] = l.pose ? json(l.pose->azimuthDeg) : json();
    j["inclination_deg"] = l.pose ? json(l.pose->inclinationDeg) : json();
    j["chord_mm"] = l.pose ? json(l.pose->lengthMm) : json();
    j["width_mm"] = l.pose ? optional(l.pose->widthMm) : json();
    j["roll_deg"] = l.pose ? optional(l.pose->rollDeg) : json();
    j["midrib_length_mm"] = optional(l.midribLengthMm);
    j["area_mm2"] = optional(l.areaMm2);
    j["area_95_mm2"] = l.areaLow95Mm2 && l.areaHigh95Mm2 ? json::array({*l.areaLow95Mm2, *l.areaHigh95Mm2}) : json();
    j["area_shape"] = l.areaShape.empty() ? json() : json(l.areaShape);
    j["divergence_deg"] = optional(l.divergenceDeg);
    if (l.divergenceDeg) {
      sum += *l.divergenceDeg;
      ++count;
    }
    leaves.push_back(j);
  }
  json doc = {{"plant", s.plant},
              {"frame", {{"flatness_mm", s.frame.flatnessMm}, {"from_digitizer", matrix}}},
              {"collar_diameter_mm", s.collarDiameterMm},
              {"nodes", nodes},
              {"leaves", leaves},
              {"divergence", {{"count", count}, {"mean_deg", count ? json(sum / count) : json()}}}};
  if (s.date) doc["date"] = toIso(*s.date);
  return detail::dumpFinite(doc, 2);
}

}  // namespace leafdig::model
