#pragma once
// `leafdig.plant-markers/1`: a plant as a technician digitizes it where it stands (schema in
// data/schema/leafdig.plant-markers-1.schema.json; docs/plants.md): landmarks on the pot rim,
// the collar with its stem diameter, then node by node from the base, each with its stem
// diameter and its leaf — a full leaf (a whole leafdig.markers/1 document), a quick leaf
// (base, tip and the widest point of one margin) or none, with an MTG state. A node follows
// the node listed before it on that node's axis unless it says otherwise: `"branches_from": K`
// starts a branch (an axis one order above K's, up to kMaxAxisOrder) at node K, `"after": K`
// follows node K on K's axis (back on the stem after a branch). All points are in the
// digitizer's frame. Unknown keys are ignored; every problem is an InputError naming
// the source, the node and the key, and what to fix.
#include <Eigen/Core>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "leafdig/model/leaf/markers.hpp"
#include "leafdig/model/plant/leaf_kind.hpp"

namespace leafdig::model {

inline constexpr const char* kPlantMarkersFormat = "leafdig.plant-markers/1";
inline constexpr std::size_t kMaxPlantNodes = 500;  // a plant digitized in place; a tall tobacco has ~40

// What the MTG's `State` column says of a leaf: present and sound, or flagged.
enum class LeafState { Alive, Dead, Broken, Yellow, Pruned };
[[nodiscard]] const char* toString(LeafState state);  // "alive", "dead", "broken", "yellow", "pruned"
// Throws UnknownName listing the states.
[[nodiscard]] LeafState leafStateFromString(const std::string& word);

// The day of a survey (the MTG's `Date`): ISO 8601 "YYYY-MM-DD" in files and options.
struct SurveyDate {
  int year = 0, month = 0, day = 0;
  friend bool operator==(const SurveyDate&, const SurveyDate&) = default;
};
// A day of the calendar from 1900 to 2999 written "YYYY-MM-DD", or nothing.
[[nodiscard]] std::optional<SurveyDate> parseSurveyDate(std::string_view iso);
[[nodiscard]] std::string toIso(const SurveyDate& date);  // "2026-11-26"

struct QuickLeaf {
  Eigen::Vector3d baseMm = Eigen::Vector3d::Zero();  // where the blade joins the petiole
  Eigen::Vector3d tipMm = Eigen::Vector3d::Zero();
  Eigen::Vector3d sideMm = Eigen::Vector3d::Zero();  // the widest point of one margin
  std::string type;                                  // the organ library's type ("lower", …); empty: any
};

inline constexpr int kMaxAxisOrder = 3;  // the main stem 1, its branches 2, theirs 3

struct PlantNode {
  // Where it hangs, when not after the node listed before it (node numbers are 1-based).
  std::optional<int> after;                                 // follows this node on that node's axis
  std::optional<int> branchesFrom;                          // starts a branch from this node
  Eigen::Vector3d pointMm = Eigen::Vector3d::Zero();        // on the stem
  double diameterMm = 0.0;                                  // the stem's, by caliper
  std::variant<std::monostate, MarkerSet, QuickLeaf> leaf;  // none, full, quick
  LeafState state = LeafState::Alive;                       // of the leaf (a node without one: Alive means none)
};

struct PlantMarkers {
  std::string plant;               // the plant's id
  std::optional<SurveyDate> date;  // the day it was digitized, when the file says
  std::vector<Eigen::Vector3d> landmarksMm;
  Eigen::Vector3d collarMm = Eigen::Vector3d::Zero();
  double collarDiameterMm = 0.0;
  std::vector<PlantNode> nodes;  // base to top (a branch's nodes in the order taken)
};

// Where each node hangs, worked out from the nodes' `after` / `branchesFrom`.
struct NodeLink {
  int parent = 0;       // the node it follows or branches from; 0: the collar (node 1)
  char relation = '<';  // '<' follows on the parent's axis, '+' starts a branch from it
  int order = 1;        // its axis' order: 1 the main stem
  int axis = 1;         // its axis, named by the axis' first node (1: the main stem)
};
// One link per node. Throws InputError (from `source`, naming the node) when a node hangs on a
// node not listed before it, says both keys, follows a node another already follows, or makes
// an axis of order above kMaxAxisOrder.
[[nodiscard]] std::vector<NodeLink> plantTopology(const std::vector<PlantNode>& nodes, const std::string& source);
[[nodiscard]] bool hasBranches(const std::vector<NodeLink>& links);

// `source` names the input in messages (a path, "<stdin>").
[[nodiscard]] PlantMarkers parsePlantMarkersJson(std::string_view text, const std::string& source);
// Reads and parses a file; an unreadable file is an InputError too.
[[nodiscard]] PlantMarkers readPlantMarkersFile(const std::filesystem::path& path);
// In millimetres; full leaves as whole markers documents.
[[nodiscard]] std::string plantMarkersToJson(const PlantMarkers& plant);

}  // namespace leafdig::model
