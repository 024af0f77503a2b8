// How a leaf is carried onto a plant (the plan's builder and the surveyed plant share it).
#pragma once

#include "leafdig/model/leaf/markers.hpp"

namespace leafdig::model::detail {

// The leaf in its own frame (docs/method.md §5: origin P_N4, +Y to the tip, +Z adaxial),
// from markers in any frame.
[[nodiscard]] MarkerSet toLeafFrame(const MarkerSet& markers);

// Scale (uniform × growth factors: x by scale × width, y and z by scale × length), then the
// extra midrib bend: a point at distance y along the leaf's +Y turns about the leaf's X axis
// by bend × (y / y_tip)², tip downwards (towards the abaxial side). Vein thickness scales
// with the length factor.
[[nodiscard]] MarkerSet shapeLeaf(const MarkerSet& leafFrame, double scale, double lengthFactor, double widthFactor,
                                  double bendDeg);

}  // namespace leafdig::model::detail
