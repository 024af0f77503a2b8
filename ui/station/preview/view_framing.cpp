#include "preview/view_framing.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace leafdig::station {
namespace {

QMatrix4x4 rotation(float yawDeg, float pitchDeg) {
  QMatrix4x4 r;
  r.rotate(pitchDeg, 1, 0, 0);
  r.rotate(yawDeg, 0, 1, 0);
  return r;
}

}  // namespace

QMatrix4x4 ViewFraming::matrix(float aspect) const {
  QMatrix4x4 projection, view;
  projection.perspective(kFovYDeg, aspect, radius * 0.02f, radius * 40.0f);
  view.translate(pan.x() * radius, pan.y() * radius, -distance * radius);
  view.rotate(pitchDeg, 1, 0, 0);
  view.rotate(yawDeg, 0, 1, 0);
  view.translate(-centre);
  return projection * view;
}

QVector3D ViewFraming::toNdc(const QVector3D& p, float aspect) const {
  return matrix(aspect).map(p);
}

float yawAcross(const QVector3D& tipToBase) {
  // Rotating (x, z) by θ about +y gives x' = x cos θ + z sin θ, z' = z cos θ − x sin θ:
  // θ = atan2(z, x) puts the direction on +x' (left to right on the screen).
  return static_cast<float>(std::atan2(tipToBase.z(), tipToBase.x()) * 180.0 / std::numbers::pi);
}

ViewFraming fitView(const std::vector<QVector3D>& points, float aspect, float yawDeg, float pitchDeg, float fill,
                    float minHalfSize) {
  ViewFraming f;
  f.yawDeg = yawDeg;
  f.pitchDeg = pitchDeg;
  if (points.empty()) return f;
  QVector3D lo = points.front(), hi = points.front();
  for (const QVector3D& p : points) {
    for (int k = 0; k < 3; ++k) {
      lo[k] = std::min(lo[k], p[k]);
      hi[k] = std::max(hi[k], p[k]);
    }
  }
  f.centre = (lo + hi) * 0.5f;
  f.radius = std::max(10.0f, (hi - lo).length() * 0.5f);
  // In camera space (before the distance), a point at (x, y, z) is seen at x / (D − z) of
  // the way to the edge when divided by tan(half field of view): solve each for D.
  const float tanY = std::tan(kFovYDeg * 0.5f * std::numbers::pi_v<float> / 180.0f) * fill;
  const float tanX = tanY * aspect;
  const QMatrix4x4 r = rotation(yawDeg, pitchDeg);
  float needed = minHalfSize / tanY;
  for (const QVector3D& p : points) {
    const QVector3D q = r.map(p - f.centre);
    needed = std::max({needed, q.z() + std::abs(q.x()) / tanX, q.z() + std::abs(q.y()) / tanY});
  }
  f.distance = std::max(0.5f, needed / f.radius);
  return f;
}

bool framingHolds(const ViewFraming& f, const std::vector<QVector3D>& points, float aspect, float inside,
                  float minFill) {
  if (points.empty()) return true;
  const QMatrix4x4 m = f.matrix(aspect);
  float xLo = 1e9f, xHi = -1e9f, yLo = 1e9f, yHi = -1e9f;
  for (const QVector3D& p : points) {
    const QVector3D n = m.map(p);
    if (std::abs(n.x()) > inside || std::abs(n.y()) > inside) return false;
    xLo = std::min(xLo, n.x());
    xHi = std::max(xHi, n.x());
    yLo = std::min(yLo, n.y());
    yHi = std::max(yHi, n.y());
  }
  // The view spans 2 in normalised coordinates.
  return (xHi - xLo) / 2.0f >= minFill || (yHi - yLo) / 2.0f >= minFill;
}

ViewFraming blend(const ViewFraming& a, const ViewFraming& b, float t) {
  const float s = t * t * (3.0f - 2.0f * t);  // smoothstep: no jolt at either end
  ViewFraming f;
  f.centre = a.centre + (b.centre - a.centre) * s;
  f.radius = a.radius + (b.radius - a.radius) * s;
  f.distance = a.distance + (b.distance - a.distance) * s;
  f.pitchDeg = a.pitchDeg + (b.pitchDeg - a.pitchDeg) * s;
  float dyaw = std::fmod(b.yawDeg - a.yawDeg + 540.0f, 360.0f) - 180.0f;
  f.yawDeg = a.yawDeg + dyaw * s;
  f.pan = a.pan + (b.pan - a.pan) * s;
  return f;
}

}  // namespace leafdig::station
