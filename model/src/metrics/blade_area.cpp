#include "leafdig/model/metrics/blade_area.hpp"

#include <cmath>

#include "leafdig/model/mesh/mesh.hpp"

namespace leafdig::model {

namespace {

struct GridAreas {
  double area = 0.0;
  double projected = 0.0;
};

GridAreas gridAreas(const BladeSurface& blade, int perRow, int across, const Eigen::Vector3d& direction) {
  const int rowSpans = static_cast<int>(blade.rowParameters.size()) - 1;
  const PointGrid g = sampleSurface(blade, subdivideSpans(blade.rowParameters, perRow * rowSpans),
                                    subdivideSpans(blade.columnParameters, across));
  GridAreas out;
  for (std::size_t i = 0; i + 1 < g.size(); ++i) {
    for (std::size_t j = 0; j + 1 < g[i].size(); ++j) {
      for (const Eigen::Vector3d& av : {triangleAreaVector(g[i][j], g[i][j + 1], g[i + 1][j + 1]),
                                        triangleAreaVector(g[i][j], g[i + 1][j + 1], g[i + 1][j])}) {
        out.area += av.norm();
        out.projected += std::abs(av.dot(direction));
      }
    }
  }
  return out;
}

}  // namespace

double bladeGridArea(const BladeSurface& blade, int perRow, int across) {
  return gridAreas(blade, perRow, across, Eigen::Vector3d::UnitZ()).area;
}

BladeAreaEstimate convergedBladeArea(const BladeSurface& blade, const Eigen::Vector3d& lightDirection, double tolerance,
                                     int maxDoublings) {
  const Eigen::Vector3d d = lightDirection.normalized();
  int perRow = 2;
  int across = 12;
  GridAreas previous = gridAreas(blade, perRow, across, d);
  BladeAreaEstimate est;
  for (int step = 0; step < maxDoublings; ++step) {
    perRow *= 2;
    across *= 2;
    const GridAreas current = gridAreas(blade, perRow, across, d);
    est = {current.area, current.projected, perRow, across, std::abs(current.area - previous.area) / current.area,
           false};
    if (est.relativeChange < tolerance) {
      est.converged = true;
      break;
    }
    previous = current;
  }
  return est;
}

}  // namespace leafdig::model
