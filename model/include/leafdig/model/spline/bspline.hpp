#pragma once
// B-spline basis functions and curves on arbitrary clamped knot vectors.
//
// Conventions (NURBS Book, Piegl & Tiller): degree p, knots u_0..u_m, n+1 = m-p control
// points. Control points are stored one per row of an Eigen matrix (#control by D), so a
// curve of any dimension D uses the same code: 3 for centre curves, 4 for ball B-splines
// (x, y, z, r).
#include <Eigen/Core>
#include <vector>

namespace leafdig::model {

using KnotVector = std::vector<double>;

// Index s of the knot span with knots[s] <= t < knots[s+1]; t at the last knot maps to the
// last non-empty span, so the end of a clamped curve is evaluated, not extrapolated.
[[nodiscard]] int findSpan(int degree, const KnotVector& knots, double t);

// Values and derivatives of the degree+1 basis functions that are non-zero on `span` at t.
// Returns (order+1) by (degree+1): row k holds d^k/dt^k N_{span-degree+j}(t), j = 0..degree.
[[nodiscard]] Eigen::MatrixXd basisDerivatives(int span, int degree, const KnotVector& knots, double t, int order);

// A clamped knot vector: `degree+1` copies of 0, the interior knots, `degree+1` copies of 1.
[[nodiscard]] KnotVector clampedKnots(int degree, const std::vector<double>& interiorKnots);

// Clamped knots with uniformly spaced interior knots for `controlCount` control points.
[[nodiscard]] KnotVector clampedUniformKnots(int degree, int controlCount);

// A non-rational B-spline curve of any dimension. Immutable after construction.
class BSplineCurve {
 public:
  // controlPoints: #control by D. Throws std::invalid_argument when the knot vector does
  // not fit (size != #control + degree + 1, decreasing, or not clamped).
  BSplineCurve(int degree, KnotVector knots, Eigen::MatrixXd controlPoints);

  [[nodiscard]] int degree() const { return degree_; }
  [[nodiscard]] const KnotVector& knots() const { return knots_; }
  [[nodiscard]] const Eigen::MatrixXd& controlPoints() const { return control_; }
  [[nodiscard]] int dimension() const { return static_cast<int>(control_.cols()); }

  // Point at t (clamped to the parameter range), a D-vector.
  [[nodiscard]] Eigen::VectorXd evaluate(double t) const;

  // (order+1) by D: row k is the k-th derivative at t. Derivatives above the degree are 0.
  [[nodiscard]] Eigen::MatrixXd derivatives(double t, int order) const;

 private:
  int degree_;
  KnotVector knots_;
  Eigen::MatrixXd control_;
};

}  // namespace leafdig::model
