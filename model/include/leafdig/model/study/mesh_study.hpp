#pragma once
// The meshing study of docs/meshing.md: one leaf (or plant) meshed uniform, seed, adaptive
// and by meshoptimizer, each at the coarsest setting whose measured Hausdorff distance to a
// fine reference is within E, with triangle counts and measured errors.
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "leafdig/model/mesh/mesh_compare.hpp"
#include "leafdig/model/mesh/mesh_method.hpp"
#include "leafdig/model/plant/plant.hpp"

namespace leafdig::model {

// A uniform resolution scaled from `export` by `factor` (every count times factor, at least
// the smallest sensible value), named "export x<factor>".
[[nodiscard]] MeshResolution scaledResolution(double factor);

// What is measured: a leaf, or a plant's leaves and stem. Each part is measured against its
// own reference (the `reference` resolution), so a plant needs no single huge mesh; the
// Hausdorff distance of the whole is at most the largest part's.
class MeshSubject {
 public:
  explicit MeshSubject(LeafModel leaf);
  explicit MeshSubject(Plant plant);

  [[nodiscard]] LeafMesh mesh(const MeshOptions& options) const;
  [[nodiscard]] const LeafMesh& reference() const { return reference_; }
  // The reference's own error against the exact surface (estimatedUniformError), stated.
  [[nodiscard]] double referenceErrorMm() const { return referenceError_; }
  // `mesh` (made by this->mesh) against the reference, part by part.
  [[nodiscard]] MeshDistance measure(const LeafMesh& mesh, std::size_t samplesPerPart) const;
  [[nodiscard]] double largestVeinRadiusMm() const;

 private:
  void prepare();
  [[nodiscard]] std::vector<TriangleSoup> partsOf(const LeafMesh& mesh) const;

  std::optional<LeafModel> leaf_;
  std::optional<Plant> plant_;
  LeafMesh reference_;
  double referenceError_ = 0.0;
  std::vector<TriangleSoup> referenceParts_;
  std::vector<std::unique_ptr<TriangleDistance>> referenceIndex_;
};

// meshoptimizer's simplifier (quadric error, collapses onto existing vertices) applied to
// every organ of `mesh` with its open borders locked, at an absolute error `errorMm`
// (converted with meshopt_simplifyScale per organ). Positions are welded first.
[[nodiscard]] LeafMesh simplifyWithMeshoptimizer(const LeafMesh& mesh, double errorMm);

struct StudyEntry {
  std::string name;  // reference, uniform, seed, adaptive, meshopt
  LeafMesh mesh;
  std::size_t triangles = 0;
  MeshDistance measured;  // for the reference: hausdorff = its stated bound
  bool meetsError = false;
  std::string parameters;                                       // human-readable
  std::vector<std::pair<std::string, double>> parameterValues;  // for --json
};

struct StudyOptions {
  double maxErrorMm = 0.1;
  std::size_t samplesPerPart = 100'000;  // while searching; the final figures use 2x
};

// Runs the study; entries in the order reference, uniform, seed, adaptive, meshopt.
[[nodiscard]] std::vector<StudyEntry> runMeshStudy(const MeshSubject& subject, const StudyOptions& options);

}  // namespace leafdig::model
