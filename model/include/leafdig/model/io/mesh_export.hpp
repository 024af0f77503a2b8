#pragma once
// Mesh exports of docs/method.md §5 and data/schema/. Bytes are produced in memory; callers write them with
// writeFileAtomically. Millimetres and the model's axes for OBJ/PLY/STL (stated in each
// file's header); glTF in metres with the frame's +Z mapped to glTF's +Y (up).
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "leafdig/model/mesh/mesh.hpp"

namespace leafdig::model {

enum class MeshFormat { Glb, Obj, Ply, Stl };

// From the file extension (.glb .obj .ply .stl, any case). Throws InputError otherwise.
[[nodiscard]] MeshFormat meshFormatForPath(const std::filesystem::path& path);

// A file's provenance (a stored session's: session, station, status, operator, curator, …), as
// (key, value) in order; empty for files made from a file. OBJ: `# provenance KEY: VALUE`
// comment lines; PLY: `comment provenance KEY: VALUE`; GLB: `asset.extras.provenance`; STL's
// 80-byte header has no room for it.
using Provenance = std::vector<std::pair<std::string, std::string>>;

struct ExportHeader {
  std::string leafId;     // may be empty
  std::string frame;      // "digitizer", "leaf", "plant" or "leaf2d" (a 2-D leaf: origin at its base)
  std::string generator;  // "leafdig 0.1.0"
  Provenance provenance{};
};

// OBJ: one `o` group per organ, vertex normals, a header comment with unit, frame, up axis.
// PLY: binary little endian, float position and normal per vertex, per-face `organ_id`
// (the organ's index, listed in header comments) and `leaf_rank` (the organ's leaf on a
// plant, 0 otherwise). STL: binary, facet normals.
// GLB: glTF 2.0 binary, one named node per organ under a node named after the leaf.
[[nodiscard]] std::string encodeMesh(const LeafMesh& mesh, MeshFormat format, const ExportHeader& header);
// Throws InputError naming the organ when a position or normal is not finite: checked before
// any file is written (encodeMesh and the plant encoders call it).
void requireFiniteMesh(const LeafMesh& mesh);

// The rotation from a leafdig frame (+Z up) to glTF's (+Y up): (x, y, z) -> (x, z, -y).
[[nodiscard]] Eigen::Vector3d toGltfAxes(const Eigen::Vector3d& p);

}  // namespace leafdig::model
