// What `_leafdig` does that needs no Python (docs/python.md): options and lights checked, a
// leaf's files written, a plant plan built, a store's session verified before anything of it is
// handed out. Kept out of leafdig_module.cpp, the one translation unit that sees pybind11 (it
// releases the GIL around these calls and turns their results into Python objects).
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "leafdig/db/event_store.hpp"
#include "leafdig/model/archive/plant_import.hpp"
#include "leafdig/model/io/leaf_build.hpp"
#include "leafdig/model/mesh/mesh.hpp"
#include "leafdig/model/metrics/metrics.hpp"
#include "leafdig/model/plant/plant.hpp"

namespace leafdig::python {

// "leafdig <version>": the generator every file written from Python names.
[[nodiscard]] const std::string& generator();

// A mesh's options from Python's words (resolution preset, method, the adaptive mesh's
// max_error): model::InputError naming the one that does not fit.
[[nodiscard]] model::MeshOptions meshOptions(const std::string& resolution, const std::string& method,
                                             std::optional<double> maxError);
// A light direction from Python: three finite numbers, not all zero; only its direction
// counts, so it is scaled to a largest component of 1 (nan, or 1e200, would leave no light).
[[nodiscard]] Eigen::Vector3d lightOf(const std::array<double, 3>& light);

// A leaf's files by extension, as `model build -o` writes them (the simulation formats through
// the leaf as a plant of one leaf; the model document for .json): the paths written.
[[nodiscard]] std::vector<std::string> exportLeaf(const model::BuiltLeaf& leaf, const std::string& source,
                                                  const std::string& path, const Eigen::Vector3d& light);

// A plant model with its mesh and metrics.
struct PlantModel {
  model::Plant plant;
  model::LeafMesh mesh;
  model::PlantMetrics metrics;
  // An archive's plant keeps its reading, so its MTG and CSV are the import's (as `plant import`
  // writes them); null: built or captured.
  std::shared_ptr<const model::ImportedFile> imported;
  // A captured plant's MTG and CSV: the survey's, as `sessions export` writes them (one MTG for a
  // plant whichever way it is asked for).
  std::optional<std::pair<std::string, std::string>> surveyMtgCsv;
};
// A digitized plant from the archives (`leafdig plant import`): the MTG file, its dressing file
// (empty: none), the unit of its coordinates (mm, cm, m), which plant, meshed at `resolution`.
[[nodiscard]] PlantModel importPlant(const std::string& path, const std::string& drf, const std::string& units,
                                     int plant, const std::string& resolution);
// A plant plan's plants, one per growth time (nullopt: the plan as written), meshed at
// `resolution`: the plant build command's path.
[[nodiscard]] std::vector<PlantModel> buildPlants(const std::string& planText, const std::string& source,
                                                  const std::string& baseDir,
                                                  const std::vector<std::optional<double>>& times,
                                                  const std::string& resolution, const Eigen::Vector3d& light);
// A plant's files by extension (as `plant build -o`): the paths written.
[[nodiscard]] std::vector<std::string> exportPlant(const PlantModel& p, const std::string& path);
// A plant's file of one format as text (the extension names it).
[[nodiscard]] std::string encodeOne(const PlantModel& p, const std::string& extension);

// Nothing of a session whose chain does not recompute is handed to Python: the CLI's words
// (acquisition::SessionError, `refused` appended).
void requireVerified(const db::EventStore& store, std::int64_t id, const std::string& refused);
// A captured plant (a plant session) as a model: the survey's plant with its quick leaves shaped
// from this store's organ library, meshed at the export resolution — the model `sessions export`
// writes as GLB, CARIBU and plant-model JSON.
[[nodiscard]] PlantModel capturedPlant(const db::EventStore& store, std::int64_t id, const Eigen::Vector3d& light);

}  // namespace leafdig::python
