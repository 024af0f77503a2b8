#pragma once
// The point of a segment nearest a point, in 2-D or 3-D (Eigen fixed-size vectors): one
// projection for the outline checks of 2-D leaves, the accuracy study's polyline distances
// and the mesh comparison's degenerate triangles.
#include <algorithm>

namespace leafdig::model::detail {

// The parameter t in [0, 1] of the point a + t (b - a) nearest p (0 for a zero-length segment).
template <class Vector>
double nearestOnSegment(const Vector& a, const Vector& b, const Vector& p) {
  const Vector ab = b - a;
  const double len2 = ab.squaredNorm();
  return len2 > 0.0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
}

template <class Vector>
double squaredDistanceToSegment(const Vector& a, const Vector& b, const Vector& p) {
  const Vector nearest = a + nearestOnSegment(a, b, p) * (b - a);
  return (nearest - p).squaredNorm();
}

}  // namespace leafdig::model::detail
