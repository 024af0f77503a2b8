#pragma once
// How organs are meshed (docs/method.md §5, docs/meshing.md): uniform grids of named resolution, the seed's
// adaptive rule (patent CN101650836: division length M, inter-segment angle α, Delaunay
// blades), or ours, bounded by an error E in millimetres. See docs/meshing.md.
#include <Eigen/Core>
#include <array>
#include <string>
#include <vector>

#include "leafdig/model/mesh/mesh.hpp"
#include "leafdig/names/name_table.hpp"

namespace leafdig::model {

enum class MeshMethod { Uniform, Seed, Adaptive };
// Its words in files, options and messages (the CLI's choices and the station's lists too).
inline constexpr NameTable<MeshMethod, 3> kMeshMethodNames{
    {{MeshMethod::Uniform, "uniform"}, {MeshMethod::Seed, "seed"}, {MeshMethod::Adaptive, "adaptive"}}};

[[nodiscard]] const char* toString(MeshMethod method);
// Throws InputError naming the accepted words.
[[nodiscard]] MeshMethod meshMethodFromString(const std::string& word);

// The resolution presets a file is meshed at (the CLI's --resolution choices; "reference" is for
// measuring meshes, not for files).
inline constexpr std::array<const char*, 3> kFileResolutionNames{"preview", "export", "paper"};

// Which organs a file keeps (issue 51, --organs): every organ, or the leaves' blades alone — a
// light model's leaves, without the veins' tubes and the stem (CARIBU, Helios).
enum class OrganChoice { All, Blades };
inline constexpr NameTable<OrganChoice, 2> kOrganChoiceNames{
    {{OrganChoice::All, "all"}, {OrganChoice::Blades, "blade"}}};
[[nodiscard]] const char* toString(OrganChoice choice);
// Throws InputError naming the accepted words.
[[nodiscard]] OrganChoice organChoiceFromString(const std::string& word);
// `mesh` with only the organs `choice` keeps, in their order (its warnings kept).
[[nodiscard]] LeafMesh withOrgans(LeafMesh mesh, OrganChoice choice);

// The seed's parameters: skeleton curves divided every `minLengthMm` along their length,
// then neighbouring segments merged while the angle between them at their shared point
// exceeds `maxAngleDeg` (180 = straight); `ringVertices` around every axis organ.
struct SeedMeshParameters {
  double minLengthMm = 2.0;
  double maxAngleDeg = 170.0;
  int ringVertices = 8;
};

struct MeshOptions {
  MeshMethod method = MeshMethod::Uniform;
  MeshResolution resolution = MeshResolution::preset("export");  // uniform
  SeedMeshParameters seed;                                       // seed
  double maxErrorMm = 0.1;                                       // adaptive
};

// Human-readable parameters of `options`' method, e.g. "resolution export" or
// "max-error 0.1 mm".
[[nodiscard]] std::string describe(const MeshOptions& options);

// ---- the seed's rule, on its own (tested on hand-made polylines) ----------------------

// Indices of `points` kept by the seed's merge rule: walking from the first point, an inner
// point is deleted while the angle at it between the segment from the last kept point and
// the segment to the next point is greater than `maxAngleDeg`; the ends are always kept.
[[nodiscard]] std::vector<std::size_t> mergeByAngle(const std::vector<Eigen::Vector3d>& points, double maxAngleDeg);

// Parameters dividing a curve, given as a dense polyline `points` at increasing parameters
// `ts`, into pieces of arc length `lengthMm` (the last one shorter; both ends included).
[[nodiscard]] std::vector<double> divideByLength(const std::vector<double>& ts,
                                                 const std::vector<Eigen::Vector3d>& points, double lengthMm);

// ---- organ meshers ----------------------------------------------------------------------

// Seed mode: rings of `p.ringVertices` at the centre-curve points kept by mergeByAngle after
// dividing the vein every `p.minLengthMm`; ends closed with hemispherical caps.
[[nodiscard]] Mesh meshVeinSeed(const Vein& vein, const SeedMeshParameters& p, CapStyle caps,
                                std::vector<Warning>& warnings);
// Seed mode: the blade split at the midrib into two closed polygons in its (u, v) domain,
// their boundaries (margin, base row, midrib) divided and merged by the same rule, each
// triangulated by constrained Delaunay without interior points, lifted onto the surface.
[[nodiscard]] Mesh meshBladeSeed(const BladeSurface& blade, const SeedMeshParameters& p);

// Error-bounded: ring count from the radius, rings placed along the vein where the chord
// error (centre sagitta + radius change + ring rotation) would exceed the budget, so the
// tube is within `maxErrorMm` of the vein's envelope (and caps of its end balls).
[[nodiscard]] Mesh meshVeinAdaptive(const Vein& vein, double maxErrorMm, CapStyle caps, std::vector<Warning>& warnings);
// Error-bounded: constrained Delaunay refinement of the blade's (u, v) domain until every
// triangle's interpolation-error bound (½ κ R², κ the largest normal curvature over the
// triangle, R its smallest enclosing radius) is within `maxErrorMm`; lifted onto the surface.
[[nodiscard]] Mesh meshBladeAdaptive(const BladeSurface& blade, double maxErrorMm);

[[nodiscard]] LeafMesh meshLeaf(const LeafModel& model, const MeshOptions& options);

// The largest distance between the uniform mesh meshLeaf(model, resolution) makes and the
// exact surface, by the same estimators the adaptive mode uses (a stated bound for
// reference meshes, not a measurement).
[[nodiscard]] double estimatedUniformError(const LeafModel& model, const MeshResolution& resolution);

}  // namespace leafdig::model
