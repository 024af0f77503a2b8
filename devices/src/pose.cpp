// Receiver poses (pose.hpp): rotations as Eigen does them, kept out of the header.
#include "leafdig/devices/pose.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "leafdig/devices/rotation_eigen.hpp"

namespace leafdig::devices {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kRad = kPi / 180.0;

}  // namespace

Rotation rotationFromEulerDeg(const Vec3& e) {
  const Eigen::Matrix3d m = (Eigen::AngleAxisd(e[0] * kRad, Eigen::Vector3d::UnitZ()) *
                             Eigen::AngleAxisd(e[1] * kRad, Eigen::Vector3d::UnitY()) *
                             Eigen::AngleAxisd(e[2] * kRad, Eigen::Vector3d::UnitX()))
                                .toRotationMatrix();
  return rotationOf(m);
}

Rotation rotationFromQuaternion(const std::array<double, 4>& q) {
  Eigen::Quaterniond e(q[0], q[1], q[2], q[3]);
  if (!(e.norm() > 0.0)) return rotationFromEulerDeg({0, 0, 0});
  return rotationOf(e.normalized().toRotationMatrix());
}

std::array<double, 4> quaternionFromRotation(const Rotation& r) {
  Eigen::Quaterniond q(matrixOf(r));
  if (q.w() < 0) q.coeffs() *= -1.0;
  return {q.w(), q.x(), q.y(), q.z()};
}

Vec3 eulerDegFromRotation(const Rotation& r) {
  // R = Rz(az) Ry(el) Rx(roll): r20 = -sin(el), r21 = cos(el) sin(roll), r22 = cos(el) cos(roll),
  // r10 = sin(az) cos(el), r00 = cos(az) cos(el).
  const double el = std::asin(std::clamp(-r[6], -1.0, 1.0));
  double az = 0.0, roll = 0.0;
  if (std::abs(r[6]) < 1.0 - 1e-12) {
    az = std::atan2(r[3], r[0]);
    roll = std::atan2(r[7], r[8]);
  } else {  // gimbal lock: only az - roll (el = +90°) or az + roll (-90°) is fixed; roll = 0
    az = std::atan2(-r[1], r[4]);
  }
  const auto wrap = [](double deg) { return deg <= -180.0 ? deg + 360.0 : deg; };
  return {wrap(az / kRad), el / kRad, wrap(roll / kRad)};
}

std::optional<ReceiverPose> poseOf(const StylusSample& s) {
  ReceiverPose p;
  p.positionMm = s.positionMm;
  if (s.quaternion)
    p.rotation = rotationFromQuaternion(*s.quaternion);
  else if (s.orientationDeg)
    p.rotation = rotationFromEulerDeg(*s.orientationDeg);
  else
    return std::nullopt;
  return p;
}

double rotationBetweenDeg(const Rotation& a, const Rotation& b) {
  const Eigen::Matrix3d d = matrixOf(a).transpose() * matrixOf(b);
  return std::acos(std::clamp((d.trace() - 1.0) / 2.0, -1.0, 1.0)) / kRad;
}

StylusSample inFrameOf(const StylusSample& stylus, const ReceiverPose& reference) {
  StylusSample out = stylus;
  const Eigen::Matrix3d rt = matrixOf(reference.rotation).transpose();
  const Eigen::Vector3d p =
      rt * (Eigen::Vector3d(stylus.positionMm[0], stylus.positionMm[1], stylus.positionMm[2]) -
            Eigen::Vector3d(reference.positionMm[0], reference.positionMm[1], reference.positionMm[2]));
  out.positionMm = {p.x(), p.y(), p.z()};
  if (const auto own = poseOf(stylus)) {
    const Rotation relative = rotationOf(rt * matrixOf(own->rotation));
    out.orientationDeg = eulerDegFromRotation(relative);
    if (stylus.quaternion) out.quaternion = quaternionFromRotation(relative);
  }
  return out;
}

}  // namespace leafdig::devices
