// PlantEngine's steps and prompts (plant_engine.hpp): what the technician does next, in words.
#include <string>

#include "leafdig/acquisition/protocol/plant_engine.hpp"

namespace leafdig::acquisition {

namespace {

namespace m = leafdig::model;

std::string num(int v) {
  return std::to_string(v);
}

// What a quick leaf's point is, in the technician's words.
std::string quickHint(const std::string& name, int part) {
  if (part == 1) return name + " (where the blade joins the petiole)";
  if (part == 2) return name + " (the leaf's tip)";
  return name + " (the widest point of one margin)";
}

}  // namespace

std::optional<PlantStep> PlantEngine::nodeStep(int node) const {
  const m::ProtocolEntity& entity = axisOf(node);
  for (int p = 1; p <= static_cast<int>(entity.points.size()); ++p)
    if (!find(PlantWhat::Point, node, p)) return PlantStep{PlantWhat::Point, node, p, {}};
  for (int r = 1; r <= static_cast<int>(entity.readings.size()); ++r)
    if (!find(PlantWhat::Reading, node, r)) return PlantStep{PlantWhat::Reading, node, r, {}};
  if (!leafEntityOf(node)) return std::nullopt;
  switch (choiceFor(node).kind) {
    case m::LeafKind::Full: {
      const Engine* e = leaf(node);
      if (!e) return PlantStep{PlantWhat::Leaf, node, 0, Step{What::Tip, 0, 0}};
      if (!e->complete()) return PlantStep{PlantWhat::Leaf, node, 0, e->step()};
      break;
    }
    case m::LeafKind::Quick:
      for (int q = 1; q <= 3; ++q)
        if (!find(PlantWhat::QuickPoint, node, q)) return PlantStep{PlantWhat::QuickPoint, node, q, {}};
      break;
    case m::LeafKind::None: break;
  }
  return std::nullopt;
}

PlantStep PlantEngine::step() const {
  if (relocating_) {
    // The landmarks again, in number order, after moving the transmitter; then the fit.
    for (int k = 1; k <= lastLandmark(); ++k)
      if (find(PlantWhat::Landmark, k, 0) && !find(PlantWhat::LandmarkAgain, k, relocating_))
        return {PlantWhat::LandmarkAgain, k, relocating_, {}};
    return {PlantWhat::LandmarkAgain, 0, relocating_, {}};
  }
  if (retake_) return *retake_;
  // A landmark taken out by a retake and then undone is asked for again at its number.
  for (int k = 1; k < lastLandmark(); ++k)
    if (!find(PlantWhat::Landmark, k, 0)) return {PlantWhat::Landmark, k, 0, {}};
  if (!landmarksEnded_ && landmarks() < protocol_.maxLandmarks) return {PlantWhat::Landmark, landmarks() + 1, 0, {}};
  if (!find(PlantWhat::Collar, 0, 0)) return {PlantWhat::Collar, 0, 0, {}};
  if (protocol_.collarDiameter && !find(PlantWhat::CollarDiameter, 0, 0)) return {PlantWhat::CollarDiameter, 0, 0, {}};
  // A full leaf being retaken has the stylus wherever the capture is.
  for (const auto& [node, e] : leaves_)
    if (e.retaking()) return {PlantWhat::Leaf, node, 0, e.step()};
  const int last = lastNode();
  for (int node = 1;; ++node) {
    if (!find(PlantWhat::Point, node, 1) && plantEnded_ && node > last) return {PlantWhat::Done, 0, 0, {}};
    if (auto s = nodeStep(node)) return *s;
  }
}

int PlantEngine::leafNode() const {
  const PlantStep s = step();
  return s.what == PlantWhat::Leaf ? s.index : 0;
}

std::string PlantEngine::pointName(const PlantStep& s) const {
  switch (s.what) {
    case PlantWhat::Point: return axisOf(s.index).points[static_cast<std::size_t>(s.part - 1)];
    case PlantWhat::Reading: return axisOf(s.index).readings[static_cast<std::size_t>(s.part - 1)];
    case PlantWhat::QuickPoint: return leafEntityOf(s.index)->leaf->quickPoints[static_cast<std::size_t>(s.part - 1)];
    default: return toString(s.what);
  }
}

std::string PlantEngine::prompt() const {
  const PlantStep s = step();
  const std::string again = retake_ ? "Retake · " : "";  // as a leaf's prompt says it
  const std::string node = again + "Node " + num(s.index) + " · ";
  switch (s.what) {
    case PlantWhat::Landmark: {
      std::string p = again + "Landmark " + num(s.index) + " · a mark on the pot rim (or the board)";
      if (!retake_ && s.index > protocol_.minLandmarks) p += "  (or hold the button to end the landmarks)";
      return p;
    }
    case PlantWhat::Collar: return again + "Collar · the stem at soil level";
    case PlantWhat::CollarDiameter: return again + "Collar · stem diameter with the caliper";
    case PlantWhat::Point: {
      const m::NodeLink l = link(s.index);
      if (l.order > 1) {
        std::string p = node + pointName(s) + " on the branch";
        if (l.relation == '+') p += " from node " + num(l.parent);
        if (!retake_ && s.part == 1 && l.relation != '+') p += "  (or hold the button to end the branch)";
        return p;
      }
      std::string p = node + pointName(s) + " on the stem";
      if (l.parent != s.index - 1) p += " after node " + num(l.parent);
      if (!retake_ && s.part == 1 && s.index > 1) p += "  (or hold the button to end the plant)";
      return p;
    }
    case PlantWhat::Reading:
      return node + (link(s.index).order > 1 ? "branch " : "stem ") + pointName(s) + " with the caliper";
    case PlantWhat::QuickPoint: return node + "quick leaf · " + quickHint(pointName(s), s.part);
    case PlantWhat::Leaf: {
      const Engine* e = leaf(s.index);
      return node + "leaf · " + (e ? e->prompt() : Engine(settings_).prompt());
    }
    case PlantWhat::Done: return "Plant complete";
    case PlantWhat::LandmarkAgain: {
      if (s.index == 0) return "Transmitter moved · every landmark taken again: hold the button (or End) to fit";
      int again = 0;
      for (const PlantItem& i : items_) again += i.what == PlantWhat::LandmarkAgain && i.part == s.part;
      std::string p = "Transmitter moved · landmark " + num(s.index) + " again";
      if (again >= 3) p += "  (or hold the button to fit)";
      return p;
    }
  }
  return "";
}

}  // namespace leafdig::acquisition
