#include "leafdig/model/io/leaf_build.hpp"

#include <algorithm>

#include "leafdig/model/errors.hpp"
#include "leafdig/model/mesh/mesh.hpp"

namespace leafdig::model {

BuiltLeaf buildLeafAsModelBuild(const MarkerSet& markers, BladeKind blade, const std::string& frame,
                                const MeshOptions& mesh, const Eigen::Vector3d& light, double areaThresholdPercent) {
  if (frame != "digitizer" && frame != "leaf")
    throw InputError("frame \"" + frame + "\" is not one: \"digitizer\" (as digitized) or \"leaf\"");
  BuiltLeaf out;
  out.model = buildLeafModel(markers, {blade, nullptr});
  if (frame == "leaf") out.model = transformed(out.model, leafFrameFromDigitizer(out.model));
  out.frame = frame;
  out.meshOptions = mesh;
  out.mesh = meshLeaf(out.model, mesh);
  out.metrics = computeLeafMetrics(out.model, light, areaThresholdPercent);
  addSilhouette(out.metrics, out.mesh);
  return out;
}

LeafAsPlant leafAsPlant(const BuiltLeaf& leaf, const std::string& source, const Eigen::Vector3d& light) {
  const int rank = std::clamp(leaf.model.markers.leaf.position.value_or(1), 1, 999);
  LeafAsPlant out{singleLeafPlant(leaf.model, rank, source), {}, {}};
  out.mesh = meshPlant(out.plant, leaf.meshOptions);
  out.metrics = computePlantMetrics(out.plant, out.mesh, light);
  if (leaf.metrics.areaInterval && !out.metrics.leaves.empty()) {  // the leaf's own, already computed
    out.metrics.leaves.front().bladeAreaLow95Mm2 = leaf.metrics.areaInterval->low95Mm2;
    out.metrics.leaves.front().bladeAreaHigh95Mm2 = leaf.metrics.areaInterval->high95Mm2;
  }
  return out;
}

}  // namespace leafdig::model
