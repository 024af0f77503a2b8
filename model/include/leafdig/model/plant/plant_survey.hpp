#pragma once
// What a plant digitized in place measures (docs/plants.md, "Digitized in place"): its nodes
// and leaves in the plant frame — heights, internodes, stem diameters, each leaf's azimuth,
// inclination, length, width (and roll for a quick leaf, area and its interval for a full
// one), and the divergence from one leaf to the next.
#include <optional>
#include <string>
#include <vector>

#include "leafdig/model/leaf/markers.hpp"
#include "leafdig/model/plant/plant_frame.hpp"
#include "leafdig/model/plant/plant_markers.hpp"

namespace leafdig::model {

struct SurveyedNode {
  int index = 0;                                      // 1 at the base
  Eigen::Vector3d pointMm = Eigen::Vector3d::Zero();  // in the plant frame
  double diameterMm = 0.0;
  double heightMm = 0.0;     // above the collar (the point's z)
  double internodeMm = 0.0;  // from the node it hangs on (the collar for node 1), straight
  NodeLink link;             // where it hangs: the main stem, or a branch
};

struct SurveyedLeaf {
  int node = 0;
  LeafKind kind = LeafKind::None;
  LeafState state = LeafState::Alive;
  std::optional<LeafPose> pose;           // full: the base (row N's midrib point) to the tip; quick: its 3 points
  std::optional<Eigen::Vector3d> baseMm;  // the pose's base, in the plant frame
  std::optional<Eigen::Vector3d> tipMm;   // the pose's tip, in the plant frame
  std::optional<Eigen::Vector3d> sideMm;  // quick: the widest point of one margin, in the plant frame
  std::string type;                       // quick: the organ library's type it asks for ("" any)
  std::optional<double> midribLengthMm;   // full: along the midrib
  std::optional<double> areaMm2;          // full: the blade's area; quick: its drawn shape's (addDrawnAreas)
  std::string areaShape;                  // quick: where the drawn shape came from ("" a full leaf)
  std::optional<double> areaLow95Mm2, areaHigh95Mm2;
  std::optional<double> divergenceDeg;  // from the previous leaf with a pose on its axis, counterclockwise
  std::optional<MarkerSet> markers;     // full: the markers in the plant frame
};

struct PlantSurvey {
  std::string plant;
  std::optional<SurveyDate> date;  // the plant-markers file's
  PlantFrame frame;
  double collarDiameterMm = 0.0;
  std::vector<SurveyedNode> nodes;
  std::vector<SurveyedLeaf> leaves;  // one per node that has a leaf (or a flagged state)
};

// The frame from the landmarks and the collar (+Z on the first node's side), then every node
// and leaf measured in it. Throws InputError for a frame that cannot be made or a leaf whose
// points do not make one (with the node's number).
[[nodiscard]] PlantSurvey surveyPlant(const PlantMarkers& plant);
// Whether a leaf of the survey is a quick one (drawn from a library shape, not digitized).
[[nodiscard]] bool hasQuickLeaf(const PlantSurvey& survey);

// The survey as JSON: {"plant", "frame": {"flatness_mm", "from_digitizer": 4×4 row-major},
// "collar_diameter_mm", "nodes": [...], "leaves": [...], "divergence": {"count", "mean_deg"}},
// and "date" ("YYYY-MM-DD") when the survey has one. A branched plant's nodes also say where
// they hang: "parent" (0 the collar), "relation" ("<" or "+") and "order".
[[nodiscard]] std::string plantSurveyToJson(const PlantSurvey& survey);

}  // namespace leafdig::model
