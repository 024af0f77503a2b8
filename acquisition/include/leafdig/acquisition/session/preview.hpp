// Markers of a capture as a model: the complete leaf for export, and a partial one for the
// live preview (midrib as soon as it has two balls, a lateral pair per complete row, the
// contour from one complete row, the blade from two).
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "leafdig/acquisition/protocol/engine.hpp"
#include "leafdig/acquisition/protocol/marker_set.hpp"
#include "leafdig/model/leaf/leaf_model.hpp"
#include "leafdig/model/leaf/markers.hpp"
#include "leafdig/model/mesh/mesh.hpp"

namespace leafdig::acquisition {

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
