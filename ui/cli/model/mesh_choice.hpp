#pragma once
// The `--mesh uniform|seed|adaptive` options that `model build`, `plant build` and `mesh
// compare|study` share, the mesh part of their --json reports (docs/meshing.md), and the
// resolution and organs a file is meshed with (`plant build`, `sessions export`).
#include <CLI/CLI.hpp>
#include <cstddef>
#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "leafdig/model/mesh/mesh_compare.hpp"
#include "leafdig/model/mesh/mesh_method.hpp"
#include "leafdig/model/study/mesh_study.hpp"

namespace leafdig::cli {

// --resolution of a file's meshes (model::kFileResolutionNames) and --organs (model::kOrganChoiceNames).
inline constexpr const char* kFileResolutionHelp = "Mesh resolution preset: preview, export (default), paper";
inline constexpr const char* kOrgansHelp =
    "The organs the meshes keep: all (default) or blade (the leaves' blades alone: no vein tubes, no stem; a light "
    "model's leaves)";
[[nodiscard]] inline std::vector<std::string> fileResolutionWords() {
  return {model::kFileResolutionNames.begin(), model::kFileResolutionNames.end()};
}

// What the user chose on the command line; checked by meshOptionsFrom.
struct MeshChoice {
  std::string method = "uniform";
  std::optional<double> minLengthMm;
  std::optional<double> maxAngleDeg;
  std::optional<int> ringVertices;
  std::optional<double> maxErrorMm;
  bool noMeasure = false;
};

void addMeshChoice(CLI::App& command, MeshChoice& choice);

// The mesh options, or an InputError naming the option that does not fit the method.
[[nodiscard]] model::MeshOptions meshOptionsFrom(const MeshChoice& choice, const model::MeshResolution& resolution);

// "mesh" of a --json report: method, parameters, triangles in total and per organ, and
// (when given) the measured distance to the reference meshes.
[[nodiscard]] nlohmann::json meshReportJson(const model::LeafMesh& mesh, const model::MeshOptions& options,
                                            const std::optional<model::MeshDistance>& measured,
                                            std::optional<double> referenceErrorMm);
// The same, measured against the subject's reference meshes with `samplesPerPart` samples,
// unless the mesh is uniform or `--no-measure` was given (the subject is made only then).
[[nodiscard]] nlohmann::json measuredMeshReportJson(const model::LeafMesh& mesh, const model::MeshOptions& options,
                                                    bool noMeasure, const std::function<model::MeshSubject()>& subject,
                                                    std::size_t samplesPerPart);

}  // namespace leafdig::cli
