#pragma once
// Natural cubic spline interpolation in B-spline form (NURBS Book §9.2.1 with the natural
// end conditions of docs/method.md §3), for points of any dimension.
#include <Eigen/Core>
#include <vector>

#include "leafdig/model/spline/bspline.hpp"

namespace leafdig::model {

// Chord-length parameters over the first `spatialDims` columns of `points` (#points by D):
// t_0 = 0, t_k = t_{k-1} + |Q_k - Q_{k-1}| / L, t_last = 1 exactly. A ball B-spline passes
// spatialDims = 3 so the radius column does not stretch the parameters.
// Throws std::invalid_argument when two consecutive points coincide (a zero chord).
[[nodiscard]] std::vector<double> chordLengthParameters(const Eigen::MatrixXd& points, int spatialDims);

// The cubic B-spline through points Q_0..Q_m (rows of `points`) at the given strictly
// increasing parameters from 0 to 1, with second derivative zero at both ends.
// Knots {0,0,0,0, t_1..t_{m-1}, 1,1,1,1}, m+3 control points; m = 1 gives a straight line.
// Solved as one tridiagonal-band system for all D columns at once.
[[nodiscard]] BSplineCurve interpolateNaturalCubic(const std::vector<double>& parameters,
                                                   const Eigen::MatrixXd& points);

}  // namespace leafdig::model
