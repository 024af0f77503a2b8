#pragma once
// How a leaf of a plant digitized in place was taken (docs/plants.md): the whole leaf
// protocol, three stylus points, or not at all (a node without a leaf, or one flagged with a
// state). Its words, in files and exports: "full", "quick", "none".
#include <string>

namespace leafdig::model {

enum class LeafKind { Full, Quick, None };
[[nodiscard]] const char* toString(LeafKind kind);
// Throws UnknownName listing the kinds.
[[nodiscard]] LeafKind leafKindFromString(const std::string& word);

}  // namespace leafdig::model
