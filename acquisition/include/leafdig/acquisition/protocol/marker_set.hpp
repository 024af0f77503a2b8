// The leaf protocol's items as the model's marker set (SPEC §2): the board frame, the complete
// rows, the thickness rule applied. The plant's full leaves, the live preview and every export
// build their leaf from here.
#pragma once

#include <Eigen/Geometry>
#include <vector>

#include "leafdig/acquisition/protocol/engine.hpp"
#include "leafdig/model/leaf/markers.hpp"

namespace leafdig::acquisition {

// Thicknesses the preview uses until the caliper has measured them (mm, diameters). The
// preview says so (Preview::provisionalThickness); exports never use them.
struct ProvisionalThickness {
  double midribMm = 1.2, veinOriginMm = 0.6, edgeMm = 0.25;
};

// The board frame of the 3 board points (origin, +X, a point on the +Y side): a rigid
// transform from the digitizer frame. Identity when the capture has no board frame.
[[nodiscard]] Eigen::Isometry3d boardFrame(const std::vector<Item>& items);

// The marker set of the complete rows (in the board frame when there is one); thicknesses that
// were not measured are filled with `provisional` when given (usedProvisional set), else left
// absent. The live preview's partial leaf.
[[nodiscard]] model::MarkerSet partialMarkerSet(const std::vector<Item>& items, const Settings& settings,
                                                const ProvisionalThickness* provisional, bool& usedProvisional);

// The leaf as a marker set (in the board frame when there is one). Throws
// model::InputError naming what is missing when the capture is not complete.
[[nodiscard]] model::MarkerSet toMarkerSet(const std::vector<Item>& items, const Settings& settings,
                                           const model::LeafInfo& leaf = {});

}  // namespace leafdig::acquisition
