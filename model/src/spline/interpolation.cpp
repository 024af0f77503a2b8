#include "leafdig/model/spline/interpolation.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

#include "leafdig/model/spline/banded.hpp"

namespace leafdig::model {

std::vector<double> chordLengthParameters(const Eigen::MatrixXd& points, int spatialDims) {
  const auto count = static_cast<int>(points.rows());
  if (count < 2) throw std::invalid_argument("chord-length parameters need at least two points");
  std::vector<double> params(static_cast<std::size_t>(count), 0.0);
  for (int k = 1; k < count; ++k) {
    const double chord = (points.row(k).head(spatialDims) - points.row(k - 1).head(spatialDims)).norm();
    if (!(chord > 0.0)) {
      throw std::invalid_argument("points " + std::to_string(k - 1) + " and " + std::to_string(k) + " coincide");
    }
    params[k] = params[k - 1] + chord;
  }
  const double total = params.back();
  for (double& t : params) t /= total;
  params.back() = 1.0;
  return params;
}

BSplineCurve interpolateNaturalCubic(const std::vector<double>& parameters, const Eigen::MatrixXd& points) {
  constexpr int kDegree = 3;
  const auto m = static_cast<int>(points.rows()) - 1;
  if (m < 1 || static_cast<int>(parameters.size()) != m + 1) {
    throw std::invalid_argument(
        "natural cubic interpolation needs at least two points, one "
        "parameter each");
  }
  if (parameters.front() != 0.0 || parameters.back() != 1.0) {
    throw std::invalid_argument("interpolation parameters must run from 0 to 1");
  }
  for (int k = 1; k <= m; ++k) {
    if (!(parameters[k] > parameters[k - 1])) {
      throw std::invalid_argument("interpolation parameters must increase strictly");
    }
  }
  const KnotVector knots = clampedKnots(kDegree, std::vector<double>(parameters.begin() + 1, parameters.end() - 1));
  const int n = m + 3;  // unknown control points

  // Row order C(t_0), C''(t_0), C(t_1) .. C(t_{m-1}), C''(t_m), C(t_m) makes the matrix
  // tridiagonal: the row for C(t_k), 1 <= k < m, touches control points k..k+2 only.
  BandedMatrix system(n, 1, 1);
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(n, points.cols());
  auto addRow = [&](int row, double t, int derivative) {
    const int span = findSpan(kDegree, knots, t);
    const Eigen::MatrixXd basis = basisDerivatives(span, kDegree, knots, t, derivative);
    for (int j = 0; j <= kDegree; ++j) {
      const double value = basis(derivative, j);
      const int column = span - kDegree + j;
      // Basis functions whose support merely starts or ends at t are zero there (up to
      // rounding); they lie outside the band by construction.
      if (column < row - 1 || column > row + 1) {
        if (std::abs(value) > 1e-9 * std::abs(basis.row(derivative).cwiseAbs().maxCoeff())) {
          throw std::logic_error("natural interpolation: basis outside the band");
        }
        continue;
      }
      system.set(row, column, value);
    }
  };
  addRow(0, 0.0, 0);
  rhs.row(0) = points.row(0);
  addRow(1, 0.0, 2);
  for (int k = 1; k < m; ++k) {
    addRow(k + 1, parameters[k], 0);
    rhs.row(k + 1) = points.row(k);
  }
  addRow(n - 2, 1.0, 2);
  addRow(n - 1, 1.0, 0);
  rhs.row(n - 1) = points.row(m);

  Eigen::MatrixXd control = std::move(system).solve(std::move(rhs));
  return BSplineCurve(kDegree, knots, std::move(control));
}

}  // namespace leafdig::model
