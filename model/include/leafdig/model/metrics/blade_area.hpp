#pragma once
// A blade's area by its triangle-area sum at a resolution, and doubled until it settles
// (docs/method.md §6): what the leaf's metrics and its area interval measure.
#include <Eigen/Core>

#include "leafdig/model/leaf/blade.hpp"

namespace leafdig::model {

// Half the cross product of a triangle's edges: its area times its unit normal.
[[nodiscard]] inline Eigen::Vector3d triangleAreaVector(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                                        const Eigen::Vector3d& c) {
  return 0.5 * (b - a).cross(c - a);
}

struct BladeAreaEstimate {
  double areaMm2 = 0.0;
  double projectedAreaMm2 = 0.0;
  int segmentsPerRow = 0;  // resolution at which the area settled
  int segmentsAcross = 0;
  double relativeChange = 0.0;  // |A - A_previous| / A at that resolution
  bool converged = false;
};

// Doubles the blade resolution from 2 per row x 12 across until the triangle-area sum
// changes by less than `tolerance` (default 0.1 %), at most `maxDoublings` times.
[[nodiscard]] BladeAreaEstimate convergedBladeArea(const BladeSurface& blade, const Eigen::Vector3d& lightDirection,
                                                   double tolerance = 1e-3, int maxDoublings = 7);

// The blade's triangle-area sum at a fixed resolution: `perRow` segments per marker-row
// span, `across` over the width (what convergedBladeArea measures at each step).
[[nodiscard]] double bladeGridArea(const BladeSurface& blade, int perRow, int across);

}  // namespace leafdig::model
