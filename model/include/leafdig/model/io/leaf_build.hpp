// `leafdig model build`'s pipeline in one place, for the CLI (ui/cli/model_build.cpp), the
// Python module (python/, docs/python.md) and the benchmark that compares them: a leaf's model
// (its blade kind, in the digitizer's or the leaf's frame), its mesh, its metrics with the
// silhouette of that mesh; and the same leaf as a plant of one leaf for the simulation formats
// (.can, .mtg, .csv), meshed with the same options and carrying the leaf's own area interval.
#pragma once

#include <Eigen/Core>
#include <string>

#include "leafdig/model/io/plant_export.hpp"
#include "leafdig/model/leaf/blade.hpp"
#include "leafdig/model/leaf/leaf_model.hpp"
#include "leafdig/model/mesh/mesh_method.hpp"
#include "leafdig/model/metrics/metrics.hpp"
#include "leafdig/model/plant/plant.hpp"

namespace leafdig::model {

struct BuiltLeaf {
  LeafModel model;
  std::string frame;  // "digitizer" (as digitized) or "leaf"
  MeshOptions meshOptions;
  LeafMesh mesh;
  LeafMetrics metrics;
};

// Throws InputError for a frame that is neither "digitizer" nor "leaf", and what the model,
// mesh and metrics throw.
[[nodiscard]] BuiltLeaf buildLeafAsModelBuild(const MarkerSet& markers, BladeKind blade, const std::string& frame,
                                              const MeshOptions& mesh, const Eigen::Vector3d& light,
                                              double areaThresholdPercent = 5.0);

struct LeafAsPlant {
  Plant plant;
  LeafMesh mesh;
  PlantMetrics metrics;
};
// CARIBU's leaf field must not be 000 (the stem, opaque): the leaf's position, or 1. `source`
// names the markers the plant's files say it came from.
[[nodiscard]] LeafAsPlant leafAsPlant(const BuiltLeaf& leaf, const std::string& source, const Eigen::Vector3d& light);

}  // namespace leafdig::model
