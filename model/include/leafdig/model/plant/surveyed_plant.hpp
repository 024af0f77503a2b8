#pragma once
// A plant digitized in place as a plant model (docs/plants.md, "The captured plant as a
// model"), so that every plant format (GLB, OBJ, PLY, STL, CARIBU, the plant's JSON) and the
// plan writer work on it:
// - the stem: the ball B-spline through the collar and every node point, each ball the
//   caliper's stem diameter there;
// - a full leaf: its model as digitized, in the plant frame (its area is a detached leaf's);
// - a quick leaf: a leaf shape of its type from the organ library (the one whose length to
//   width ratio is nearest the measured one), else the fallback shape, stretched in its
//   own frame to the measured chord length and width and laid on the three points: base on
//   the base, +Y along the base-to-tip chord, the width towards the side point, the adaxial
//   side up. Its area follows from the shape; the digitizer's interval does not apply.
// - a node without a leaf, or a flagged leaf without points: no leaf.
// Leaf ranks are node numbers; a leaf's insertion height is its node's height.
#include <string>
#include <vector>

#include "leafdig/model/plant/plant.hpp"
#include "leafdig/model/plant/plant_survey.hpp"

namespace leafdig::model {

// `fallback` is the shape a quick leaf takes when the library has none of its type (the
// station's: synth/synthetic_leaf.hpp's sampleLeafShape()). Throws InputError (naming the
// node) when a leaf's points make no leaf.
[[nodiscard]] Plant surveyedPlant(const PlantSurvey& survey, const std::vector<LibraryLeaf>& library,
                                  const LibraryLeaf& fallback);

// Each quick leaf's area as surveyedPlant draws it — its shape stretched to its length and
// width — into its `areaMm2`, with `areaShape` naming where the shape came from ("library:
// session 12", the fallback's source), so that the survey's areas add up to the plant's leaves
// (docs/plants.md, "Quick leaves' areas"). No interval: a drawn shape is not a measurement. Full
// leaves keep their digitized blade's area.
void addDrawnAreas(PlantSurvey& survey, const std::vector<LibraryLeaf>& library, const LibraryLeaf& fallback);

}  // namespace leafdig::model
