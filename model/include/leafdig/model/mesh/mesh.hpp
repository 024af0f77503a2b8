#pragma once
// Triangle meshes of the leaf's organs, with named resolution parameters (docs/method.md §5).
#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "leafdig/model/errors.hpp"
#include "leafdig/model/leaf/leaf_model.hpp"

namespace leafdig::model {

// positions/normals: one entry per vertex (normals unit length); triangles index them,
// counter-clockwise seen from outside (veins) or from the adaxial side (blade).
struct Mesh {
  std::vector<Eigen::Vector3d> positions;
  std::vector<Eigen::Vector3d> normals;
  std::vector<std::array<std::uint32_t, 3>> triangles;
  std::size_t quads = 0;  // quadrilateral faces before triangulation (the seed counts these)
};

enum class OrganKind { Vein, Blade };

struct Organ {
  std::string name;  // the vein's name, or "blade"
  OrganKind kind;
  Mesh mesh;
  int leafRank = 0;  // on a plant: the leaf's rank (0 for the stem and for a lone leaf)
};

enum class CapStyle { None, Sphere };

struct MeshResolution {
  std::string name;
  int ringVertices;           // vertices around a vein
  int lateralSegments;        // along one half-lateral vein (3 marker spans)
  int midribSegmentsPerRow;   // along the midrib, per marker span
  int contourSegmentsPerRow;  // along the contour, per marker span
  int bladeSegmentsAcross;    // across the blade (6 marker spans)
  int bladeSegmentsPerRow;    // along the blade, per marker row span
  CapStyle caps;              // hemispherical vein end caps
  int capRings;               // latitude steps of a cap

  // "paper": reproduces the seed's Table 1 (ring 5, lateral 20, midrib and contour 10 per
  // row, blade 30 across and 5 per row, open ends): veins 360 N + 10 vertices, 350 N quads;
  // blade (5 N + 1) x 31 vertices, 150 N quads. "preview": light, for live display.
  // "export": fine, for rendering and simulation. "reference": 3x export in every count,
  // the ground truth meshes are measured against (docs/meshing.md). Throws InputError for
  // other names.
  [[nodiscard]] static MeshResolution preset(const std::string& name);
};

struct LeafMesh {
  std::vector<Organ> organs;  // veins in model order, then "blade"
  std::vector<Warning> warnings;
};

// Vein tube on the exact envelope of docs/method.md §3, rings at `ts` (increasing, in [0, 1]).
[[nodiscard]] Mesh meshVein(const Vein& vein, const std::vector<double>& ts, int ringVertices, CapStyle caps,
                            int capRings, std::vector<Warning>& warnings);

// The blade sampled on `segmentsPerRow` per marker-row span and `segmentsAcross` over the
// whole width, vertex grid rows at the marker rows. Degenerate triangles (height under 1e-9
// of the longest edge: the tip row, where the tip repeats) are left out; the quad count is
// the seed's.
[[nodiscard]] Mesh meshBlade(const BladeSurface& blade, int segmentsPerRow, int segmentsAcross);

// Sets every vertex normal to the area-weighted mean of its triangles' normals, unit length;
// a vertex with none (or whose normals cancel) gets the mesh's mean normal, else +Z.
void setAreaWeightedNormals(Mesh& mesh);

[[nodiscard]] LeafMesh meshLeaf(const LeafModel& model, const MeshResolution& resolution);

// Parameters subdividing consecutive breaks: `segments` in total, spread over the spans as
// evenly as whole numbers allow; every break is included.
[[nodiscard]] std::vector<double> subdivideSpans(const std::vector<double>& breaks, int segments);

struct MeshCounts {
  std::size_t vertices = 0;
  std::size_t quads = 0;
  std::size_t triangles = 0;
};
[[nodiscard]] MeshCounts countVeins(const LeafMesh& mesh);
[[nodiscard]] MeshCounts countBlade(const LeafMesh& mesh);

// The rigid transform from the digitizer frame to the leaf frame of docs/method.md §5: origin at
// P_N4, +Y towards the tip, +Z the mean adaxial blade normal (made perpendicular to Y),
// X = Y x Z. (Here, not in leaf/, because the normal is measured on a coarse mesh of the
// blade.)
[[nodiscard]] Eigen::Isometry3d leafFrameFromDigitizer(const LeafModel& model);

}  // namespace leafdig::model
