#include "leafdig/model/spline/bspline.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace leafdig::model {

int findSpan(int degree, const KnotVector& knots, double t) {
  const int n = static_cast<int>(knots.size()) - degree - 2;  // index of last control point
  if (t >= knots[n + 1]) return n;
  if (t <= knots[degree]) return degree;
  // upper_bound gives the first knot > t; the span starts one before it.
  const auto it = std::upper_bound(knots.begin() + degree, knots.begin() + n + 2, t);
  return static_cast<int>(it - knots.begin()) - 1;
}

// NURBS Book algorithm A2.3, written with Eigen storage.
Eigen::MatrixXd basisDerivatives(int span, int degree, const KnotVector& knots, double t, int order) {
  const int p = degree;
  Eigen::MatrixXd ndu(p + 1, p + 1);
  std::vector<double> left(p + 1, 0.0);
  std::vector<double> right(p + 1, 0.0);
  ndu(0, 0) = 1.0;
  for (int j = 1; j <= p; ++j) {
    left[j] = t - knots[span + 1 - j];
    right[j] = knots[span + j] - t;
    double saved = 0.0;
    for (int r = 0; r < j; ++r) {
      ndu(j, r) = right[r + 1] + left[j - r];  // lower triangle: knot differences
      const double temp = ndu(r, j - 1) / ndu(j, r);
      ndu(r, j) = saved + right[r + 1] * temp;  // upper triangle: basis functions
      saved = left[j - r] * temp;
    }
    ndu(j, j) = saved;
  }

  Eigen::MatrixXd ders = Eigen::MatrixXd::Zero(order + 1, p + 1);
  for (int j = 0; j <= p; ++j) ders(0, j) = ndu(j, p);

  const int top = std::min(order, p);
  Eigen::MatrixXd a(2, p + 1);
  for (int r = 0; r <= p; ++r) {
    int s1 = 0;
    int s2 = 1;
    a.setZero();
    a(0, 0) = 1.0;
    for (int k = 1; k <= top; ++k) {
      double d = 0.0;
      const int rk = r - k;
      const int pk = p - k;
      if (r >= k) {
        a(s2, 0) = a(s1, 0) / ndu(pk + 1, rk);
        d = a(s2, 0) * ndu(rk, pk);
      }
      const int j1 = (rk >= -1) ? 1 : -rk;
      const int j2 = (r - 1 <= pk) ? k - 1 : p - r;
      for (int j = j1; j <= j2; ++j) {
        a(s2, j) = (a(s1, j) - a(s1, j - 1)) / ndu(pk + 1, rk + j);
        d += a(s2, j) * ndu(rk + j, pk);
      }
      if (r <= pk) {
        a(s2, k) = -a(s1, k - 1) / ndu(pk + 1, r);
        d += a(s2, k) * ndu(r, pk);
      }
      ders(k, r) = d;
      std::swap(s1, s2);
    }
  }
  double factor = p;
  for (int k = 1; k <= top; ++k) {
    ders.row(k) *= factor;
    factor *= (p - k);
  }
  return ders;
}

KnotVector clampedKnots(int degree, const std::vector<double>& interiorKnots) {
  KnotVector knots(degree + 1, 0.0);
  knots.insert(knots.end(), interiorKnots.begin(), interiorKnots.end());
  knots.insert(knots.end(), degree + 1, 1.0);
  return knots;
}

KnotVector clampedUniformKnots(int degree, int controlCount) {
  std::vector<double> interior;
  const int spans = controlCount - degree;
  for (int i = 1; i < spans; ++i) interior.push_back(static_cast<double>(i) / spans);
  return clampedKnots(degree, interior);
}

BSplineCurve::BSplineCurve(int degree, KnotVector knots, Eigen::MatrixXd controlPoints)
    : degree_(degree), knots_(std::move(knots)), control_(std::move(controlPoints)) {
  const auto expected = static_cast<std::size_t>(control_.rows() + degree_ + 1);
  if (degree_ < 1 || control_.rows() < degree_ + 1 || knots_.size() != expected) {
    throw std::invalid_argument("B-spline: " + std::to_string(knots_.size()) + " knots do not fit " +
                                std::to_string(control_.rows()) + " control points of degree " +
                                std::to_string(degree_));
  }
  if (!std::is_sorted(knots_.begin(), knots_.end())) {
    throw std::invalid_argument("B-spline: knots must not decrease");
  }
  for (int i = 0; i < degree_; ++i) {
    if (knots_[i] != knots_[degree_] || knots_[knots_.size() - 1 - i] != knots_.back()) {
      throw std::invalid_argument("B-spline: knot vector must be clamped");
    }
  }
}

Eigen::VectorXd BSplineCurve::evaluate(double t) const {
  return derivatives(t, 0).row(0).transpose();
}

Eigen::MatrixXd BSplineCurve::derivatives(double t, int order) const {
  t = std::clamp(t, knots_.front(), knots_.back());
  const int span = findSpan(degree_, knots_, t);
  const Eigen::MatrixXd basis = basisDerivatives(span, degree_, knots_, t, order);
  // (order+1) x (p+1) times (p+1) x D
  return basis * control_.middleRows(span - degree_, degree_ + 1);
}

}  // namespace leafdig::model
