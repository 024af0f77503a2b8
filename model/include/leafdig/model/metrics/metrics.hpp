#pragma once
// Leaf metrics of docs/method.md §6.
#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "leafdig/model/leaf/blade.hpp"
#include "leafdig/model/mesh/mesh.hpp"
#include "leafdig/model/metrics/area_interval.hpp"
#include "leafdig/model/metrics/blade_area.hpp"

namespace leafdig::model {

[[nodiscard]] double meshArea(const Mesh& mesh);

// Sum of A_k |n_k . d| over the triangles (overlaps counted repeatedly); d need not be unit.
[[nodiscard]] double projectedArea(const Mesh& mesh, const Eigen::Vector3d& lightDirection);

// The silhouette (displayed) area of docs/method.md §6 for light from `direction`: the area of the
// union of the triangles' projections onto the plane perpendicular to it, so overlaps count
// once. Computed on a square raster of `pixels` across the larger extent of the projection,
// sampling pixel centres; the error is about half a pixel along the outline (under 0.5 % for
// a 300 mm leaf at 2048 pixels). A mesh seen edge-on has zero silhouette.
[[nodiscard]] double silhouetteArea(const std::vector<const Mesh*>& meshes, const Eigen::Vector3d& direction,
                                    int pixels = 2048);

// Seed 001's markers-only estimate: each grid cell split along both diagonals, triangle
// areas by Kahan's stable Heron formula, the two splits averaged. A comparison figure
// only; it under-estimates a curved blade.
[[nodiscard]] double markerGridHeronArea(const MarkerGrid& grid);

struct AreaConstraint {
  double measuredMm2;
  double modelMm2;
  double differencePercent;  // (model - measured) / measured * 100
  double thresholdPercent;
  bool exceeded;
};
[[nodiscard]] AreaConstraint compareArea(double modelMm2, double measuredMm2, double thresholdPercent = 5.0);

// The protocol's last row is at the leaf base, where the blade meets the stem or petiole, and
// the blade ends there (docs/decisions.md). At the base the blade narrows: the last row's
// width (P_N1 to P_N7) is 22–49 % of the widest row's on the synthetic leaves of every shape.
// A last row at least 60 % as wide as the widest was either not at the base, or the base is
// broad (winged, cordate) and its lowest veins meet the margin far up: either way the model
// ends short of the leaf and its area falls short of a leaf area meter's.
inline constexpr double kBaseRowWidthWarningRatio = 0.6;
[[nodiscard]] std::vector<Warning> captureWarnings(const MarkerSet& markers);

// Seed 001's light metrics of one leaf (docs/method.md §6), the same as a plant's per leaf
// (computePlantMetrics): the blade mesh's area, its silhouette (displayed) area for the
// light at 1024 pixels across the leaf, and STAR = silhouette / area.
struct LeafSilhouette {
  double meshAreaMm2 = 0.0;
  double silhouetteMm2 = 0.0;
  double star = 0.0;
};
[[nodiscard]] LeafSilhouette leafSilhouette(const Mesh& blade, const Eigen::Vector3d& lightDirection);

struct LeafMetrics {
  BladeAreaEstimate blade;
  Eigen::Vector3d lightDirection;                // unit, in the model's frame
  double markerGridHeronAreaMm2;                 // seed 001's quad sum, for comparison only
  std::optional<AreaConstraint> areaConstraint;  // when the leaf has a measured area
  std::optional<AreaUncertainty> areaInterval;   // blade area's 95 % interval (FASTRAK accuracy)
  std::vector<Warning> warnings;                 // captureWarnings of the markers
  std::optional<LeafSilhouette> silhouette;      // of the exported mesh's blade (addSilhouette)
};

// Light direction in the model's frame; measured area from the marker set's leaf info. The
// area interval uses the FASTRAK's stated accuracy, 64 draws, a seed from the markers.
[[nodiscard]] LeafMetrics computeLeafMetrics(const LeafModel& model, const Eigen::Vector3d& lightDirection,
                                             double areaThresholdPercent = 5.0);

// The silhouette and STAR of `mesh`'s blade for the metrics' light (the mesh exported with
// them: model build, session export, review at the export resolution).
void addSilhouette(LeafMetrics& metrics, const LeafMesh& mesh);

// The metrics as a JSON object (text), the shape `leafdig model build --json` prints.
[[nodiscard]] std::string metricsToJson(const LeafMetrics& metrics);

}  // namespace leafdig::model
