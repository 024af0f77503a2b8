#pragma once
// Ball B-spline curves (docs/method.md §3): a B-spline centre curve c(t) and a B-spline radius
// r(t) held as one 4-D B-spline over (x, y, z, r), t in [0, 1].
#include <Eigen/Core>
#include <Eigen/Geometry>  // cross products
#include <vector>

#include "leafdig/model/spline/bspline.hpp"

namespace leafdig::model {

struct Ball {
  Eigen::Vector3d center;
  double radius;  // mm; a radius, i.e. caliper thickness / 2
};

// Orthonormal frame along a curve: tangent T, normal N, binormal B = T x N.
struct Frame {
  Eigen::Vector3d tangent;
  Eigen::Vector3d normal;
  Eigen::Vector3d binormal;
};

class BallBSplineCurve {
 public:
  // The interpolating BBSC of docs/method.md §3: chord-length parameters from the centres, natural
  // cubic spline over all four coordinates. Throws std::invalid_argument if fewer than two
  // balls are given or two consecutive centres coincide.
  [[nodiscard]] static BallBSplineCurve interpolate(const std::vector<Ball>& dataBalls);

  // From a stored 4-D spline (model files). Data balls/parameters may be empty.
  BallBSplineCurve(BSplineCurve spline, std::vector<double> dataParameters, std::vector<Ball> dataBalls);

  [[nodiscard]] const BSplineCurve& spline() const { return spline_; }
  [[nodiscard]] const std::vector<double>& dataParameters() const { return dataParameters_; }
  [[nodiscard]] const std::vector<Ball>& dataBalls() const { return dataBalls_; }

  // Position, first and second derivatives of centre and radius at t.
  struct Jet {
    Eigen::Vector3d c, dc, ddc;
    double r, dr, ddr;
  };
  [[nodiscard]] Jet jet(double t) const;
  [[nodiscard]] Eigen::Vector3d center(double t) const;
  [[nodiscard]] double radius(double t) const;

  // The characteristic circle of the envelope at t: where the moving ball touches the
  // envelope. centre = c - (r r'/|c'|^2) c', radius = (r/|c'|) sqrt(|c'|^2 - r'^2), in the
  // plane perpendicular to c'. `exists` is false where |r'| >= |c'| or r <= 0.
  struct Circle {
    Eigen::Vector3d center;
    double radius;
    bool exists;
  };
  [[nodiscard]] Circle envelopeCircle(double t) const;
  // The same from an already evaluated jet (meshing evaluates each parameter once).
  [[nodiscard]] static Circle envelopeCircle(const Jet& jet);

  // S(t, theta) on the envelope, with the frame's N and B spanning the circle's plane.
  [[nodiscard]] Eigen::Vector3d envelopePoint(double t, double theta, const Frame& frame) const;

 private:
  BSplineCurve spline_;
  std::vector<double> dataParameters_;
  std::vector<Ball> dataBalls_;
};

// Rotation-minimising frames at increasing parameters ts by the double-reflection method
// (Wang, Juttler, Zheng, Liu 2008). The first normal is the direction most perpendicular
// to the first tangent among the world axes, or `firstNormalHint` when given (it is
// projected onto the normal plane). Frenet frames are not used: they are undefined on
// straight veins.
[[nodiscard]] std::vector<Frame> rotationMinimisingFrames(const BallBSplineCurve& curve, const std::vector<double>& ts,
                                                          const Eigen::Vector3d* firstNormalHint = nullptr);

// The same from points x_i on the curve and its derivatives there (any length).
[[nodiscard]] std::vector<Frame> rotationMinimisingFrames(const std::vector<Eigen::Vector3d>& points,
                                                          const std::vector<Eigen::Vector3d>& derivatives,
                                                          const Eigen::Vector3d* firstNormalHint = nullptr);

}  // namespace leafdig::model
