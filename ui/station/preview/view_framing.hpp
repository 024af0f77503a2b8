// How the live preview frames the leaf: pure geometry (no GL), so the widget test can check
// it. The camera looks at `centre` from `distance` × `radius`, turned by `yawDeg` about the
// up axis and tilted by `pitchDeg`, with a vertical field of view of kFovYDeg.
#pragma once

#include <QMatrix4x4>
#include <QVector3D>
#include <vector>

namespace leafdig::station {

inline constexpr float kFovYDeg = 35.0f;

struct ViewFraming {
  QVector3D centre{0, 0, 0};
  float radius = 100.0f;  // scale of the scene (near/far planes, pan and zoom steps)
  float yawDeg = -30.0f, pitchDeg = 35.0f, distance = 3.0f;
  QVector3D pan{0, 0, 0};

  // Projection × view for a viewport of this aspect ratio (width / height).
  [[nodiscard]] QMatrix4x4 matrix(float aspect) const;
  // Normalised device coordinates (−1…1 inside the view) of a point.
  [[nodiscard]] QVector3D toNdc(const QVector3D& p, float aspect) const;
};

// The yaw that lays the direction `tipToBase` (view coordinates) across the screen, tip on
// the left: a leaf is wider than it is tall on a landscape screen.
[[nodiscard]] float yawAcross(const QVector3D& tipToBase);

// A framing of `points` with the given yaw and pitch: centred on their box, at the distance
// where they fill `fill` (0…1) of the view in its tighter direction, and never closer than
// showing ±`minHalfSize` around the centre (a tip alone is not blown up to the screen).
[[nodiscard]] ViewFraming fitView(const std::vector<QVector3D>& points, float aspect, float yawDeg, float pitchDeg,
                                  float fill, float minHalfSize = 0.0f);

// Whether `f` still frames `points` well: all inside `inside` of the view, and filling at
// least `minFill` of it in one direction. While it holds, the view does not move.
[[nodiscard]] bool framingHolds(const ViewFraming& f, const std::vector<QVector3D>& points, float aspect, float inside,
                                float minFill);

// The framing a fraction `t` (0…1, eased) of the way from `a` to `b` (yaw the short way).
[[nodiscard]] ViewFraming blend(const ViewFraming& a, const ViewFraming& b, float t);

}  // namespace leafdig::station
