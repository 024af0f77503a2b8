// The leaf frame needs the blade's mean normal, measured on a coarse mesh of it: it lives
// with the meshes, not with the leaf model (which meshes nothing).
#include "leafdig/model/mesh/mesh.hpp"

namespace leafdig::model {

Eigen::Isometry3d leafFrameFromDigitizer(const LeafModel& model) {
  const Eigen::Vector3d origin = model.markers.rows.back().pointsMm[kMidribColumn];
  const Eigen::Vector3d y = (model.markers.tipMm - origin).normalized();
  // Mean adaxial normal: the blade's triangles face the adaxial side, so their summed
  // area vectors point there.
  const Mesh blade = meshBlade(model.blade, 4, 24);
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();
  for (const auto& tri : blade.triangles) {
    const Eigen::Vector3d& a = blade.positions[tri[0]];
    normal += (blade.positions[tri[1]] - a).cross(blade.positions[tri[2]] - a);
  }
  Eigen::Vector3d z = normal - normal.dot(y) * y;
  if (z.norm() < 1e-12) {
    // A blade seen edge-on along its own axis: any perpendicular will do, keep it stable.
    z = y.unitOrthogonal();
  }
  z.normalize();
  const Eigen::Vector3d x = y.cross(z);
  Eigen::Matrix3d axes;
  axes << x, y, z;  // columns: leaf axes in digitizer coordinates
  Eigen::Isometry3d toLeaf = Eigen::Isometry3d::Identity();
  toLeaf.linear() = axes.transpose();
  toLeaf.translation() = -(axes.transpose() * origin);
  return toLeaf;
}

}  // namespace leafdig::model
