// The base and the tip of a 2-D outline (given, or found: the outline's diameter, the tip at
// its narrower end), and the outline's sections they are found with.
#include <algorithm>

#include "leaf2d/sections.hpp"
#include "leafdig/model/leaf2d/leaf2d.hpp"

namespace leafdig::model {

namespace detail {

std::vector<double> sectionCrossings(const std::vector<Eigen::Vector2d>& poly, const Eigen::Vector2d& origin,
                                     const Eigen::Vector2d& axis, const Eigen::Vector2d& across, double s) {
  std::vector<double> ws;
  for (std::size_t i = 0; i < poly.size(); ++i) {
    const Eigen::Vector2d& p = poly[i];
    const Eigen::Vector2d& q = poly[(i + 1) % poly.size()];
    const double sp = (p - origin).dot(axis);
    const double sq = (q - origin).dot(axis);
    if ((sp <= s && s < sq) || (sq <= s && s < sp)) {
      const Eigen::Vector2d x = p + (s - sp) / (sq - sp) * (q - p);
      ws.push_back((x - origin).dot(across));
    }
  }
  std::sort(ws.begin(), ws.end());
  return ws;
}

std::vector<double> crossingsAt(const std::vector<Eigen::Vector2d>& poly, double y) {
  return sectionCrossings(poly, Eigen::Vector2d::Zero(), Eigen::Vector2d::UnitY(), Eigen::Vector2d::UnitX(), y);
}

std::optional<std::pair<double, double>> sectionExtent(const std::vector<Eigen::Vector2d>& poly,
                                                       const Eigen::Vector2d& origin, const Eigen::Vector2d& axis,
                                                       const Eigen::Vector2d& across, double s) {
  const std::vector<double> ws = sectionCrossings(poly, origin, axis, across, s);
  if (ws.empty()) return std::nullopt;
  return std::pair{ws.front(), ws.back()};
}

}  // namespace detail

using detail::sectionExtent;

std::pair<Eigen::Vector2d, Eigen::Vector2d> findBaseAndTip(const Outline2d& o) {
  const auto& pts = o.pointsMm;
  if (o.baseMm && o.tipMm) return {*o.baseMm, *o.tipMm};
  // The farthest point from a given end, or the farthest pair (the polygon's diameter: the
  // outline's convex hull would be faster, but O(n^2) over a few thousand points is ~10 ms).
  auto farthestFrom = [&](const Eigen::Vector2d& p) {
    return *std::max_element(pts.begin(), pts.end(), [&](const auto& a, const auto& b) {
      return (a - p).squaredNorm() < (b - p).squaredNorm();
    });
  };
  if (o.baseMm) return {*o.baseMm, farthestFrom(*o.baseMm)};
  if (o.tipMm) return {farthestFrom(*o.tipMm), *o.tipMm};
  std::size_t stride = std::max<std::size_t>(1, pts.size() / 2000);
  double best = -1.0;
  Eigen::Vector2d a = pts[0];
  Eigen::Vector2d b = pts[0];
  for (std::size_t i = 0; i < pts.size(); i += stride) {
    for (std::size_t j = i + stride; j < pts.size(); j += stride) {
      const double d = (pts[i] - pts[j]).squaredNorm();
      if (d > best) {
        best = d;
        a = pts[i];
        b = pts[j];
      }
    }
  }
  // Refine on the full outline: alternate farthest points (converges in one or two steps).
  for (int k = 0; k < 3; ++k) {
    b = farthestFrom(a);
    a = farthestFrom(b);
  }
  // The tip is the end where the leaf is narrower 5 % of the length inside.
  const double length = (b - a).norm();
  const Eigen::Vector2d axis = (b - a) / length;
  const Eigen::Vector2d across(-axis.y(), axis.x());
  auto widthAt = [&](double s) {
    const auto e = sectionExtent(pts, a, axis, across, s);
    return e ? e->second - e->first : 0.0;
  };
  if (widthAt(0.05 * length) < widthAt(0.95 * length)) return {b, a};
  return {a, b};
}

}  // namespace leafdig::model
