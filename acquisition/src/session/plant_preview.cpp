#include "leafdig/acquisition/session/plant_preview.hpp"

#include <exception>
#include <utility>

#include "leafdig/model/errors.hpp"
#include "leafdig/model/plant/plant_survey.hpp"
#include "leafdig/model/plant/surveyed_plant.hpp"
#include "leafdig/model/synth/synthetic_leaf.hpp"

namespace leafdig::acquisition {

namespace m = leafdig::model;

namespace {

Eigen::Vector3d at(const Vec3& v) {
  return {v[0], v[1], v[2]};
}

Vec3 vec(const Eigen::Vector3d& v) {
  return {v.x(), v.y(), v.z()};
}

// Landmarks, collar, node points and quick points as markers: row the landmark or node, col
// which point of it (the collar is row 0); then the full leaves' markers.
std::vector<Item> pointsOf(const PlantEngine& engine, const m::PlantFrame* frame) {
  std::vector<Item> out;
  for (const PlantItem& i : engine.items()) {
    if (!isStylusItem(i.what)) continue;
    Item item;
    item.what = What::Marker;
    item.row = i.index;
    item.col = i.what == PlantWhat::Landmark ? 0 : i.part;
    item.positionMm = frame ? vec(frame->point(at(i.positionMm))) : i.positionMm;
    out.push_back(item);
  }
  // Each full leaf's markers (row: the node; col: 100 + the marker's order), so that a view
  // framed on the points holds the leaves too.
  for (int node = 1; node <= engine.nodes(); ++node) {
    const Engine* leaf = engine.leaf(node);
    if (!leaf) continue;
    int k = 0;
    for (const Item& i : leaf->items()) {
      if (i.what != What::Tip && i.what != What::Marker) continue;
      Item item;
      item.what = What::Marker;
      item.row = node;
      item.col = 100 + k++;
      item.positionMm = frame ? vec(frame->point(at(i.positionMm))) : i.positionMm;
      out.push_back(item);
    }
  }
  return out;
}

// The full leaf's live preview moved into the plant frame, as organs of leaf `node`.
void addLeafUnderCapture(m::LeafMesh& into, const Preview& leaf, int node, const m::PlantFrame& frame) {
  for (const m::Organ& o : leaf.mesh.organs) {
    m::Organ moved = o;
    moved.name = "plant/leaf-" + std::to_string(node) + "/" + o.name;
    moved.leafRank = node;
    for (Eigen::Vector3d& p : moved.mesh.positions) p = frame.point(p);
    for (Eigen::Vector3d& n : moved.mesh.normals) n = frame.direction(n);
    into.organs.push_back(std::move(moved));
  }
}

}  // namespace

PlantPreviewer::PlantPreviewer(std::vector<m::LibraryLeaf> library) : library_(std::move(library)) {}

PlantPreview buildPlantPreview(const PlantEngine& engine, const std::vector<m::LibraryLeaf>& library) {
  return PlantPreviewer(library).build(engine);
}

PlantPreview PlantPreviewer::build(const PlantEngine& engine) {
  PlantPreview out;
  const PlantStep step = engine.step();
  if (step.what == PlantWhat::Leaf) {
    if (const Engine* leaf = engine.leaf(step.index)) {
      out.leafNode = step.index;
      out.leafItems = leaf->items();
      out.leaf = std::make_shared<const Preview>(buildPreview(leaf->items(), engine.leafSettings()));
    }
  }
  m::PlantMarkers captured = engine.captured("plant");
  if (captured.nodes.empty() || captured.landmarksMm.size() < 3) {
    out.points = pointsOf(engine, nullptr);
    out.notes.emplace_back("the plant frame is made once the landmarks, the collar and the first node are taken");
    return out;
  }
  // A diameter not read yet: the one below it, for the drawing only.
  double below = captured.collarDiameterMm;
  for (std::size_t i = 0; i < captured.nodes.size(); ++i) {
    m::PlantNode& n = captured.nodes[i];
    if (n.diameterMm <= 0.0) {
      if (below > 0.0)
        out.notes.push_back("node " + std::to_string(i + 1) + ": stem diameter not read yet, drawn as the one below");
      n.diameterMm = below > 0.0 ? below : 1.0;
    }
    below = n.diameterMm;
  }
  if (captured.collarDiameterMm <= 0.0) captured.collarDiameterMm = captured.nodes.front().diameterMm;
  // The stem and the frame: the nodes without their leaves.
  m::PlantMarkers bare = captured;
  for (m::PlantNode& n : bare.nodes) n.leaf = std::monostate{};
  m::PlantSurvey survey;
  try {
    survey = m::surveyPlant(bare);
  } catch (const std::exception& e) {
    out.notes.emplace_back(e.what());
    out.points = pointsOf(engine, nullptr);
    return out;
  }
  out.inPlantFrame = true;
  out.points = pointsOf(engine, &survey.frame);
  const m::LibraryLeaf sample{m::kSampleShapeSource, m::sampleLeafShape()};
  try {
    out.mesh = m::meshPlant(m::surveyedPlant(survey, library_, sample), m::MeshResolution::preset("preview"));
  } catch (const std::exception& e) {
    out.notes.emplace_back(e.what());
  }
  // Each leaf on its own, in node order (as the plant's mesh has them): the frame and the
  // node's leaf are its key; an unchanged leaf's organs are reused.
  std::map<int, CachedLeaf> kept;
  for (std::size_t i = 0; i < captured.nodes.size(); ++i) {
    const int node = static_cast<int>(i) + 1;
    const m::PlantNode& n = captured.nodes[i];
    if (std::holds_alternative<std::monostate>(n.leaf)) {
      if (node == out.leafNode && out.leaf && !out.leaf->mesh.organs.empty()) {
        addLeafUnderCapture(out.mesh, *out.leaf, node, survey.frame);
        ++out.leaves;
      }
      continue;
    }
    // The plant up to this node, with this node's leaf alone; its key is what the leaf's
    // placement depends on: the frame (landmarks, collar, the first node) and the node itself.
    m::PlantMarkers one = bare;
    one.nodes.resize(i + 1);
    one.nodes[i].leaf = n.leaf;
    one.nodes[i].state = n.state;
    m::PlantMarkers keyOf = one;
    keyOf.nodes = {one.nodes.front()};
    if (i > 0) keyOf.nodes.push_back(one.nodes[i]);
    std::string key = m::plantMarkersToJson(keyOf);
    CachedLeaf leaf;
    if (auto found = leaves_.find(node); found != leaves_.end() && found->second.key == key) {
      leaf = std::move(found->second);
      ++reused_;
    } else {
      leaf.key = std::move(key);
      try {
        const m::Plant plant = m::surveyedPlant(m::surveyPlant(one), library_, sample);
        for (m::Organ& o : m::meshPlant(plant, m::MeshResolution::preset("preview")).organs)
          if (o.leafRank == node) leaf.organs.push_back(std::move(o));
      } catch (const std::exception& e) {
        leaf.note = e.what();
      }
    }
    if (!leaf.note.empty()) out.notes.push_back(leaf.note);
    if (!leaf.organs.empty()) ++out.leaves;
    out.mesh.organs.insert(out.mesh.organs.end(), leaf.organs.begin(), leaf.organs.end());
    kept.emplace(node, std::move(leaf));
  }
  leaves_ = std::move(kept);
  return out;
}

}  // namespace leafdig::acquisition
