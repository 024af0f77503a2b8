// The plant protocol's engine (docs/plants.md, "The plant capture engine"): a state machine that takes
// a plant where it stands in the order a plant protocol file (model::PlantProtocol) gives —
// landmarks on the pot rim, the collar and its diameter, then node by node the axis entity's
// points and readings and each node's leaf: in full (the leaf protocol, one leaf Engine per
// node), quick (three stylus points) or none (with a state). Like the leaf Engine it decides
// (accept / reject with words) and applies decisions; replaying the applied decisions rebuilds
// its state exactly. Every point stays in the digitizer's frame, as pressed; the plant frame is
// made from them (capturedPlant → model::surveyPlant), so correcting a landmark moves every
// point after it.
//
// The stylus works as on a leaf: a point is the mean of the still samples around the press, a
// long press ends the landmarks (once there are enough) or the plant (at a node's first point),
// a very long press undoes the last action. Inside a full leaf the leaf Engine has the stylus
// (its long press ends the rows); a very long press there with nothing of the leaf to undo
// undoes the plant's last action.
//
// Retake (as on a leaf): any item held — a landmark, the collar, a node's point or reading, a
// quick leaf's point, or a full leaf's marker or reading — is taken out and becomes the next step
// wherever the capture is; the next accepted input of that kind replaces it, with the same
// plant-frame and leaf-pose checks as the first time (a landmark that would leave no plant frame
// is refused). undo() before that puts the old item back; undo() after it takes the new item out
// and the step asks for it again.
//
// Protocols: one repeating axis of order 1 with its leaf, and optionally one repeating axis of
// order 2 (a branch) with its own leaf (data/protocols/branched.plant-protocol.json). Nodes are
// numbered in the order taken, depth first: branch(K) makes the next node start a branch from
// main-stem node K, and the nodes after it follow on the branch until the branch is ended (the
// long press or end() at a branch node's first point), when the next node follows the main
// stem's last node again. Where a node hangs is a decision (NodePlaced), undone like any other;
// a node's points, readings and leaf are those of its axis' entities.
//
// Moving the transmitter (issue 29; docs/plants.md, "Moving the transmitter"): once the
// landmarks are ended, moveTransmitter() at any step starts relocation r (1, 2, …): the
// technician moves the transmitter and takes the landmarks again in number order (at least
// three; the long press or end() then fits), each a LandmarkAgain item in the new transmitter's
// frame. The fit (fitRelocation, against the landmarks as first taken) is refused in words
// naming the landmark that moved; accepted, every later stylus sample is taken into the first
// transmitter position's frame before anything else sees it, so every point — the plant's and
// a full leaf's — is in one frame, and relocations chain through it (a third position maps to
// the first directly, not through the second). Undo goes back through a fit and a start.
//
// Thread contract: one thread owns a PlantEngine; it never blocks.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <tuple>
#include <vector>

#include "leafdig/acquisition/protocol/engine.hpp"
#include "leafdig/acquisition/protocol/relocation.hpp"
#include "leafdig/model/plant/plant_markers.hpp"
#include "leafdig/model/plant/plant_protocol.hpp"

namespace leafdig::acquisition {

// Landmark (index 1…), Collar, CollarDiameter, Point / Reading of the axis entity at node
// `index` (part 1… of the entity's points / readings), QuickPoint (part 1…3 of node `index`'s
// quick leaf), Leaf (node `index`'s full leaf: the leaf Engine's step), LandmarkAgain (landmark
// `index` taken again after moving the transmitter, relocation `part`; index 0: all are taken
// again, the fit is next), Done.
enum class PlantWhat { Landmark, Collar, CollarDiameter, Point, Reading, QuickPoint, Leaf, Done, LandmarkAgain };
[[nodiscard]] const char* toString(PlantWhat w);  // "landmark", "collar", "collar_diameter", "point", …
[[nodiscard]] PlantWhat plantWhatFromString(const std::string& s);  // throws UnknownName
[[nodiscard]] bool isStylusItem(PlantWhat w);

struct PlantStep {
  PlantWhat what = PlantWhat::Landmark;
  int index = 0;  // landmark number, or node number (1 at the base); 0 for the collar
  int part = 0;   // which point / reading / quick point (1-based); 0 where it does not apply
  Step leaf;      // Leaf: the leaf Engine's step
  friend bool operator==(const PlantStep&, const PlantStep&) = default;
};

struct PlantItem {
  PlantWhat what = PlantWhat::Landmark;
  int index = 0, part = 0;
  Vec3 positionMm{};   // stylus items, in the first transmitter position's frame (LandmarkAgain: as pressed)
  int frame = 0;       // the transmitter position it was taken from (0 the first; LandmarkAgain: its own)
  double valueMm = 0;  // caliper items (diameters)
  std::string raw;
  std::string flag;  // e.g. "repeated reading"
};

// What the technician chose for a node's leaf (a LeafChosen decision).
struct LeafChoice {
  model::LeafKind kind = model::LeafKind::None;
  model::LeafState state = model::LeafState::Alive;
  // The organ library's type of the leaf ("lower", "upper", …; empty: not said): a quick leaf
  // takes its shape from an approved leaf of this type, a full leaf carries it as its own.
  std::string type;
  friend bool operator==(const LeafChoice&, const LeafChoice&) = default;
};

// Where a node hangs, when the technician placed it (a NodePlaced decision): it follows
// `parent` on its axis ('<': back on the stem after a branch) or starts a branch from it ('+').
// A leaf's organ-library type, as the technician says it: a short word.
inline constexpr std::size_t kMaxLeafTypeChars = 64;

struct NodePlace {
  int parent = 0;
  char relation = '<';
  friend bool operator==(const NodePlace&, const NodePlace&) = default;
};

struct PlantDecision {
  enum class Kind {
    Ignored,
    Accepted,
    Rejected,
    Undone,
    LandmarksEnded,
    LandmarksReopened,
    PlantEnded,
    PlantReopened,
    LeafChosen,           // node's leaf kind / state set (choice); `previous` is what it was
    ChoiceUndone,         // the last LeafChosen taken back: node's leaf is `previous` again
    Leaf,                 // a decision of node's full leaf Engine (leaf; its own retakes too)
    RetakeStarted,        // item (the plant's own) is taken out and is the next step
    RetakeCancelled,      // item is put back as it was
    NodePlaced,           // node (not taken yet) hangs at place: a branch begins or ends
    PlacementUndone,      // the last NodePlaced taken back: node hangs by default again (place: the one undone)
    RelocationStarted,    // the transmitter is moved: relocation `node` begins, landmarks again
    RelocationFitted,     // relocation `node` fitted (fit): later samples go into the first frame
    RelocationReopened,   // the last fit taken back: its landmarks again (undo)
    RelocationCancelled,  // the last start taken back, with no landmark taken again (undo)
  };
  Kind kind = Kind::Ignored;
  PlantItem item;  // Accepted / Undone
  int node = 0;    // LeafChosen, Leaf, NodePlaced
  LeafChoice choice, previous;
  NodePlace place;    // NodePlaced, PlacementUndone
  RelocationFit fit;  // RelocationFitted: its residual and worst landmark (recomputed on apply)
  Decision leaf;
  std::string reason;  // Rejected
};

class PlantEngine {
 public:
  // `leafSettings`: the stylus guards and the leaf protocol of full leaves (board frame off).
  // Throws std::invalid_argument naming what the protocol asks that capture cannot do yet.
  explicit PlantEngine(model::PlantProtocol protocol, Settings leafSettings = {});

  PlantDecision onStylus(const StylusInput& s);
  PlantDecision onCaliper(const CaliperInput& c);
  PlantDecision undo();
  // The key equivalent of the long press: ends the landmarks (at least the protocol's minimum)
  // or, at a node's first point, the plant; inside a full leaf, its rows.
  PlantDecision end();
  // Sets node's leaf kind and state (the current node or one still to come; a leaf with points
  // taken cannot change kind: undo them first).
  PlantDecision chooseLeaf(int node, LeafChoice choice);
  // Takes a held item out to take it again (RetakeStarted): the plant's own (landmark number,
  // node number; part = which point or reading, 1 for the first) or node's full leaf's (what,
  // row, col as on a leaf: retakeLeaf). Rejected in words when nothing is held there or another
  // retake is in progress.
  PlantDecision retake(PlantWhat what, int index, int part);
  PlantDecision retakeLeaf(int node, What what, int row, int col);
  [[nodiscard]] bool retaking() const;
  // The next node starts a branch from node `from` (0: the main stem's last node), or hangs at
  // `place` — at a new node's first point, nothing of it taken; the protocol must have a branch
  // for '+', and a branch starts from the main stem. Rejected in words otherwise.
  PlantDecision branch(int from = 0);
  PlantDecision place(int node, NodePlace where);
  // Where node hangs (node numbers 1…; the node asked for next included), as a plant-markers
  // file says it.
  [[nodiscard]] model::NodeLink link(int node) const;
  // Starts a relocation (above); refused in words before the landmarks are ended, during a
  // retake or another relocation, or once the plant is ended.
  PlantDecision moveTransmitter();
  [[nodiscard]] int relocating() const { return relocating_; }  // the relocation in progress, 0 none
  // Transmitter position r's frame → the first's (0: identity); one per fitted relocation.
  [[nodiscard]] const std::vector<Eigen::Isometry3d>& toFirst() const { return toFirst_; }
  [[nodiscard]] const RelocationSettings& relocationSettings() const { return relocation_; }
  // Relocation r's fit (1…) from its LandmarkAgain items against the landmarks as first taken:
  // its residual and worst landmark, as the station shows them.
  [[nodiscard]] RelocationFit fitOf(int relocation) const;
  // The transmitter positions (0 the first) node's full leaf's stylus points were accepted from,
  // as far as replayed (a point undone keeps its position counted: the set only grows).
  [[nodiscard]] std::set<int> leafPositions(int node) const;

  void apply(const PlantDecision& d);
  // A curator's correction in review (review.hpp's correct() on a plant session, and its
  // replay): the held item at fixed's place (what, index, part) is replaced where it stands, so
  // the landmarks keep their order; node's full leaf's item (fixed's what, row, col) through its
  // leaf Engine, as a leaf session's correction is replayed. False when no such item is held.
  bool correct(const PlantItem& fixed);
  bool correctLeaf(int node, const Item& fixed);

  [[nodiscard]] PlantStep step() const;
  [[nodiscard]] std::string prompt() const;
  [[nodiscard]] const std::vector<PlantItem>& items() const { return items_; }
  // node's full leaf Engine, or null when node has none (yet).
  [[nodiscard]] const Engine* leaf(int node) const;
  // node's leaf choice: the technician's, or the protocol's default (every k-th node in full).
  [[nodiscard]] LeafChoice choiceFor(int node) const;
  [[nodiscard]] int nodes() const;  // nodes with their first point taken
  [[nodiscard]] bool complete() const { return step().what == PlantWhat::Done; }
  [[nodiscard]] const model::PlantProtocol& protocol() const { return protocol_; }
  // Whether the protocol has a branch (an axis of order 2): a '+' placement needs one.
  [[nodiscard]] bool hasBranches() const { return axisIndex_[1] >= 0; }
  [[nodiscard]] const Settings& leafSettings() const { return settings_; }
  // What was captured, in the digitizer's frame, as a plant-markers document holds it: every
  // node with all its points and readings, each leaf as chosen (a full leaf once complete).
  [[nodiscard]] model::PlantMarkers captured(const std::string& plant) const;

 private:
  struct Action {
    enum class Kind {
      Item,
      LandmarksEnded,
      PlantEnded,
      Leaf,
      Choice,
      Place,
      RelocationStart,
      RelocationFit
    } kind = Kind::Item;
    int node = 0;  // Leaf, Choice, Place
    LeafChoice previous;
    bool hadChoice = false;
    std::optional<NodePlace> previousPlace;  // Place
  };
  [[nodiscard]] PlantDecision decidePoint(const StylusInput& release);
  [[nodiscard]] PlantDecision decideEnd() const;
  [[nodiscard]] PlantDecision reject(std::string reason) const;
  [[nodiscard]] PlantDecision fromLeaf(int node, const Decision& d) const;
  [[nodiscard]] const PlantItem* find(PlantWhat w, int index, int part) const;
  [[nodiscard]] int landmarks() const;
  // The landmarks by number (a retaken one comes back at its place), with `extra` at number
  // `extraIndex` when given (a landmark being retaken, not held).
  [[nodiscard]] std::vector<Eigen::Vector3d> landmarkPoints(const Eigen::Vector3d* extra = nullptr,
                                                            int extraIndex = 0) const;
  // The plant frame and a quick leaf's pose with `p` at step st: the words of what fails.
  [[nodiscard]] std::optional<std::string> geometryRefusal(const PlantStep& st, const Eigen::Vector3d& p) const;
  [[nodiscard]] int lastLandmark() const;  // the highest landmark number held, 0 for none
  [[nodiscard]] int lastNode() const;      // the highest node number with a point, reading or quick point held
  void eraseItem(std::size_t index);
  [[nodiscard]] std::optional<PlantStep> nodeStep(int node) const;  // the first step node still needs
  [[nodiscard]] int leafNode() const;                               // the node whose full leaf has the stylus now, or 0
  [[nodiscard]] std::string pointName(const PlantStep& s) const;
  Engine& leafEngine(int node);
  // Keeps the plant's action list in step with a decision node's leaf Engine applied.
  void mirror(int node, const Decision& d);

  // The stem entity taken node by node, and the leaf entity (null: the nodes carry no leaf), of
  // axis order 1 or 2 (the branch: null when the protocol has none): indices into
  // protocol_.entities, so that an engine copies and moves whole. Of a node: its axis' own.
  [[nodiscard]] const model::ProtocolEntity& axis(int order = 1) const;
  [[nodiscard]] const model::ProtocolEntity* leafEntity(int order = 1) const;
  [[nodiscard]] const model::ProtocolEntity& axisOf(int node) const;
  [[nodiscard]] const model::ProtocolEntity* leafEntityOf(int node) const;
  [[nodiscard]] int mainLast() const;  // the main stem's last node held, 0 for none
  void relink();                       // placedLinks_ from places_

  model::PlantProtocol protocol_;
  int axisIndex_[2] = {-1, -1}, leafIndex_[2] = {-1, -1};
  std::map<int, NodePlace> places_;           // nodes the technician placed; others follow the node before
  std::vector<model::NodeLink> placedLinks_;  // nodes 1 … the last placed one
  int relocating_ = 0;
  std::vector<Eigen::Isometry3d> toFirst_{Eigen::Isometry3d::Identity()};
  std::map<int, std::set<int>> leafPositions_;
  RelocationSettings relocation_;
  Settings settings_;
  std::vector<PlantItem> items_;
  // find()'s index: the first item of each (what, index, part) in items_, made again after
  // items_ changes (a plant of N nodes is read in O(N), not O(N²): issue 47).
  mutable std::map<std::tuple<int, int, int>, std::size_t> found_;
  mutable bool foundValid_ = false;
  std::map<int, Engine> leaves_;
  std::map<int, LeafChoice> choices_;
  std::vector<Action> actions_;
  bool landmarksEnded_ = false, plantEnded_ = false;
  std::optional<PlantStep> retake_;  // a plant item being retaken
  PlantItem retakeOld_;
  StylusPress press_;
  std::int64_t lastAcceptedReleaseNs_ = -1;
  std::int64_t lastReadingAt_ = -1;
  double lastReading_ = -1;
};

}  // namespace leafdig::acquisition
