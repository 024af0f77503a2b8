#include "leafdig/model/metrics.hpp"

#include <algorithm>
#include <array>
#include <cmath>

namespace leafdig::model {

namespace {

Eigen::Vector3d areaVector(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  return 0.5 * (b - a).cross(c - a);
}

// Kahan's numerically stable Heron formula (sides sorted a >= b >= c).
double heronArea(const Eigen::Vector3d& p, const Eigen::Vector3d& q, const Eigen::Vector3d& r) {
  std::array<double, 3> s{(p - q).norm(), (q - r).norm(), (r - p).norm()};
  std::sort(s.begin(), s.end(), std::greater<>());
  const double a = s[0];
  const double b = s[1];
  const double c = s[2];
  const double product = (a + (b + c)) * (c - (a - b)) * (c + (a - b)) * (a + (b - c));
  return product > 0.0 ? 0.25 * std::sqrt(product) : 0.0;
}

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
      for (const Eigen::Vector3d& av :
           {areaVector(g[i][j], g[i][j + 1], g[i + 1][j + 1]), areaVector(g[i][j], g[i + 1][j + 1], g[i + 1][j])}) {
        out.area += av.norm();
        out.projected += std::abs(av.dot(direction));
      }
    }
  }
  return out;
}

}  // namespace

double meshArea(const Mesh& mesh) {
  double area = 0.0;
  for (const auto& t : mesh.triangles) {
    area += areaVector(mesh.positions[t[0]], mesh.positions[t[1]], mesh.positions[t[2]]).norm();
  }
  return area;
}

double projectedArea(const Mesh& mesh, const Eigen::Vector3d& lightDirection) {
  const Eigen::Vector3d d = lightDirection.normalized();
  double area = 0.0;
  for (const auto& t : mesh.triangles) {
    area += std::abs(areaVector(mesh.positions[t[0]], mesh.positions[t[1]], mesh.positions[t[2]]).dot(d));
  }
  return area;
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

double markerGridHeronArea(const MarkerGrid& grid) {
  double area = 0.0;
  for (std::size_t k = 0; k + 1 < grid.size(); ++k) {
    for (int l = 0; l + 1 < kMarkersPerRow; ++l) {
      const auto& p00 = grid[k][l];
      const auto& p01 = grid[k][l + 1];
      const auto& p10 = grid[k + 1][l];
      const auto& p11 = grid[k + 1][l + 1];
      const double first = heronArea(p00, p10, p11) + heronArea(p00, p11, p01);
      const double second = heronArea(p00, p10, p01) + heronArea(p10, p11, p01);
      area += 0.5 * (first + second);
    }
  }
  return area;
}

AreaConstraint compareArea(double modelMm2, double measuredMm2, double thresholdPercent) {
  const double diff = (modelMm2 - measuredMm2) / measuredMm2 * 100.0;
  return {measuredMm2, modelMm2, diff, thresholdPercent, std::abs(diff) > thresholdPercent};
}

}  // namespace leafdig::model

#include <nlohmann/json.hpp>

namespace leafdig::model {

LeafMetrics computeLeafMetrics(const LeafModel& model, const Eigen::Vector3d& lightDirection,
                               double areaThresholdPercent) {
  LeafMetrics m{convergedBladeArea(model.blade, lightDirection), lightDirection.normalized(),
                markerGridHeronArea(markerGrid(model.markers)), std::nullopt};
  if (model.markers.leaf.measuredAreaMm2) {
    m.areaConstraint = compareArea(m.blade.areaMm2, *model.markers.leaf.measuredAreaMm2, areaThresholdPercent);
  }
  return m;
}

std::string metricsToJson(const LeafMetrics& m) {
  nlohmann::json j;
  j["blade_area_mm2"] = m.blade.areaMm2;
  j["projected_area_mm2"] = m.blade.projectedAreaMm2;
  j["light_direction"] = {m.lightDirection.x(), m.lightDirection.y(), m.lightDirection.z()};
  j["area_resolution"] = {{"segments_per_row", m.blade.segmentsPerRow},
                          {"segments_across", m.blade.segmentsAcross},
                          {"relative_change", m.blade.relativeChange},
                          {"converged", m.blade.converged}};
  j["marker_grid_heron_area_mm2"] = m.markerGridHeronAreaMm2;
  if (m.areaConstraint) {
    const AreaConstraint& a = *m.areaConstraint;
    j["area_constraint"] = {{"measured_mm2", a.measuredMm2},
                            {"model_mm2", a.modelMm2},
                            {"difference_percent", a.differencePercent},
                            {"threshold_percent", a.thresholdPercent},
                            {"exceeded", a.exceeded}};
  } else {
    j["area_constraint"] = nullptr;
  }
  return j.dump();
}

}  // namespace leafdig::model
