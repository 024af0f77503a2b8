// A mesh routine the 2-D leaf curls its flat leaf with; it knows nothing of leaves.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <utility>
#include <vector>

#include "leafdig/model/mesh/mesh.hpp"

namespace leafdig::model {

// Laplacian deformation (seed 001 eq. 5): with L the cotangent Laplacian of `mesh` as it is
// (rows normalised so that the weights of a vertex sum to 1) and sigma = L v its differential
// coordinates, returns the positions v' minimising sum_i |L v'_i - sigma_i|^2 over all
// vertices while every handle (vertex index, position) is held exactly. Throws InputError if
// a free vertex has no triangle or the handles leave a part of the mesh free to float.
[[nodiscard]] std::vector<Eigen::Vector3d> laplacianDeform(
    const Mesh& mesh, const std::vector<std::pair<std::uint32_t, Eigen::Vector3d>>& handles);

}  // namespace leafdig::model
