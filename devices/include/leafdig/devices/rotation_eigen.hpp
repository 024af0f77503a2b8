#pragma once
// A receiver's rotation (pose.hpp's row-major 3×3) as an Eigen matrix and back, for the code
// that computes with Eigen (pose.cpp, the simulators' rigid moves); pose.hpp itself keeps Eigen
// out of its users.
#include <Eigen/Core>

#include "leafdig/devices/pose.hpp"

namespace leafdig::devices {

[[nodiscard]] inline Eigen::Matrix3d matrixOf(const Rotation& r) {
  Eigen::Matrix3d m;
  m << r[0], r[1], r[2], r[3], r[4], r[5], r[6], r[7], r[8];
  return m;
}

[[nodiscard]] inline Rotation rotationOf(const Eigen::Matrix3d& m) {
  return {m(0, 0), m(0, 1), m(0, 2), m(1, 0), m(1, 1), m(1, 2), m(2, 0), m(2, 1), m(2, 2)};
}

}  // namespace leafdig::devices
