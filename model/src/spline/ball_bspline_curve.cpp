#include "leafdig/model/spline/ball_bspline_curve.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

#include "leafdig/model/spline/interpolation.hpp"

namespace leafdig::model {

BallBSplineCurve BallBSplineCurve::interpolate(const std::vector<Ball>& dataBalls) {
  if (dataBalls.size() < 2) {
    throw std::invalid_argument("a ball B-spline curve needs at least two data balls");
  }
  Eigen::MatrixXd data(static_cast<Eigen::Index>(dataBalls.size()), 4);
  for (std::size_t k = 0; k < dataBalls.size(); ++k) {
    const auto row = static_cast<Eigen::Index>(k);
    data.block<1, 3>(row, 0) = dataBalls[k].center.transpose();
    data(row, 3) = dataBalls[k].radius;
  }
  std::vector<double> params = chordLengthParameters(data, 3);
  BSplineCurve spline = interpolateNaturalCubic(params, data);
  return {std::move(spline), std::move(params), dataBalls};
}

BallBSplineCurve::BallBSplineCurve(BSplineCurve spline, std::vector<double> dataParameters, std::vector<Ball> dataBalls)
    : spline_(std::move(spline)), dataParameters_(std::move(dataParameters)), dataBalls_(std::move(dataBalls)) {
  if (spline_.dimension() != 4) {
    throw std::invalid_argument("a ball B-spline curve is a 4-D spline (x, y, z, r), got " +
                                std::to_string(spline_.dimension()) + "-D");
  }
}

BallBSplineCurve::Jet BallBSplineCurve::jet(double t) const {
  const Eigen::MatrixXd d = spline_.derivatives(t, 2);
  Jet j{};
  j.c = d.block<1, 3>(0, 0).transpose();
  j.dc = d.block<1, 3>(1, 0).transpose();
  j.ddc = d.block<1, 3>(2, 0).transpose();
  j.r = d(0, 3);
  j.dr = d(1, 3);
  j.ddr = d(2, 3);
  return j;
}

Eigen::Vector3d BallBSplineCurve::center(double t) const {
  return spline_.evaluate(t).head<3>();
}

double BallBSplineCurve::radius(double t) const {
  return spline_.evaluate(t)(3);
}

BallBSplineCurve::Circle BallBSplineCurve::envelopeCircle(double t) const {
  return envelopeCircle(jet(t));
}

BallBSplineCurve::Circle BallBSplineCurve::envelopeCircle(const Jet& j) {
  const double speed2 = j.dc.squaredNorm();
  if (!(j.r > 0.0) || !(speed2 > j.dr * j.dr)) {
    // No envelope here: fall back to the ball's great circle so the mesh stays finite.
    return {j.c, std::max(j.r, 0.0), false};
  }
  const Eigen::Vector3d centre = j.c - (j.r * j.dr / speed2) * j.dc;
  const double rho = (j.r / std::sqrt(speed2)) * std::sqrt(speed2 - j.dr * j.dr);
  return {centre, rho, true};
}

Eigen::Vector3d BallBSplineCurve::envelopePoint(double t, double theta, const Frame& frame) const {
  const Circle circle = envelopeCircle(t);
  return circle.center + circle.radius * (std::cos(theta) * frame.normal + std::sin(theta) * frame.binormal);
}

namespace {

Eigen::Vector3d leastAlignedAxis(const Eigen::Vector3d& tangent) {
  Eigen::Index axis = 0;
  tangent.cwiseAbs().minCoeff(&axis);
  return Eigen::Vector3d::Unit(axis);
}

Eigen::Vector3d unitTangent(const Eigen::Vector3d& d) {
  const double n = d.norm();
  return n > 0.0 ? Eigen::Vector3d(d / n) : Eigen::Vector3d::UnitX();
}

}  // namespace

std::vector<Frame> rotationMinimisingFrames(const BallBSplineCurve& curve, const std::vector<double>& ts,
                                            const Eigen::Vector3d* firstNormalHint) {
  std::vector<Eigen::Vector3d> points;
  std::vector<Eigen::Vector3d> derivatives;
  for (double t : ts) {
    const auto j = curve.jet(t);
    points.push_back(j.c);
    derivatives.push_back(j.dc);
  }
  return rotationMinimisingFrames(points, derivatives, firstNormalHint);
}

std::vector<Frame> rotationMinimisingFrames(const std::vector<Eigen::Vector3d>& points,
                                            const std::vector<Eigen::Vector3d>& derivatives,
                                            const Eigen::Vector3d* firstNormalHint) {
  std::vector<Frame> frames;
  if (points.empty()) return frames;
  frames.reserve(points.size());

  Eigen::Vector3d t0 = unitTangent(derivatives.front());
  Eigen::Vector3d hint = firstNormalHint != nullptr ? *firstNormalHint : leastAlignedAxis(t0);
  Eigen::Vector3d n0 = hint - hint.dot(t0) * t0;
  if (n0.norm() < 1e-9) {
    hint = leastAlignedAxis(t0);
    n0 = hint - hint.dot(t0) * t0;
  }
  n0.normalize();
  frames.push_back({t0, n0, t0.cross(n0)});

  for (std::size_t i = 1; i < points.size(); ++i) {
    const Frame& prev = frames.back();
    const Eigen::Vector3d& x0 = points[i - 1];
    const Eigen::Vector3d& x1 = points[i];
    const Eigen::Vector3d t1 = unitTangent(derivatives[i]);
    // Reflection 1 across the bisector plane of x0, x1.
    const Eigen::Vector3d v1 = x1 - x0;
    const double c1 = v1.squaredNorm();
    Eigen::Vector3d rL = prev.normal;
    Eigen::Vector3d tL = prev.tangent;
    if (c1 > 0.0) {
      rL = prev.normal - (2.0 / c1) * v1.dot(prev.normal) * v1;
      tL = prev.tangent - (2.0 / c1) * v1.dot(prev.tangent) * v1;
    }
    // Reflection 2 maps the reflected tangent onto the new tangent.
    const Eigen::Vector3d v2 = t1 - tL;
    const double c2 = v2.squaredNorm();
    Eigen::Vector3d n1 = c2 > 0.0 ? Eigen::Vector3d(rL - (2.0 / c2) * v2.dot(rL) * v2) : rL;
    n1 = (n1 - n1.dot(t1) * t1).normalized();
    frames.push_back({t1, n1, t1.cross(n1)});
  }
  return frames;
}

}  // namespace leafdig::model
