#pragma once
// A plant's meshes for two light simulators (docs/plants.md, "Formats"), each keeping organ
// identity:
// - Helios XML (`.xml`): one `<triangle>` per triangle, built by Helios from its `<transform>` of
//   the unit triangle (0,0,0), (0,1,0), (1,1,0), so the matrix's top rows are
//   [v2 − v1 | v1 − v0 | (1,1,1) − v2 | v0] (the affine map that sends those three corners to
//   v0, v1, v2 and (1,1,1) to itself, as Helios's Triangle::makeTransformationMatrix solves it);
//   metres; each organ a `<polymesh>` object (objID 1, 2, … in the mesh's organ order) and every
//   triangle carrying `plantID`, `leafID` (the leaf's rank, 0 the wood) and `organID` as
//   primitive data; colours as `<color>`.
// - VegeSTAR (`.vgx`): a title row, then one row per triangle, `Obj` 0 (an explicit triangle,
//   X1 … Z3), tab-separated numbers only, centimetres with Z negated (VegeSTAR's Z points down:
//   RATP reads z = −Z / 100), `Grp1` the organ, `Grp2` the plant; TransX … TransZ the
//   triangle's centroid and EchX = EchY = √(area / 0.7), so that a reader that takes each row as
//   a leaf symbol (PyRATP's: area EchX · EchY · 0.7 at Trans) finds each triangle's area where it
//   is, while an explicit-triangle reader (PlantGL's) uses X1 … Z3.
#include <string>

#include "leafdig/model/mesh/mesh.hpp"

namespace leafdig::model {

[[nodiscard]] std::string encodeHeliosXml(const LeafMesh& mesh, const std::string& generator, int plantNumber = 1);
[[nodiscard]] std::string encodeVgx(const LeafMesh& mesh, int plantNumber = 1);

}  // namespace leafdig::model
