#pragma once
// Where the uniform mesh puts a vein's rings (mesh.cpp meshes at them, mesh_method.cpp
// estimates the uniform mesh's error at them): one rule for both.
#include <vector>

#include "leafdig/model/leaf/leaf_model.hpp"
#include "leafdig/model/mesh/mesh.hpp"

namespace leafdig::model::detail {

// The resolution's lateral segments, or its segments per row for the midrib and the contour,
// over the vein's spans; every data parameter is a ring.
[[nodiscard]] std::vector<double> uniformVeinParameters(const Vein& vein, const MeshResolution& resolution);

}  // namespace leafdig::model::detail
