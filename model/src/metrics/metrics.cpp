#include "leafdig/model/metrics/metrics.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <iomanip>
#include <limits>
#include <sstream>

#include "json_text.hpp"

namespace leafdig::model {

namespace {

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

}  // namespace

double meshArea(const Mesh& mesh) {
  double area = 0.0;
  for (const auto& t : mesh.triangles) {
    area += triangleAreaVector(mesh.positions[t[0]], mesh.positions[t[1]], mesh.positions[t[2]]).norm();
  }
  return area;
}

double projectedArea(const Mesh& mesh, const Eigen::Vector3d& lightDirection) {
  const Eigen::Vector3d d = lightDirection.normalized();
  double area = 0.0;
  for (const auto& t : mesh.triangles) {
    area += std::abs(triangleAreaVector(mesh.positions[t[0]], mesh.positions[t[1]], mesh.positions[t[2]]).dot(d));
  }
  return area;
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

namespace {

// Rows whose points do not run the way the protocol takes them: in the leaf's own plane
// (the markers' principal axes), every row runs right to left across the midrib the same
// way, point after point, and rows follow each other from the tip down the midrib. A row
// taken backwards, a point out of order or rows out of order fold the blade over itself:
// its area counts twice (crossed margins gave three times the area).
void orderWarnings(const MarkerSet& markers, std::vector<Warning>& out) {
  const std::size_t n = markers.rows.size();
  Eigen::Vector3d mean = markers.tipMm;
  for (const MarkerRow& row : markers.rows)
    for (const Eigen::Vector3d& p : row.pointsMm) mean += p;
  mean /= static_cast<double>(1 + kMarkersPerRow * n);
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  for (const MarkerRow& row : markers.rows)
    for (const Eigen::Vector3d& p : row.pointsMm) scatter += (p - mean) * (p - mean).transpose();
  scatter += (markers.tipMm - mean) * (markers.tipMm - mean).transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> axes(scatter);
  const Eigen::Vector3d normal = axes.eigenvectors().col(0);
  const auto inPlane = [&](const Eigen::Vector3d& v) { return Eigen::Vector3d(v - v.dot(normal) * normal); };
  // Across: the sum of the rows' own directions; a row against it runs the other way.
  Eigen::Vector3d across = Eigen::Vector3d::Zero();
  for (const MarkerRow& row : markers.rows) across += inPlane(row.pointsMm[6] - row.pointsMm[0]);
  if (across.norm() == 0.0) return;
  across.normalize();
  std::vector<std::size_t> reversed, folded;
  for (std::size_t i = 0; i < n; ++i) {
    const auto& pts = markers.rows[i].pointsMm;
    if (inPlane(pts[6] - pts[0]).dot(across) < 0) {
      reversed.push_back(i + 1);
      continue;
    }
    for (int j = 0; j + 1 < kMarkersPerRow; ++j)
      if (inPlane(pts[j + 1] - pts[j]).dot(across) < 0) {
        folded.push_back(i + 1);
        break;
      }
  }
  const auto list = [](const std::vector<std::size_t>& rows) {
    std::string s;
    for (std::size_t k = 0; k < rows.size() && k < 8; ++k) s += (k ? ", " : "") + std::to_string(rows[k]);
    return s + (rows.size() > 8 ? ", …" : "");
  };
  if (!reversed.empty())
    out.push_back({"row-reversed", "row" + std::string(reversed.size() > 1 ? "s " : " ") + list(reversed) + " run" +
                                       (reversed.size() > 1 ? "" : "s") +
                                       " the other way across the leaf (left to right): the blade crosses itself "
                                       "there and its area is too large. Retake the row, right to left"});
  if (!folded.empty())
    out.push_back({"row-points-out-of-order",
                   "in row" + std::string(folded.size() > 1 ? "s " : " ") + list(folded) +
                       " a point lies back across the previous one: the blade folds over itself there and its area "
                       "counts twice. Retake the point"});
  // Down the midrib, from the tip: each row's midrib point further along than the last.
  Eigen::Vector3d down = inPlane(markers.rows.back().pointsMm[kMidribColumn] - markers.tipMm);
  if (down.norm() == 0.0) return;
  down.normalize();
  std::vector<std::size_t> behind;
  double previous = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const double along = inPlane(markers.rows[i].pointsMm[kMidribColumn] - markers.tipMm).dot(down);
    if (along <= previous) behind.push_back(i + 1);
    previous = std::max(previous, along);
  }
  if (!behind.empty())
    out.push_back({"rows-out-of-order", "row" + std::string(behind.size() > 1 ? "s " : " ") + list(behind) +
                                            " lie nearer the tip than the row before: the blade folds back on itself "
                                            "and its area counts twice. Rows are taken from the tip to the base"});
}

}  // namespace

std::vector<Warning> captureWarnings(const MarkerSet& markers) {
  std::vector<Warning> out;
  const std::size_t n = markers.rows.size();
  if (n < 2) return out;
  orderWarnings(markers, out);
  const auto width = [&](std::size_t i) { return (markers.rows[i].pointsMm[0] - markers.rows[i].pointsMm[6]).norm(); };
  double widest = 0.0;
  std::size_t widestRow = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (width(i) > widest) {
      widest = width(i);
      widestRow = i;
    }
  }
  const double last = width(n - 1);
  if (widest > 0.0 && last >= kBaseRowWidthWarningRatio * widest) {
    std::ostringstream msg;
    msg << std::fixed << std::setprecision(0) << "the last row (row " << n << ") is " << 100.0 * last / widest
        << " % as wide as the widest (row " << widestRow + 1
        << "): either it was not at the leaf base, where the blade meets the stem or petiole, or the base is broad "
           "(winged or cordate) and its lowest veins meet the margin far up. The model ends at row "
        << n << "'s veins and its area falls short of the whole leaf's; if the row was not at the base, capture the "
        << "leaf again with it there.";
    out.push_back({"last-row-not-at-base", msg.str()});
  }
  return out;
}

LeafMetrics computeLeafMetrics(const LeafModel& model, const Eigen::Vector3d& lightDirection,
                               double areaThresholdPercent) {
  LeafMetrics m{convergedBladeArea(model.blade, lightDirection),
                lightDirection.normalized(),
                markerGridHeronArea(markerGrid(model.markers)),
                std::nullopt,
                std::nullopt,
                captureWarnings(model.markers),
                std::nullopt};
  if (model.markers.leaf.measuredAreaMm2) {
    m.areaConstraint = compareArea(m.blade.areaMm2, *model.markers.leaf.measuredAreaMm2, areaThresholdPercent);
  }
  // A NURBS blade with weights of its own is rebuilt by the draws only from markers, which
  // would lose the weights: no interval for it (docs/accuracy.md).
  bool ownWeights = false;
  for (const auto& row : model.blade.weights) {
    for (double w : row) ownWeights = ownWeights || w != 1.0;
  }
  if (!ownWeights) {
    AreaUncertaintyOptions options;
    options.blade = model.blade.kind;
    m.areaInterval = areaUncertainty(model.markers, options);
  }
  return m;
}

LeafSilhouette leafSilhouette(const Mesh& blade, const Eigen::Vector3d& lightDirection) {
  LeafSilhouette out;
  out.meshAreaMm2 = meshArea(blade);
  // 1024 pixels across one leaf: within 0.2 % of a 4096-pixel raster on the samples
  // (plant_test), at a quarter of the cost.
  out.silhouetteMm2 = silhouetteArea({&blade}, lightDirection.normalized(), 1024);
  out.star = out.meshAreaMm2 > 0 ? out.silhouetteMm2 / out.meshAreaMm2 : 0.0;
  return out;
}

void addSilhouette(LeafMetrics& metrics, const LeafMesh& mesh) {
  for (const Organ& organ : mesh.organs)
    if (organ.kind == OrganKind::Blade) {
      metrics.silhouette = leafSilhouette(organ.mesh, metrics.lightDirection);
      return;
    }
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
  if (m.silhouette) {
    j["silhouette_mm2"] = m.silhouette->silhouetteMm2;
    j["star"] = m.silhouette->star;
    j["mesh_area_mm2"] = m.silhouette->meshAreaMm2;
  }
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
  j["warnings"] = nlohmann::json::array();
  for (const Warning& w : m.warnings) j["warnings"].push_back({{"name", w.name}, {"message", w.message}});
  if (m.areaInterval) {
    const AreaUncertainty& u = *m.areaInterval;
    j["blade_area_95_mm2"] = {u.low95Mm2, u.high95Mm2};
    j["area_interval"] = {{"low_mm2", u.low95Mm2},
                          {"high_mm2", u.high95Mm2},
                          {"digitizer_sigma_mm", u.sigmaMm},
                          {"draws", u.draws},
                          {"noise_low_mm2", u.noiseLowMm2},
                          {"noise_high_mm2", u.noiseHighMm2},
                          {"row_drop_mm2", u.interpolationMm2},
                          {"systematic_mm2", u.systematicMm2},
                          {"margin_low_mm2", u.marginLowMm2},
                          {"margin_high_mm2", u.marginHighMm2},
                          {"margin", u.margin},
                          {"note", u.note.empty() ? nlohmann::json(nullptr) : nlohmann::json(u.note)}};
  } else {
    j["blade_area_95_mm2"] = nullptr;
    j["area_interval"] = nullptr;
  }
  return detail::dumpFinite(j);
}

}  // namespace leafdig::model

namespace leafdig::model {

double silhouetteArea(const std::vector<const Mesh*>& meshes, const Eigen::Vector3d& direction, int pixels) {
  const Eigen::Vector3d d = direction.normalized();
  // An orthonormal basis (e1, e2) of the projection plane.
  const Eigen::Vector3d helper = std::abs(d.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  const Eigen::Vector3d e1 = d.cross(helper).normalized();
  const Eigen::Vector3d e2 = d.cross(e1);
  Eigen::Vector2d lo(std::numeric_limits<double>::max(), std::numeric_limits<double>::max());
  Eigen::Vector2d hi = -lo;
  for (const Mesh* m : meshes) {
    for (const auto& p : m->positions) {
      const Eigen::Vector2d q(p.dot(e1), p.dot(e2));
      lo = lo.cwiseMin(q);
      hi = hi.cwiseMax(q);
    }
  }
  const double extent = (hi - lo).maxCoeff();
  if (!(extent > 0.0) || pixels < 1) return 0.0;
  const double pixel = extent / pixels;
  const auto nx = static_cast<long>(std::ceil((hi.x() - lo.x()) / pixel)) + 1;
  const auto ny = static_cast<long>(std::ceil((hi.y() - lo.y()) / pixel)) + 1;
  std::vector<std::uint8_t> covered(static_cast<std::size_t>(nx * ny), 0);
  // Scanlines through pixel centres: each triangle marks the run of centres inside it on
  // every row it spans (half-open, so a shared edge is not counted twice; no matter here,
  // as coverage is a union anyway).
  for (const Mesh* m : meshes) {
    for (const auto& t : m->triangles) {
      Eigen::Vector2d v[3];
      for (int k = 0; k < 3; ++k) {
        const Eigen::Vector3d& p = m->positions[t[static_cast<std::size_t>(k)]];
        v[k] = (Eigen::Vector2d(p.dot(e1), p.dot(e2)) - lo) / pixel;
      }
      const double area2 = (v[1] - v[0]).x() * (v[2] - v[0]).y() - (v[1] - v[0]).y() * (v[2] - v[0]).x();
      if (std::abs(area2) < 1e-12) continue;  // seen edge-on
      const double ymin = std::min({v[0].y(), v[1].y(), v[2].y()});
      const double ymax = std::max({v[0].y(), v[1].y(), v[2].y()});
      const long r0 = std::max(0L, static_cast<long>(std::ceil(ymin - 0.5)));
      const long r1 = std::min(ny - 1, static_cast<long>(std::ceil(ymax - 0.5)) - 1);
      for (long y = r0; y <= r1; ++y) {
        const double cy = static_cast<double>(y) + 0.5;
        double xl = std::numeric_limits<double>::max();
        double xr = std::numeric_limits<double>::lowest();
        for (int k = 0; k < 3; ++k) {
          const Eigen::Vector2d& a = v[k];
          const Eigen::Vector2d& b = v[(k + 1) % 3];
          if ((a.y() <= cy && cy < b.y()) || (b.y() <= cy && cy < a.y())) {
            const double x = a.x() + (cy - a.y()) * (b.x() - a.x()) / (b.y() - a.y());
            xl = std::min(xl, x);
            xr = std::max(xr, x);
          }
        }
        if (xl > xr) continue;
        const long c0 = std::max(0L, static_cast<long>(std::ceil(xl - 0.5)));
        const long c1 = std::min(nx, static_cast<long>(std::ceil(xr - 0.5)));
        if (c1 > c0) std::fill_n(covered.begin() + y * nx + c0, c1 - c0, static_cast<std::uint8_t>(1));
      }
    }
  }
  std::size_t count = 0;
  for (std::uint8_t c : covered) count += c;
  return static_cast<double>(count) * pixel * pixel;
}

}  // namespace leafdig::model
