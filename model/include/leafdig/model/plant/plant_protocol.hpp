#pragma once
// `leafdig.plant-protocol/1` (docs/plants.md, "The plant protocol file"; schema in
// data/schema/leafdig.plant-protocol-1.schema.json): what a plant capture asks for and in what
// order — the configuration file the Vp suite uses so that labs digitize other species. The
// plant frame's landmarks and the collar come first; then the entities in the order listed,
// each with its MTG class, where it hangs (the entity it follows with `<` or branches from with
// `+`), whether it repeats node by node, its stylus points and caliper readings, and for a leaf
// the kinds the technician may choose (full, quick, none), the three points of a quick leaf
// and the default choice. Built in: tobacco (defaultPlantProtocol). Unknown keys are ignored;
// every problem is an InputError naming the source, the entity and the key, and what to fix.
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "leafdig/model/plant/leaf_kind.hpp"

namespace leafdig::model {

inline constexpr const char* kPlantProtocolFormat = "leafdig.plant-protocol/1";

struct ProtocolLeaf {
  std::vector<LeafKind> kinds{LeafKind::Full, LeafKind::Quick, LeafKind::None};  // what the technician may choose
  std::vector<std::string> quickPoints{"base", "tip", "side"};                   // a quick leaf's three stylus points
  int fullEvery = 3;        // by default every k-th leaf of the axis is digitized in full…
  bool largestFull = true;  // …and the largest (the technician decides per node)

  [[nodiscard]] bool allows(LeafKind kind) const;
};

struct ProtocolEntity {
  std::string name;                   // "internode", "leaf", "branch", …
  char mtgClass = 'I';                // one capital letter, not P (the plant)
  std::string parent;                 // the entity it hangs on; empty: the plant's first axis
  char relation = '<';                // '<' follows the parent on its axis, '+' branches from it
  int order = 1;                      // axis order: 1 the main stem, 2 a branch
  bool repeat = false;                // taken again and again (node by node) until the technician ends it
  std::vector<std::string> points;    // stylus points, in order ("node")
  std::vector<std::string> readings;  // caliper readings, in order ("diameter")
  std::optional<ProtocolLeaf> leaf;   // the entity is a leaf: its kinds and quick points
};

struct PlantProtocol {
  std::string species;
  int minLandmarks = 3, maxLandmarks = 64;
  bool collarDiameter = true;  // the collar's stem diameter by caliper
  std::vector<ProtocolEntity> entities;

  // The entity named `name`, or null.
  [[nodiscard]] const ProtocolEntity* find(std::string_view name) const;
};

// Tobacco (the field's practice, docs/plants.md): internodes node by node with the node point
// and the stem diameter, each with its leaf branching (+): full, quick or none, every third
// and the largest in full.
[[nodiscard]] const PlantProtocol& defaultPlantProtocol();

// `source` names the input in messages (a path, "<stdin>").
[[nodiscard]] PlantProtocol parsePlantProtocolJson(std::string_view text, const std::string& source);
// Reads and parses a file; an unreadable file is an InputError too.
[[nodiscard]] PlantProtocol readPlantProtocolFile(const std::filesystem::path& path);
[[nodiscard]] std::string plantProtocolToJson(const PlantProtocol& protocol);

// The protocol's steps in words, one per line, as the station prompts them ("landmark 1…3 ·
// stylus", "internode · node · stylus", "internode · diameter · caliper", …).
[[nodiscard]] std::vector<std::string> describeSteps(const PlantProtocol& protocol);

}  // namespace leafdig::model
