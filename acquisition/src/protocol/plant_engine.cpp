#include "leafdig/acquisition/protocol/plant_engine.hpp"

#include <algorithm>
#include <cstdio>
#include <stdexcept>
#include <utility>

#include "leafdig/acquisition/protocol/point_rules.hpp"
#include "leafdig/model/errors.hpp"
#include "leafdig/model/limits.hpp"
#include "leafdig/model/plant/plant_frame.hpp"
#include "leafdig/names/name_table.hpp"

namespace leafdig::acquisition {

namespace {

namespace m = leafdig::model;

constexpr NameTable<PlantWhat, 9> kPlantWhatNames{{{PlantWhat::Landmark, "landmark"},
                                                   {PlantWhat::Collar, "collar"},
                                                   {PlantWhat::CollarDiameter, "collar_diameter"},
                                                   {PlantWhat::Point, "point"},
                                                   {PlantWhat::Reading, "reading"},
                                                   {PlantWhat::QuickPoint, "quick_point"},
                                                   {PlantWhat::Leaf, "leaf"},
                                                   {PlantWhat::Done, "done"},
                                                   {PlantWhat::LandmarkAgain, "landmark_again"}}};

std::string num(int v) {
  return std::to_string(v);
}

rules::Point at(const PlantItem& i) {
  return rules::toPoint(i.positionMm);
}

}  // namespace

const char* toString(PlantWhat w) {
  return nameIn(kPlantWhatNames, w);
}

PlantWhat plantWhatFromString(const std::string& s) {
  return parseName(kPlantWhatNames, s, "plant item");
}

bool isStylusItem(PlantWhat w) {
  return w == PlantWhat::Landmark || w == PlantWhat::Collar || w == PlantWhat::Point || w == PlantWhat::QuickPoint ||
         w == PlantWhat::LandmarkAgain;
}

PlantEngine::PlantEngine(m::PlantProtocol protocol, Settings leafSettings)
    : protocol_(std::move(protocol)), settings_(leafSettings) {
  settings_.boardFrame = false;                               // a full leaf is taken where it hangs, in the plant frame
  relocation_.toleranceMm = settings_.relocationToleranceMm;  // the session's, like every other rule
  // First the axes (order 1, the stem; order 2, a branch), then the leaves hanging on them.
  for (std::size_t k = 0; k < protocol_.entities.size(); ++k) {
    const m::ProtocolEntity& e = protocol_.entities[k];
    if (e.leaf) continue;
    if (e.order > 2)
      throw std::invalid_argument("the protocol's \"" + e.name + "\" is an axis of order " + num(e.order) +
                                  ": plant capture takes the main stem and branches from it (order 2); digitize "
                                  "a branch's branches as a plant of their own");
    int& slot = axisIndex_[e.order - 1];
    if (slot >= 0)
      throw std::invalid_argument("the protocol lists two " + std::string(e.order == 1 ? "stem" : "branch") +
                                  " entities (\"" + protocol_.entities[static_cast<std::size_t>(slot)].name +
                                  "\" and \"" + e.name +
                                  "\"): plant capture takes one entity node by node on each axis");
    slot = static_cast<int>(k);
  }
  if (axisIndex_[0] < 0 || !axis().repeat || axis().points.empty())
    throw std::invalid_argument(
        "the protocol has no stem entity taken node by node with a point (\"repeat\": true, \"points\": [\"node\"])");
  if (axisIndex_[1] >= 0 && (!axis(2).repeat || axis(2).points.empty() || axis(2).parent != axis().name))
    throw std::invalid_argument("the protocol's branch \"" + axis(2).name + "\" must hang on \"" + axis().name +
                                "\" and be taken node by node with a point (\"repeat\": true, \"points\": [\"node\"])");
  for (std::size_t k = 0; k < protocol_.entities.size(); ++k) {
    const m::ProtocolEntity& e = protocol_.entities[k];
    if (!e.leaf) continue;
    const int order = e.parent == axis().name ? 1 : axisIndex_[1] >= 0 && e.parent == axis(2).name ? 2 : 0;
    if (order == 0)
      throw std::invalid_argument("the protocol's leaf \"" + e.name + "\" does not hang on \"" + axis().name + "\"" +
                                  (axisIndex_[1] >= 0 ? " or \"" + axis(2).name + "\"" : std::string()));
    int& slot = leafIndex_[order - 1];
    if (slot >= 0)
      throw std::invalid_argument("the protocol hangs two leaf entities (\"" +
                                  protocol_.entities[static_cast<std::size_t>(slot)].name + "\" and \"" + e.name +
                                  "\") on its " + (order == 1 ? "nodes" : "branch nodes") +
                                  ": plant capture takes one leaf per node");
    slot = static_cast<int>(k);
  }
}

const m::ProtocolEntity& PlantEngine::axis(int order) const {
  return protocol_.entities[static_cast<std::size_t>(axisIndex_[order - 1])];
}

const m::ProtocolEntity* PlantEngine::leafEntity(int order) const {
  const int k = leafIndex_[order - 1];
  return k < 0 ? nullptr : &protocol_.entities[static_cast<std::size_t>(k)];
}

void PlantEngine::relink() {
  placedLinks_.clear();
  if (places_.empty()) return;
  std::vector<m::PlantNode> nodes(static_cast<std::size_t>(places_.rbegin()->first));
  for (const auto& [node, where] : places_) {
    m::PlantNode& n = nodes[static_cast<std::size_t>(node - 1)];
    if (where.relation == '+')
      n.branchesFrom = where.parent;
    else
      n.after = where.parent;
  }
  placedLinks_ = m::plantTopology(nodes, "the capture");  // place() let in only what holds
}

m::NodeLink PlantEngine::link(int node) const {
  if (node < 1) return {};
  const auto placed = static_cast<int>(placedLinks_.size());
  if (node <= placed) return placedLinks_[static_cast<std::size_t>(node - 1)];
  // Past the last placed node each follows the one before, on its axis.
  m::NodeLink l{node - 1, '<', 1, 1};
  if (placed > 0) {
    l.order = placedLinks_.back().order;
    l.axis = placedLinks_.back().axis;
  }
  return l;
}

const m::ProtocolEntity& PlantEngine::axisOf(int node) const {
  return axis(link(node).order);
}

const m::ProtocolEntity* PlantEngine::leafEntityOf(int node) const {
  return leafEntity(link(node).order);
}

int PlantEngine::mainLast() const {
  for (int k = nodes(); k >= 1; --k)
    if (link(k).order == 1) return k;
  return 0;
}

const PlantItem* PlantEngine::find(PlantWhat w, int index, int part) const {
  if (!foundValid_) {
    found_.clear();
    for (std::size_t k = 0; k < items_.size(); ++k)
      found_.emplace(std::make_tuple(static_cast<int>(items_[k].what), items_[k].index, items_[k].part), k);
    foundValid_ = true;
  }
  const auto it = found_.find({static_cast<int>(w), index, part});
  return it == found_.end() ? nullptr : &items_[it->second];
}

int PlantEngine::landmarks() const {
  int n = 0;
  for (const PlantItem& i : items_) n += i.what == PlantWhat::Landmark;
  return n;
}

int PlantEngine::lastLandmark() const {
  int n = 0;
  for (const PlantItem& i : items_)
    if (i.what == PlantWhat::Landmark) n = std::max(n, i.index);
  return n;
}

int PlantEngine::lastNode() const {
  int n = 0;
  for (const PlantItem& i : items_)
    if (i.what == PlantWhat::Point || i.what == PlantWhat::Reading || i.what == PlantWhat::QuickPoint)
      n = std::max(n, i.index);
  return n;
}

std::vector<Eigen::Vector3d> PlantEngine::landmarkPoints(const Eigen::Vector3d* extra, int extraIndex) const {
  std::vector<Eigen::Vector3d> out;
  const int last = std::max(lastLandmark(), extra ? extraIndex : 0);
  for (int k = 1; k <= last; ++k) {
    if (extra && k == extraIndex)
      out.push_back(*extra);
    else if (const PlantItem* i = find(PlantWhat::Landmark, k, 0))
      out.push_back(at(*i));
  }
  return out;
}

bool PlantEngine::retaking() const {
  if (retake_) return true;
  for (const auto& [node, e] : leaves_)
    if (e.retaking()) return true;
  return false;
}

int PlantEngine::nodes() const {
  int n = 0;
  while (find(PlantWhat::Point, n + 1, 1)) ++n;
  return n;
}

const Engine* PlantEngine::leaf(int node) const {
  const auto it = leaves_.find(node);
  return it == leaves_.end() ? nullptr : &it->second;
}

Engine& PlantEngine::leafEngine(int node) {
  return leaves_.try_emplace(node, settings_).first->second;
}

LeafChoice PlantEngine::choiceFor(int node) const {
  if (const auto it = choices_.find(node); it != choices_.end()) return it->second;
  const m::ProtocolEntity* leafIs = leafEntityOf(node);
  if (!leafIs) return {};
  const m::ProtocolLeaf& p = *leafIs->leaf;
  // Every k-th node of its axis (on a plant without branches, its number).
  int rank = node;
  if (!places_.empty()) {
    const int axisOfNode = link(node).axis;
    rank = 0;
    for (int k = 1; k <= node; ++k) rank += link(k).axis == axisOfNode;
  }
  const bool kth = p.fullEvery > 0 && rank % p.fullEvery == 0;
  if (kth && p.allows(m::LeafKind::Full)) return {m::LeafKind::Full, m::LeafState::Alive, {}};
  for (const m::LeafKind k : {m::LeafKind::Quick, m::LeafKind::Full})
    if (p.allows(k)) return {k, m::LeafState::Alive, {}};
  return {};
}

PlantDecision PlantEngine::reject(std::string reason) const {
  PlantDecision d;
  d.kind = PlantDecision::Kind::Rejected;
  d.reason = std::move(reason);
  return d;
}

PlantDecision PlantEngine::fromLeaf(int node, const Decision& leafDecision) const {
  PlantDecision d;
  d.node = node;
  d.leaf = leafDecision;
  if (leafDecision.kind == Decision::Kind::Rejected) {
    d.kind = PlantDecision::Kind::Rejected;
    d.reason = "node " + num(node) + " leaf: " + leafDecision.reason;
  } else if (leafDecision.kind != Decision::Kind::Ignored) {
    d.kind = PlantDecision::Kind::Leaf;
  }
  return d;
}

PlantDecision PlantEngine::onStylus(const StylusInput& s) {
  // The press as the plant sees it (also inside a full leaf: a very long press there with
  // nothing of the leaf to undo undoes the plant's last action).
  // After a move of the transmitter every sample is taken into the first position's frame
  // before anything sees it (not while the landmarks are being taken again: those are fitted).
  StylusInput in = s;
  if (!relocating_ && toFirst_.size() > 1) {
    const Eigen::Vector3d p = toFirst_.back() * Eigen::Vector3d(s.positionMm[0], s.positionMm[1], s.positionMm[2]);
    in.positionMm = {p.x(), p.y(), p.z()};
  }
  const std::optional<PressEnd> end = press_.take(in, settings_);
  const bool released = end && !end->cut;  // a press that ended as pressed, not one a reconnect cut
  if (const int node = leafNode()) {
    Engine& e = leafEngine(node);
    e.setPlantPosition(static_cast<int>(toFirst_.size()) - 1);
    const bool hadActions = !e.items().empty() || e.rowsEnded();
    const Decision ld = e.onStylus(in);  // decides and applies, as on a detached leaf
    if (released && end->heldNs >= settings_.undoPressNs && !hadActions && ld.kind == Decision::Kind::Rejected)
      return undo();
    PlantDecision d = fromLeaf(node, ld);
    if (d.kind == PlantDecision::Kind::Leaf) mirror(node, ld);
    if (ld.kind == Decision::Kind::Accepted) lastAcceptedReleaseNs_ = s.tNs;
    return d;
  }
  if (!end) return {};
  if (end->cut) return reject(cutPressWords(end->heldNs));
  if (end->heldNs >= settings_.undoPressNs) return undo();
  PlantDecision d = end->heldNs >= settings_.longPressNs ? decideEnd() : decidePoint(in);
  if (d.kind != PlantDecision::Kind::Rejected && d.kind != PlantDecision::Kind::Ignored) apply(d);
  if (d.kind == PlantDecision::Kind::Accepted) lastAcceptedReleaseNs_ = s.tNs;
  return d;
}

PlantDecision PlantEngine::decidePoint(const StylusInput& release) {
  const PlantStep st = step();
  if (!isStylusItem(st.what)) {
    if (st.what == PlantWhat::Done) return reject("the plant is complete: nothing more to point at");
    return reject("now measure with the caliper: " + prompt());
  }
  if (st.what == PlantWhat::LandmarkAgain && st.index == 0)
    return reject("every landmark is taken again: hold the button (or End) to fit the transmitter's new position");
  const std::vector<const StylusInput*> window = press_.window(release.tNs, settings_);
  const rules::Press press = rules::settle(window, settings_);
  if (press.refusal) return reject(*press.refusal);
  // The last point in the same frame: landmarks taken again are in the moved transmitter's.
  std::optional<rules::Point> previous;
  for (auto it = items_.rbegin(); it != items_.rend() && !previous; ++it)
    if (isStylusItem(it->what) && (it->what == PlantWhat::LandmarkAgain) == (st.what == PlantWhat::LandmarkAgain))
      previous = at(*it);
  if (auto r = rules::doublePressNear(press.mean, previous, press_.pressedAt(), lastAcceptedReleaseNs_, settings_))
    return reject(*r);
  // The plant's own rules, in the words of the plant frame and the leaf's pose.
  if (auto why = geometryRefusal(st, press.mean)) {
    if (retake_)
      *why += " (take it again, or undo to put the old one back)";
    else if (st.what == PlantWhat::Collar || st.what == PlantWhat::Point)
      *why += " (undo to take the landmarks again)";
    return reject(*why);
  }
  PlantDecision d;
  d.kind = PlantDecision::Kind::Accepted;
  d.item.what = st.what;
  d.item.index = st.index;
  d.item.part = st.part;
  d.item.positionMm = {press.mean.x(), press.mean.y(), press.mean.z()};
  d.item.frame = st.what == PlantWhat::LandmarkAgain ? st.part : static_cast<int>(toFirst_.size()) - 1;
  d.item.raw = window.back()->raw;
  return d;
}

std::optional<std::string> PlantEngine::geometryRefusal(const PlantStep& st, const Eigen::Vector3d& p) const {
  const bool retakenLandmark = retake_ && st.what == PlantWhat::Landmark;
  const std::vector<Eigen::Vector3d> marks = retakenLandmark ? landmarkPoints(&p, st.index) : landmarkPoints();
  const PlantItem* collar = find(PlantWhat::Collar, 0, 0);
  const PlantItem* first = find(PlantWhat::Point, 1, 1);
  try {
    if (retakenLandmark) {
      // A new landmark is checked when the landmarks end; a retaken one against the plant now.
      const Eigen::Vector3d normal = m::landmarkPlane(marks).normal;
      if (collar) (void)m::plantFrameFromLandmarks(marks, at(*collar), first ? at(*first) - at(*collar) : normal);
    } else if (st.what == PlantWhat::Collar) {
      (void)m::plantFrameFromLandmarks(marks, p, m::landmarkPlane(marks).normal);
      if (first) (void)m::plantFrameFromLandmarks(marks, p, at(*first) - p);
    } else if (st.what == PlantWhat::Point && st.index == 1 && st.part == 1) {
      const Eigen::Vector3d c = at(*collar);
      (void)m::plantFrameFromLandmarks(marks, c, p - c);
    } else if (st.what == PlantWhat::QuickPoint) {
      // base, tip, side: the one at st.part is p.
      std::optional<Eigen::Vector3d> q[3];
      for (int k = 1; k <= 3; ++k) {
        if (k == st.part)
          q[k - 1] = p;
        else if (const PlantItem* i = find(PlantWhat::QuickPoint, st.index, k))
          q[k - 1] = at(*i);
      }
      if (q[0] && q[1] && q[2])
        (void)m::leafPose(*q[0], *q[1], *q[2]);
      else if (q[0] && q[1])
        (void)m::leafPose(*q[0], *q[1]);
    }
  } catch (const m::InputError& e) {
    return std::string(e.what());
  }
  return std::nullopt;
}

PlantDecision PlantEngine::onCaliper(const CaliperInput& c) {
  if (const int node = leafNode()) {
    const Decision ld = leafEngine(node).onCaliper(c);
    PlantDecision d = fromLeaf(node, ld);
    if (d.kind == PlantDecision::Kind::Leaf) mirror(node, ld);
    return d;
  }
  const PlantStep st = step();
  if (isStylusItem(st.what)) return reject("a caliper reading now? " + prompt() + " first");
  if (st.what == PlantWhat::Done) return reject("the plant is complete: the reading was not used");
  if (!(c.valueMm >= settings_.minThicknessMm && c.valueMm <= m::kMaxThicknessMm)) {
    char b[160];
    std::snprintf(b, sizeof b,
                  "a stem diameter of %.3f mm is outside %g–%g mm: check the unit and the jaws, measure again",
                  c.valueMm, settings_.minThicknessMm, m::kMaxThicknessMm);
    return reject(b);
  }
  PlantDecision d;
  d.kind = PlantDecision::Kind::Accepted;
  d.item.what = st.what;
  d.item.index = st.index;
  d.item.part = st.part;
  d.item.valueMm = c.valueMm;
  d.item.raw = c.raw;
  if (lastReadingAt_ >= 0 && c.tNs - lastReadingAt_ <= settings_.repeatWindowNs && c.valueMm == lastReading_)
    d.item.flag = "repeated reading";
  lastReadingAt_ = c.tNs;
  lastReading_ = c.valueMm;
  apply(d);
  return d;
}

PlantDecision PlantEngine::decideEnd() const {
  if (retake_) return reject("finish the retake first: " + prompt());
  const PlantStep st = step();
  PlantDecision d;
  if (st.what == PlantWhat::LandmarkAgain) {
    const RelocationFit fit = fitOf(st.part);
    if (fit.refusal) return reject(*fit.refusal);
    d.kind = PlantDecision::Kind::RelocationFitted;
    d.node = st.part;
    d.fit = fit;
    return d;
  }
  if (st.what == PlantWhat::Landmark) {
    if (landmarks() < protocol_.minLandmarks)
      return reject("the plant frame needs at least " + num(protocol_.minLandmarks) + " landmarks (" +
                    num(landmarks()) + " taken)");
    if (st.index <= lastLandmark())
      return reject("landmark " + num(st.index) + " was taken out: take it again before ending the landmarks");
    const std::vector<Eigen::Vector3d> marks = landmarkPoints();
    try {
      (void)m::landmarkPlane(marks);
    } catch (const m::InputError& e) {
      return reject(std::string(e.what()) + " (undo to take a landmark again)");
    }
    d.kind = PlantDecision::Kind::LandmarksEnded;
    return d;
  }
  if (st.what == PlantWhat::Point && st.part == 1) {
    if (st.index == 1) return reject("a plant needs at least one node: take node 1 on the stem");
    const m::NodeLink l = link(st.index);
    if (l.order > 1) {
      // On a branch: the branch ends, the next node goes on along the main stem.
      if (l.relation == '+')
        return reject("node " + num(st.index) + " starts the branch: take its point, or undo the branch");
      d.kind = PlantDecision::Kind::NodePlaced;
      d.node = st.index;
      d.place = {mainLast(), '<'};
      return d;
    }
    d.kind = PlantDecision::Kind::PlantEnded;
    return d;
  }
  if (st.what == PlantWhat::Done) return reject("the plant is already complete");
  return reject("nothing to end now: " + prompt());
}

PlantDecision PlantEngine::end() {
  if (const int node = leafNode()) {
    const Decision ld = leafEngine(node).endRows();
    PlantDecision d = fromLeaf(node, ld);
    if (d.kind == PlantDecision::Kind::Leaf) mirror(node, ld);
    return d;
  }
  PlantDecision d = decideEnd();
  apply(d);
  return d;
}

PlantDecision PlantEngine::undo() {
  // A retake in progress is taken back first: the old item returns.
  if (retake_) {
    PlantDecision d;
    d.kind = PlantDecision::Kind::RetakeCancelled;
    d.item = retakeOld_;
    apply(d);
    return d;
  }
  for (auto& [node, e] : leaves_)
    if (e.retaking()) {
      const Decision ld = e.undo();
      PlantDecision d = fromLeaf(node, ld);
      if (d.kind == PlantDecision::Kind::Leaf) mirror(node, ld);
      return d;
    }
  if (actions_.empty()) return reject("nothing to undo");
  const Action a = actions_.back();
  PlantDecision d;
  switch (a.kind) {
    case Action::Kind::Item:
      d.kind = PlantDecision::Kind::Undone;
      d.item = items_.back();
      break;
    case Action::Kind::LandmarksEnded: d.kind = PlantDecision::Kind::LandmarksReopened; break;
    case Action::Kind::PlantEnded: d.kind = PlantDecision::Kind::PlantReopened; break;
    case Action::Kind::Choice:
      d.kind = PlantDecision::Kind::ChoiceUndone;
      d.node = a.node;
      d.choice = choiceFor(a.node);
      d.previous = a.previous;
      break;
    case Action::Kind::Place:
      d.kind = PlantDecision::Kind::PlacementUndone;
      d.node = a.node;
      d.place = places_.at(a.node);
      break;
    case Action::Kind::RelocationStart:
      d.kind = PlantDecision::Kind::RelocationCancelled;
      d.node = a.node;
      break;
    case Action::Kind::RelocationFit:
      d.kind = PlantDecision::Kind::RelocationReopened;
      d.node = a.node;
      break;
    case Action::Kind::Leaf: {
      const Decision ld = leafEngine(a.node).undo();
      d = fromLeaf(a.node, ld);
      if (d.kind == PlantDecision::Kind::Leaf) mirror(a.node, ld);
      return d;
    }
  }
  apply(d);
  return d;
}

PlantDecision PlantEngine::chooseLeaf(int node, LeafChoice choice) {
  const bool inRange = node >= 1 && node <= nodes() + 1;
  const m::ProtocolEntity* leafIs = inRange ? leafEntityOf(node) : leafEntity();
  if (!leafIs)
    return reject(inRange && link(node).order > 1 ? "this protocol's branch nodes carry no leaf"
                                                  : "this protocol's nodes carry no leaf");
  if (!leafIs->leaf->allows(choice.kind))
    return reject("the protocol does not take " + std::string(m::toString(choice.kind)) + " leaves");
  if (plantEnded_) return reject("the plant is ended: undo the end first");
  if (relocating_) return reject("finish moving the transmitter first: " + prompt());
  if (choice.type.size() > kMaxLeafTypeChars)
    return reject("a leaf type is a short word (at most " + num(static_cast<int>(kMaxLeafTypeChars)) +
                  " characters), such as lower or upper");
  if (node < 1 || node > nodes() + 1)
    return reject("node " + num(node) + " is not taken yet: choose for node " + num(nodes() + 1) + " or one before");
  const LeafChoice now = choiceFor(node);
  if (choice == now) return {};
  const Engine* e = leaf(node);
  const bool fullTaken = e && (!e->items().empty() || e->retaking());
  const bool quickTaken = find(PlantWhat::QuickPoint, node, 1) != nullptr;
  if (choice.kind != now.kind && (fullTaken || quickTaken))
    return reject("node " + num(node) + "'s leaf has points taken as a " + m::toString(now.kind) +
                  " leaf: undo them first");
  PlantDecision d;
  d.kind = PlantDecision::Kind::LeafChosen;
  d.node = node;
  d.choice = choice;
  d.previous = now;
  apply(d);
  return d;
}

PlantDecision PlantEngine::moveTransmitter() {
  if (!landmarksEnded_) return reject("end the landmarks first: the transmitter's new position is found from them");
  if (plantEnded_) return reject("the plant is ended: undo the end first");
  if (relocating_) return reject("the transmitter is being moved already: " + prompt());
  if (retaking()) return reject("finish the retake in progress first (or undo it)");
  PlantDecision d;
  d.kind = PlantDecision::Kind::RelocationStarted;
  d.node = static_cast<int>(toFirst_.size());
  apply(d);
  return d;
}

std::set<int> PlantEngine::leafPositions(int node) const {
  const auto it = leafPositions_.find(node);
  return it == leafPositions_.end() ? std::set<int>{} : it->second;
}

RelocationFit PlantEngine::fitOf(int relocation) const {
  std::vector<Eigen::Vector3d> before, after;
  std::vector<int> numbers;
  for (int k = 1; k <= lastLandmark(); ++k) {
    const PlantItem* first = find(PlantWhat::Landmark, k, 0);
    const PlantItem* again = find(PlantWhat::LandmarkAgain, k, relocation);
    if (!first || !again) continue;
    before.push_back(at(*first));
    after.push_back(at(*again));
    numbers.push_back(k);
  }
  return fitRelocation(before, after, relocation_, numbers);
}

PlantDecision PlantEngine::branch(int from) {
  if (from == 0) from = mainLast();
  if (from == 0) return reject("take node 1 on the stem first: a branch starts from a node of the main stem");
  return place(step().index, {from, '+'});
}

PlantDecision PlantEngine::place(int node, NodePlace where) {
  if (relocating_) return reject("finish moving the transmitter first: " + prompt());
  if (where.relation == '+' && axisIndex_[1] < 0)
    return reject(
        "this protocol has no branches (no axis of order 2): capture with one that has, such as "
        "data/protocols/branched.plant-protocol.json");
  if (plantEnded_) return reject("the plant is ended: undo the end first");
  if (retaking()) return reject("finish the retake in progress first (or undo it)");
  const PlantStep st = step();
  if (st.what != PlantWhat::Point || st.part != 1 || st.index != node || node <= lastNode())
    return reject("a node is placed on the plant before its first point, and now: " + prompt());
  if (where.parent < 1 || where.parent >= node)
    return reject("node " + num(where.parent) + " is not taken: a node hangs on one taken before it (1 to " +
                  num(node - 1) + ")");
  if (where.relation == '+' && link(where.parent).order != 1)
    return reject("node " + num(where.parent) +
                  " is on a branch: branches start from the main stem (plant capture takes axes of order 2)");
  if (where.relation == '<')
    for (int k = where.parent + 1; k < node; ++k)
      if (const m::NodeLink l = link(k); l.parent == where.parent && l.relation == '<')
        return reject("node " + num(k) + " already follows node " + num(where.parent) +
                      " on its axis: a node after it starts a branch (branch " + num(where.parent) + ")");
  const m::NodeLink now = link(node);
  if (now.parent == where.parent && now.relation == where.relation) return {};
  // A leaf chosen ahead for this node must be one its new axis' leaf takes.
  const int order = where.relation == '+' ? link(where.parent).order + 1 : link(where.parent).order;
  if (const auto chosen = choices_.find(node);
      chosen != choices_.end() && leafEntity(order) && !leafEntity(order)->leaf->allows(chosen->second.kind))
    return reject("node " + num(node) + "'s leaf is chosen " + m::toString(chosen->second.kind) + ", which \"" +
                  leafEntity(order)->name + "\" does not take: choose its leaf again first");
  PlantDecision d;
  d.kind = PlantDecision::Kind::NodePlaced;
  d.node = node;
  d.place = where;
  apply(d);
  return d;
}

PlantDecision PlantEngine::retake(PlantWhat what, int index, int part) {
  if (relocating_) return reject("finish moving the transmitter first: " + prompt());
  if (what == PlantWhat::LandmarkAgain)
    return reject("a landmark taken again after moving the transmitter is undone, not retaken (undo takes it back)");
  if (what == PlantWhat::Leaf || what == PlantWhat::Done)
    return reject(
        "retake names an item: a landmark, the collar, collar_diameter, a node's point or reading, a "
        "quick_point, or a full leaf's item with its node");
  if (retaking()) return reject("finish the retake in progress first (or undo it)");
  if (what == PlantWhat::Collar || what == PlantWhat::CollarDiameter) index = 0;
  if (what == PlantWhat::Landmark || what == PlantWhat::Collar || what == PlantWhat::CollarDiameter) part = 0;
  const PlantItem* old = find(what, index, part);
  if (!old) {
    std::string where = what == PlantWhat::Landmark ? "landmark " + num(index)
                        : index > 0                 ? "node " + num(index) + " " + toString(what) + " " + num(part)
                                                    : std::string(toString(what));
    return reject("nothing was captured as " + where + " yet: there is nothing to retake");
  }
  PlantDecision d;
  d.kind = PlantDecision::Kind::RetakeStarted;
  d.item = *old;
  apply(d);
  return d;
}

PlantDecision PlantEngine::retakeLeaf(int node, What what, int row, int col) {
  if (relocating_) return reject("finish moving the transmitter first: " + prompt());
  if (retaking()) return reject("finish the retake in progress first (or undo it)");
  const auto it = leaves_.find(node);
  if (it == leaves_.end() || it->second.items().empty())
    return reject("node " + num(node) + " has no full leaf taken: there is nothing of it to retake");
  const Decision ld = it->second.retake(what, row, col);
  PlantDecision d = fromLeaf(node, ld);
  if (d.kind == PlantDecision::Kind::Leaf) mirror(node, ld);
  return d;
}

}  // namespace leafdig::acquisition
