// Markers of a capture as a model: the complete leaf for export, and a partial one for the
// live preview (midrib as soon as it has two balls, a lateral pair per complete row, the
// contour from one complete row, the blade from two).
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "leafdig/acquisition/engine.hpp"
#include "leafdig/model/leaf/leaf_model.hpp"
#include "leafdig/model/leaf/markers.hpp"
#include "leafdig/model/mesh/mesh.hpp"

namespace leafdig::acquisition {

// Thicknesses the preview uses until the caliper has measured them (mm, diameters). The
// preview says so (Preview::provisionalThickness); exports never use them.
struct ProvisionalThickness {
  double midribMm = 1.2, veinOriginMm = 0.6, edgeMm = 0.25;
};

// The board frame of the 3 board points (origin, +X, a point on the +Y side): a rigid
// transform from the digitizer frame. Identity when the capture has no board frame.
[[nodiscard]] Eigen::Isometry3d boardFrame(const std::vector<Item>& items);

// The leaf as a marker set (in the board frame when there is one). Throws
// model::InputError naming what is missing when the capture is not complete.
[[nodiscard]] model::MarkerSet toMarkerSet(const std::vector<Item>& items, const Settings& settings,
                                           const model::LeafInfo& leaf = {});

// The preview's meshes by the screen-space error they are made for (issue 26): the adaptive
// mesher within maxErrorMm of the model; a view draws the coarsest whose error is under half
// a pixel at its zoom (the exact model is for exports, not for the screen).
struct PreviewLevel {
  double maxErrorMm = 0.0;
  model::LeafMesh mesh;
};
inline constexpr double kPreviewLevelsMm[] = {0.5, 0.15};

struct Preview {
  model::LeafModel model;             // veins so far; blade.controlNet empty until two rows are complete
  model::LeafMesh mesh;               // the finest of `levels` (the adaptive mesh within 0.15 mm)
  std::vector<PreviewLevel> levels;   // coarse to fine (kPreviewLevelsMm)
  bool provisionalThickness = false;  // some radii are ProvisionalThickness, not measured
  std::vector<std::string> notes;     // why a part is missing (e.g. a degenerate row)
};

// Never throws for a partial or odd capture: what cannot be built is left out and noted.
// `meshes` false: the model and its notes only, no `levels` and no `mesh` (a terminal draws
// nothing; the meshes are most of the cost).
[[nodiscard]] Preview buildPreview(const std::vector<Item>& items, const Settings& settings,
                                   const ProvisionalThickness& provisional = {}, bool meshes = true);

}  // namespace leafdig::acquisition
