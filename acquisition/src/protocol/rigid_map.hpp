#pragma once
// A transmitter position's map to the first (Engine::positionToFirst: row-major rotation, then
// translation) as an Eigen isometry and back; engine.hpp keeps Eigen out of its users.
#include <Eigen/Geometry>
#include <array>
#include <cstddef>

namespace leafdig::acquisition::detail {

[[nodiscard]] inline Eigen::Isometry3d isometryOf(const std::array<double, 12>& m) {
  Eigen::Isometry3d e = Eigen::Isometry3d::Identity();
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) e.linear()(r, c) = m[static_cast<std::size_t>(3 * r + c)];
    e.translation()(r) = m[static_cast<std::size_t>(9 + r)];
  }
  return e;
}

[[nodiscard]] inline std::array<double, 12> mapOf(const Eigen::Isometry3d& e) {
  std::array<double, 12> m{};
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) m[static_cast<std::size_t>(3 * r + c)] = e.linear()(r, c);
    m[static_cast<std::size_t>(9 + r)] = e.translation()(r);
  }
  return m;
}

// p (in a position's frame) placed into the first's by map m.
[[nodiscard]] inline std::array<double, 3> placed(const std::array<double, 12>& m, const std::array<double, 3>& p) {
  const Eigen::Vector3d q = isometryOf(m) * Eigen::Vector3d(p[0], p[1], p[2]);
  return {q.x(), q.y(), q.z()};
}

// A point `before` placed into the first frame, placed by `after` instead (a move refitted
// after a curator corrected one of its landmarks).
[[nodiscard]] inline std::array<double, 3> replaced(const Eigen::Isometry3d& before, const Eigen::Isometry3d& after,
                                                    const std::array<double, 3>& p) {
  const Eigen::Vector3d q = after * (before.inverse() * Eigen::Vector3d(p[0], p[1], p[2]));
  return {q.x(), q.y(), q.z()};
}

}  // namespace leafdig::acquisition::detail
