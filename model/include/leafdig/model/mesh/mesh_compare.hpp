#pragma once
// Distances between triangle meshes (Metro-style, docs/meshing.md): area-weighted sample
// points on one mesh, exact point-to-triangle distances to the other through a bounding
// volume hierarchy, both ways.
#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "leafdig/model/mesh/mesh.hpp"

namespace leafdig::model {

// Triangles only: what a distance needs from any mesh or file.
struct TriangleSoup {
  std::vector<Eigen::Vector3d> positions;
  std::vector<std::array<std::uint32_t, 3>> triangles;
};

// All organs of `mesh` in one soup (indices renumbered).
[[nodiscard]] TriangleSoup soupOf(const LeafMesh& mesh);
[[nodiscard]] TriangleSoup soupOf(const Mesh& mesh);
[[nodiscard]] double surfaceArea(const TriangleSoup& soup);

// Exact distance from points to the nearest point of a triangle set: a median-split
// bounding-volume hierarchy of the triangles, nearest child first, pruned by box distance.
class TriangleDistance {
 public:
  explicit TriangleDistance(const TriangleSoup& soup);
  ~TriangleDistance();
  TriangleDistance(const TriangleDistance&) = delete;
  TriangleDistance& operator=(const TriangleDistance&) = delete;

  // Distance from p to the triangles. `upperBound`, a distance known to be at least the
  // answer (e.g. a neighbouring query's answer plus the distance between the two points),
  // only speeds the search.
  [[nodiscard]] double distance(const Eigen::Vector3d& p,
                                double upperBound = std::numeric_limits<double>::infinity()) const;

 private:
  struct Impl;
  Impl* impl_;
};

struct OneSidedDistance {
  double max = 0.0;   // the one-sided Hausdorff distance h(A, B)
  double mean = 0.0;  // over the samples (area-weighted)
  double rms = 0.0;
  std::size_t samples = 0;
};

struct MeshDistance {
  double hausdorff = 0.0;  // max(h(A, B), h(B, A))
  double mean = 0.0;       // over the samples of both sides
  double rms = 0.0;
  OneSidedDistance aToB;
  OneSidedDistance bToA;
  std::size_t trianglesA = 0;
  std::size_t trianglesB = 0;
};

struct CompareOptions {
  // Samples on each side: this many area-weighted points (at least `perTriangle` per
  // triangle of that side) plus every vertex — or as many evenly spread vertices as there
  // are area samples, when the side has more vertices than that.
  std::size_t samples = 200'000;
  double perTriangle = 2.0;
  std::uint64_t seed = 1;  // the same seed gives the same answer
  int threads = 2;
};

// Throws InputError when a mesh has no triangles of positive area.
[[nodiscard]] MeshDistance compareMeshes(const TriangleSoup& a, const TriangleSoup& b,
                                         const CompareOptions& options = {});
// One direction only: samples on `from`, distances to `to`.
[[nodiscard]] OneSidedDistance oneSidedDistance(const TriangleSoup& from, const TriangleDistance& to,
                                                const CompareOptions& options = {});

// Reads a triangle mesh (OBJ, PLY, STL, GLB/glTF) with assimp. glTF is read as the format
// says (metres, +Y up) and turned into leafdig's frame (millimetres, +Z up), so a GLB export
// compares with its OBJ/PLY siblings. Throws InputError naming the file and what is wrong.
[[nodiscard]] TriangleSoup readMeshFile(const std::string& path);

}  // namespace leafdig::model
