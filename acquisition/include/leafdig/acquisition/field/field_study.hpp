// What a field check and its correction are worth (issue 50, "Measured, on the simulated field";
// docs/field-study.md is this study's report, made by `leafdig field study`). A known distortion
// (a `leafdig.field-distortion/1` grid, the steel-bench preset by default) bends every position
// the digitizer reports; the study takes the sample leaves and the sample plant as their markers
// stand, each position as the bent field reports it (plus the digitizer's noise), and compares
// three captures with the truth:
//   clean       — the truth plus noise: what the digitizer gives in a clean field;
//   uncorrected — the bent field's report plus noise;
//   corrected   — that report through the correction a simulated check of the jig chose
//                 (chooseCorrection: the jig placed where the leaves or the plant stand, its
//                 divots reported by the same bent field, with noise).
// For a leaf: marker RMS (absolute, in the transmitter's frame), shape RMS (after the best rigid
// fit, what a model's geometry feels) and the blade area's error against the truth's model; for a
// plant: node positions and leaf angles in the plant frame and the full leaves' total area.
// Then the check itself: its reported RMS against the noiseless truth of the same fit, and with
// fewer divots (spread over the jig) the chosen model, its held-out error and the error it
// leaves on the leaves' markers — how many divots a lab must digitize.
//
// The marker is the sensor: the stylus's tip offset is not turned by the field here (a captured
// sample is, by the simulated digitizer). Every number is a mean over `repeats` seeded noise
// draws; the study is deterministic for a seed.
#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "leafdig/devices/sim/field_distortion.hpp"
#include "leafdig/model/field/jig.hpp"
#include "leafdig/model/leaf/markers.hpp"
#include "leafdig/model/plant/plant_markers.hpp"

namespace leafdig::acquisition {

struct FieldStudyInput {
  devices::sim::FieldDistortion field;
  std::string fieldName;  // for the report ("steel-bench preset", a file's name)
  model::Jig jig;
  Eigen::Isometry3d leafJigPose = Eigen::Isometry3d::Identity();   // the jig where the leaves lie
  Eigen::Isometry3d plantJigPose = Eigen::Isometry3d::Identity();  // the jig where the plant stands
  std::vector<std::pair<std::string, model::MarkerSet>> leaves;
  std::optional<std::pair<std::string, model::PlantMarkers>> plant;
  double noiseMm = 0.25;  // the digitizer's noise, σ per coordinate
  int repeats = 10;
  std::uint64_t seed = 1;
  std::vector<int> jigCounts;  // divots for the count table; empty: 6, 8, 12, 16 and every one
};

// One way of capturing, as a mean over the repeats.
struct CaptureError {
  double markerRmsMm = 0, shapeRmsMm = 0, areaErrorPercent = 0;  // area: |model − truth| / truth
};
struct LeafStudyRow {
  std::string leaf;
  int markers = 0;
  CaptureError clean, uncorrected, corrected;
};
struct PlantError {
  double nodeRmsMm = 0;         // the nodes in the plant frame
  double leafAngleDeg = 0;      // mean |Δ| of the leaves' azimuth and inclination
  double areaErrorPercent = 0;  // the full leaves' total area
};
struct PlantStudyRow {
  std::string plant;
  int nodes = 0, leaves = 0;
  PlantError clean, uncorrected, corrected;
  double outsidePercent = 0;  // of its points outside the box the correction was fitted in (clamped there)
};
struct JigCountRow {
  int points = 0;
  std::string model;  // the model chosen most often
  double holdoutRmsMm = 0, holdoutMaxMm = 0;
  double leafShapeRmsMm = 0;  // the leaves' markers through that correction: shape RMS against their truth
};
struct FieldStudyResult {
  std::string fieldName, jigName;
  int jigPoints = 0, repeats = 0;
  double noiseMm = 0;
  std::uint64_t seed = 0;
  double checkRmsMm = 0;       // what the check reports (mean)
  double fieldRmsMm = 0;       // the same fit of the noiseless report: the field's truth at the jig
  double cleanCheckRmsMm = 0;  // the check in a clean field (noise alone)
  std::string model;           // the correction chosen (most often) at the leaves' jig
  double holdoutRmsMm = 0;
  std::vector<LeafStudyRow> leaves;
  std::optional<PlantStudyRow> plant;
  std::vector<JigCountRow> counts;
};

// InputError (model) when a leaf or the plant does not build, or a count is below 4 or above the
// jig's points.
[[nodiscard]] FieldStudyResult runFieldStudy(const FieldStudyInput& in);

// The report (Markdown): how it was made (`command`), the check, the leaves, the plant, the
// counts, with the targets beside the numbers.
[[nodiscard]] std::string fieldStudyMarkdown(const FieldStudyResult& r, const std::string& command);
// The leaves' rows as docs/accuracy.md's section "Through a bent field" (issue 50): clean,
// uncorrected and corrected, what the study was and where the rest is.
[[nodiscard]] std::string fieldStudyAccuracySection(const FieldStudyResult& r, const std::string& command);

}  // namespace leafdig::acquisition
