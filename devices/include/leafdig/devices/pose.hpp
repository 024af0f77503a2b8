// A receiver's pose from its record, and a stylus sample expressed in another receiver's frame
// (the reference receiver of issue 29: docs/devices.md, "A reference receiver").
//
// Orientation conventions (Polhemus FASTRAK, Patriot, Liberty; docs/devices.md): Euler angles
// azimuth, elevation, roll in degrees turn the transmitter's axes into the receiver's by azimuth
// about Z, then elevation about the new Y, then roll about the newer X — R = Rz(az)·Ry(el)·Rx(roll),
// whose columns are the receiver's axes in the transmitter's frame; a quaternion (w, x, y, z) is
// the same rotation. A receiver's position is its origin in the transmitter's frame, so a point
// p of the transmitter's frame is R^T (p - t) in the receiver's.
#pragma once

#include <array>
#include <optional>

#include "leafdig/devices/sample.hpp"

namespace leafdig::devices {

using Rotation = std::array<double, 9>;  // row-major 3×3

struct ReceiverPose {
  Rotation rotation{1, 0, 0, 0, 1, 0, 0, 0, 1};
  Vec3 positionMm{};
};

[[nodiscard]] Rotation rotationFromEulerDeg(const Vec3& azElRoll);
[[nodiscard]] Rotation rotationFromQuaternion(const std::array<double, 4>& wxyz);  // normalises
[[nodiscard]] std::array<double, 4> quaternionFromRotation(const Rotation& r);     // w >= 0
// Azimuth in (-180, 180], elevation in [-90, 90], roll in (-180, 180].
[[nodiscard]] Vec3 eulerDegFromRotation(const Rotation& r);

// The pose a record reports: its quaternion when it has one, else its Euler angles; nothing
// when it carries no orientation (an output list without item 4 / 11 or 5 / 7).
[[nodiscard]] std::optional<ReceiverPose> poseOf(const StylusSample& s);

// The angle of the rotation that takes a to b, degrees in [0, 180].
[[nodiscard]] double rotationBetweenDeg(const Rotation& a, const Rotation& b);

// `stylus` expressed in the frame of a receiver at `reference`: its position R^T (p - t), its
// orientation (when it has one) R^T R_stylus as Euler angles; everything else as it was.
[[nodiscard]] StylusSample inFrameOf(const StylusSample& stylus, const ReceiverPose& reference);

}  // namespace leafdig::devices
