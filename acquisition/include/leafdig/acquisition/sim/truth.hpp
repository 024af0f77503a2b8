// What a known leaf or plant says the technician should press or read at a step: the virtual
// technician's answers (simulated captures, the demo, the tests), from a markers file or a
// plant-markers file. A reading the document does not hold is answered with a tobacco leaf's
// typical one (midrib 1.2 mm, vein origin 0.6 mm, edge 0.25 mm, a point's thickness between its
// vein origin and the edge by its place in the row; truth.cpp).
#pragma once

#include <optional>

#include "leafdig/acquisition/protocol/engine.hpp"
#include "leafdig/acquisition/protocol/plant_engine.hpp"
#include "leafdig/model/leaf/markers.hpp"
#include "leafdig/model/plant/plant_markers.hpp"

namespace leafdig::acquisition {

// The stylus point of a leaf step (board, tip, marker).
[[nodiscard]] Vec3 leafPointTruth(const model::MarkerSet& leaf, What w, int row, int col);
// The caliper reading of a leaf's thickness step.
[[nodiscard]] double leafReadingTruth(const model::MarkerSet& leaf, What w, int row, int col);

// The stylus point of a plant step (landmark, collar, node point, quick leaf point); nothing
// when the plant has no such point: a landmark or a node beyond the document's, the step
// where the technician ends the landmarks or the plant.
[[nodiscard]] std::optional<Vec3> plantPointTruth(const model::PlantMarkers& plant, const PlantStep& step);
// The caliper reading of a plant step (a stem diameter).
[[nodiscard]] double plantReadingTruth(const model::PlantMarkers& plant, const PlantStep& step);
// How node's leaf is taken in the document (none, with its state, for a node without a leaf).
[[nodiscard]] LeafChoice plantChoiceTruth(const model::PlantMarkers& plant, int node);
// What the technician says before node `node`'s first point so that it hangs as the plant says,
// given where it hangs now: a branch from a stem node (relation '+', the parent), the end of a
// branch (relation '<': back on the stem), or nothing.
[[nodiscard]] std::optional<NodePlace> plantPlacementTruth(const model::PlantMarkers& plant, int node,
                                                           const model::NodeLink& now);
// node's full leaf (null when the node's leaf is not full).
[[nodiscard]] const model::MarkerSet* plantLeafTruth(const model::PlantMarkers& plant, int node);

}  // namespace leafdig::acquisition
