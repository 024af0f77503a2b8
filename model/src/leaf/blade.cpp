#include "leafdig/model/leaf/blade.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "leafdig/model/errors.hpp"
#include "leafdig/model/spline/interpolation.hpp"
#include "leafdig/names/name_table.hpp"

namespace leafdig::model {

const char* toString(BladeKind kind) {
  return nameIn(kBladeKindNames, kind);
}

BladeKind bladeKindFromString(const std::string& word) {
  return parseName(kBladeKindNames, word, "blade kind");
}

namespace {

// Basis values of `degree` at each t, scattered into a dense row of length `count`.
Eigen::MatrixXd basisRows(int degree, const KnotVector& knots, int count, const std::vector<double>& ts) {
  Eigen::MatrixXd rows = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(ts.size()), count);
  for (std::size_t a = 0; a < ts.size(); ++a) {
    const double t = std::clamp(ts[a], knots.front(), knots.back());
    const int span = findSpan(degree, knots, t);
    const Eigen::MatrixXd b = basisDerivatives(span, degree, knots, t, 0);
    rows.block(static_cast<Eigen::Index>(a), span - degree, 1, degree + 1) = b;
  }
  return rows;
}

std::vector<double> uniformBreaks(int spans) {
  std::vector<double> breaks(static_cast<std::size_t>(spans + 1));
  for (int i = 0; i <= spans; ++i) breaks[i] = static_cast<double>(i) / spans;
  return breaks;
}

std::vector<double> averageNormalisedChords(const std::vector<std::vector<double>>& chordSets, std::size_t count) {
  std::vector<double> params(count, 0.0);
  int used = 0;
  for (const auto& chords : chordSets) {
    double total = 0.0;
    for (double c : chords) total += c;
    if (!(total > 0.0)) continue;  // e.g. the tip row: all chords vanish
    ++used;
    double acc = 0.0;
    for (std::size_t k = 1; k < count; ++k) {
      acc += chords[k - 1] / total;
      params[k] += acc;
    }
  }
  if (used == 0) throw std::invalid_argument("all chords vanish: the grid is degenerate");
  for (double& p : params) p /= used;
  params.back() = 1.0;
  return params;
}

}  // namespace

std::vector<double> averagedParametersU(const MarkerGrid& grid) {
  std::vector<std::vector<double>> sets;
  for (int l = 0; l < kMarkersPerRow; ++l) {
    std::vector<double> chords;
    for (std::size_t k = 1; k < grid.size(); ++k) chords.push_back((grid[k][l] - grid[k - 1][l]).norm());
    sets.push_back(std::move(chords));
  }
  return averageNormalisedChords(sets, grid.size());
}

std::vector<double> averagedParametersV(const MarkerGrid& grid) {
  std::vector<std::vector<double>> sets;
  for (const auto& row : grid) {
    std::vector<double> chords;
    for (int l = 1; l < kMarkersPerRow; ++l) chords.push_back((row[l] - row[l - 1]).norm());
    sets.push_back(std::move(chords));
  }
  return averageNormalisedChords(sets, kMarkersPerRow);
}

Eigen::Vector3d BladeSurface::evaluate(double u, double v) const {
  // Local support only: the (p+1) x (q+1) control points whose basis functions are non-zero.
  u = std::clamp(u, knotsU.front(), knotsU.back());
  v = std::clamp(v, knotsV.front(), knotsV.back());
  const int su = findSpan(degreeU, knotsU, u);
  const int sv = findSpan(degreeV, knotsV, v);
  const Eigen::MatrixXd bu = basisDerivatives(su, degreeU, knotsU, u, 0);
  const Eigen::MatrixXd bv = basisDerivatives(sv, degreeV, knotsV, v, 0);
  const bool rational = !weights.empty();
  Eigen::Vector4d h = Eigen::Vector4d::Zero();
  for (int a = 0; a <= degreeU; ++a) {
    const auto i = static_cast<std::size_t>(su - degreeU + a);
    for (int b = 0; b <= degreeV; ++b) {
      const auto j = static_cast<std::size_t>(sv - degreeV + b);
      const double w = (rational ? weights[i][j] : 1.0) * bu(0, a) * bv(0, b);
      h.head<3>() += w * controlNet[i][j];
      h(3) += w;
    }
  }
  return h.head<3>() / h(3);
}

PointGrid sampleSurface(const BladeSurface& s, const std::vector<double>& us, const std::vector<double>& vs) {
  const auto nu = static_cast<int>(s.controlNet.size());
  const auto nv = static_cast<int>(s.controlNet.front().size());
  const bool rational = !s.weights.empty();
  const Eigen::MatrixXd bv = basisRows(s.degreeV, s.knotsV, nv, vs);
  // Homogeneous control net, nu by (4 nv): [w x, w y, w z, w] per control point.
  Eigen::MatrixXd net(nu, 4 * nv);
  for (int i = 0; i < nu; ++i) {
    for (int j = 0; j < nv; ++j) {
      const double w = rational ? s.weights[i][j] : 1.0;
      net.block<1, 3>(i, 4 * j) = w * s.controlNet[i][j].transpose();
      net(i, 4 * j + 3) = w;
    }
  }
  // Curves in v, one per u: only the degreeU + 1 basis functions that are non-zero at u
  // contribute (local support), summed in order of the control rows, so the cost is linear in
  // the rows (a dense #us-by-nu product made 1 000 rows cost seconds; issue 26).
  Eigen::MatrixXd along = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(us.size()), 4 * nv);
  for (std::size_t a = 0; a < us.size(); ++a) {
    const double u = std::clamp(us[a], s.knotsU.front(), s.knotsU.back());
    const int span = findSpan(s.degreeU, s.knotsU, u);
    const Eigen::MatrixXd b = basisDerivatives(span, s.degreeU, s.knotsU, u, 0);
    for (int c = 0; c < 4 * nv; ++c) {
      double sum = 0.0;
      for (int k = 0; k <= s.degreeU; ++k) sum += b(0, k) * net(span - s.degreeU + k, c);
      along(static_cast<Eigen::Index>(a), c) = sum;
    }
  }
  PointGrid out(us.size(), std::vector<Eigen::Vector3d>(vs.size()));
  for (std::size_t a = 0; a < us.size(); ++a) {
    for (std::size_t b = 0; b < vs.size(); ++b) {
      Eigen::Vector4d h = Eigen::Vector4d::Zero();
      for (int j = 0; j < nv; ++j) {
        const double nvb = bv(static_cast<Eigen::Index>(b), j);
        if (nvb == 0.0) continue;
        for (int c = 0; c < 4; ++c) h(c) += nvb * along(static_cast<Eigen::Index>(a), 4 * j + c);
      }
      out[a][b] = h.head<3>() / h(3);
    }
  }
  return out;
}

BladeSurface buildBlade(const MarkerGrid& grid, BladeKind kind, const std::vector<std::vector<double>>* weights) {
  const int rows = static_cast<int>(grid.size());  // N + 1
  if (rows < 2) throw std::invalid_argument("a blade needs the tip and at least one row");
  BladeSurface s;
  s.kind = kind;
  if (kind == BladeKind::Interp) {
    s.rowParameters = averagedParametersU(grid);
    s.columnParameters = averagedParametersV(grid);
    // Columns first: each column of markers becomes a natural cubic in u ...
    std::vector<Eigen::MatrixXd> columns;
    for (int l = 0; l < kMarkersPerRow; ++l) {
      Eigen::MatrixXd pts(rows, 3);
      for (int k = 0; k < rows; ++k) pts.row(k) = grid[k][l].transpose();
      columns.push_back(interpolateNaturalCubic(s.rowParameters, pts).controlPoints());
    }
    s.knotsU = clampedKnots(3, std::vector<double>(s.rowParameters.begin() + 1, s.rowParameters.end() - 1));
    s.knotsV = clampedKnots(3, std::vector<double>(s.columnParameters.begin() + 1, s.columnParameters.end() - 1));
    // ... then each row of those control points is interpolated in v.
    const auto nu = columns.front().rows();
    for (Eigen::Index i = 0; i < nu; ++i) {
      Eigen::MatrixXd pts(kMarkersPerRow, 3);
      for (int l = 0; l < kMarkersPerRow; ++l) pts.row(l) = columns[l].row(i);
      const Eigen::MatrixXd ctrl = interpolateNaturalCubic(s.columnParameters, pts).controlPoints();
      std::vector<Eigen::Vector3d> netRow;
      for (Eigen::Index j = 0; j < ctrl.rows(); ++j) netRow.emplace_back(ctrl.row(j).transpose());
      s.controlNet.push_back(std::move(netRow));
    }
    return s;
  }

  for (const auto& row : grid) s.controlNet.emplace_back(row.begin(), row.end());
  s.rowParameters = uniformBreaks(rows - 1);
  s.columnParameters = uniformBreaks(kMarkersPerRow - 1);
  if (kind == BladeKind::Bezier) {
    s.degreeU = rows - 1;
    s.degreeV = kMarkersPerRow - 1;
  } else {
    s.degreeU = std::min(3, rows - 1);
    s.degreeV = 3;
  }
  s.knotsU = clampedUniformKnots(s.degreeU, rows);
  s.knotsV = clampedUniformKnots(s.degreeV, kMarkersPerRow);
  if (kind == BladeKind::Nurbs) {
    s.weights.assign(static_cast<std::size_t>(rows), std::vector<double>(kMarkersPerRow, 1.0));
    if (weights != nullptr) {
      if (static_cast<int>(weights->size()) != rows) {
        throw InputError("nurbs weights: expected " + std::to_string(rows) +
                         " rows (the tip row and every marker row)");
      }
      for (int k = 0; k < rows; ++k) {
        if ((*weights)[k].size() != kMarkersPerRow) {
          throw InputError("nurbs weights: row " + std::to_string(k) + " needs 7 weights");
        }
        for (int l = 0; l < kMarkersPerRow; ++l) {
          const double w = (*weights)[k][l];
          if (!(w > 0.0) || !std::isfinite(w)) {
            throw InputError("nurbs weights: row " + std::to_string(k) + ", point " + std::to_string(l + 1) +
                             " must be a positive number");
          }
          s.weights[k][l] = w;
        }
      }
    }
  }
  return s;
}

}  // namespace leafdig::model
