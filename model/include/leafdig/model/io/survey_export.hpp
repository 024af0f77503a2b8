#pragma once
// A plant digitized in place as files: an MTG coding file in the AMAP conventions (docs/plants.md,
// "The survey's MTG") that OpenAlea's reader and PlantFrame use: the stem as internodes
// `I<k>` ending at node k (`XX YY ZZ` the digitized node, `TopDia` the stem diameter there,
// `Length` the internode), `I0` the collar; each leaf `+L<k>` from its node's internode with
// `XX YY ZZ` (its base), `Length`, `Width`, `Area`, `Azimuth`, `Inclination`, `State` and
// its `Kind`; every entity carries the survey's `Date`. Lengths in mm, areas in mm², angles
// in degrees, in the plant frame; the header says so. A branch's internodes are `I` too, the
// first one branching (`+I<k>`) from the internode of the node that bears it; the MTG's order
// is depth first (a node, its leaf, its branches whole, then the next node on its axis).
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include "leafdig/model/io/mesh_export.hpp"
#include "leafdig/model/mesh/mesh.hpp"
#include "leafdig/model/plant/plant_survey.hpp"

namespace leafdig::model {

// One entity of the survey's MTG — `I0` (the collar), `I<k>` (the internode ending at node k),
// `L<k>` (node k's leaf) — with its features as the MTG and the GLB give them: numbers in mm,
// mm² and degrees (the azimuth in [0, 360) after the MTG's rounding), words for State and Kind;
// only the features that have a value, in the MTG's column order (Date left to the writer).
struct SurveyEntity {
  std::string name;    // "I0", "I3", "L3"
  std::string parent;  // the entity it follows or that bears it; empty for I0
  char relation = 0;   // '<' follows, '+' bears; 0 for I0
  int depth = 0;       // the MTG line's indentation: 0 the main stem, +1 for each `+`
  using Value = std::variant<double, std::string>;
  std::vector<std::pair<std::string, Value>> features;
};
[[nodiscard]] std::vector<SurveyEntity> surveyEntities(const PlantSurvey& survey);

// The survey as MTG text, dated `date` (the reserved `Date` feature, DD/MM/YYYY).
[[nodiscard]] std::string encodeSurveyMtg(const PlantSurvey& survey, const SurveyDate& date);

// The same entities as a CSV, one row each in the MTG's order, for a spreadsheet: entity
// (I0, I1, L2, …), class, index, parent entity, relation, date (ISO), x_mm, y_mm, z_mm,
// top_diameter_mm, length_mm, width_mm, area_mm2, area_low95_mm2, area_high95_mm2,
// azimuth_deg, inclination_deg, roll_deg, divergence_deg, state, kind; empty where a value
// does not apply. Numbers in fixed notation, 3 decimals.
[[nodiscard]] std::string encodeSurveyCsv(const PlantSurvey& survey, const SurveyDate& date);

// The captured plant as GLB with one node per MTG entity (docs/plants.md, "A plant session's
// files"): the plant's root (extras: units, frame, date), `I0` and each `I<k>` child of the one
// it follows, each `L<k>` child of its internode, the features of surveyEntities() in each
// node's extras; a leaf's organ meshes (`plant/leaf-<k>/…` of `mesh`) are children of its
// `L<k>`, and the stem's mesh cut at the nodes: the piece from node k-1 (the collar for k = 1)
// to node k (`plant/stem/I<k>`) a child of `I<k>`.
// Every node's transform is the identity: the geometry is in the plant frame (glTF +Y up).
// Implemented beside the other glTF writers (tinygltf stays in one translation unit).
// `provenance`: a stored session's, in `asset.extras.provenance` (ExportHeader's).
[[nodiscard]] std::string encodeSurveyGlb(const PlantSurvey& survey, const SurveyDate& date, const LeafMesh& mesh,
                                          const std::string& generator, const Provenance& provenance = {});

}  // namespace leafdig::model
