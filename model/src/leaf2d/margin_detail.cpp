// What a scan shows of a leaf's margin between the markers (issue 26): the outline's reach
// outside and inside a smooth margin at the markers' spacing.
#include <algorithm>
#include <cmath>
#include <vector>

#include "leafdig/model/errors.hpp"
#include "leafdig/model/leaf2d/leaf2d.hpp"

namespace leafdig::model {

MarginSample marginFromOutline(const Outline2d& outline, double spacingMm) {
  const std::vector<Eigen::Vector2d>& poly = outline.pointsMm;
  if (poly.size() < 8) throw InputError("the scan's outline is too short to measure its margin");
  if (!(spacingMm > 0.0)) throw InputError("the markers' spacing along the margin must be positive");
  const std::size_t n = poly.size();
  std::vector<double> at(n + 1, 0.0);  // arc length at each vertex
  double twiceArea = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector2d& a = poly[i];
    const Eigen::Vector2d& b = poly[(i + 1) % n];
    at[i + 1] = at[i] + (b - a).norm();
    twiceArea += a.x() * b.y() - b.x() * a.y();
  }
  const double perimeter = at[n];
  if (!(perimeter > 0.0)) throw InputError("the scan's outline has no length");
  // Uniform samples along the margin, fine against both the spacing and the outline.
  const auto m =
      static_cast<std::size_t>(std::clamp(perimeter / std::min(spacingMm / 16.0, perimeter / 512.0), 512.0, 200000.0));
  const double h = perimeter / static_cast<double>(m);
  std::vector<Eigen::Vector2d> p(m);
  std::size_t seg = 0;
  for (std::size_t k = 0; k < m; ++k) {
    const double s = h * static_cast<double>(k);
    while (seg + 1 < n && at[seg + 1] < s) ++seg;
    const double len = at[seg + 1] - at[seg];
    const double t = len > 0 ? (s - at[seg]) / len : 0.0;
    p[k] = poly[seg] + t * (poly[(seg + 1) % n] - poly[seg]);
  }
  // The smooth margin: a moving average over one spacing of arc (circular, by prefix sums).
  const auto w = std::max<std::size_t>(1, std::min(m / 2, static_cast<std::size_t>(std::lround(spacingMm / h))));
  std::vector<Eigen::Vector2d> prefix(3 * m + 1, Eigen::Vector2d::Zero());
  for (std::size_t k = 0; k < 3 * m; ++k) prefix[k + 1] = prefix[k] + p[k % m];
  std::vector<Eigen::Vector2d> smooth(m);
  for (std::size_t k = 0; k < m; ++k) {
    const std::size_t from = k + m - w / 2;  // in the tripled sequence, centred on k
    smooth[k] = (prefix[from + w] - prefix[from]) / static_cast<double>(w);
  }
  // Signed distance of the margin from the smooth curve along its outward normal.
  const double outward = twiceArea > 0 ? 1.0 : -1.0;  // counter-clockwise: the normal is (t.y, -t.x)
  std::vector<double> d(m);
  for (std::size_t k = 0; k < m; ++k) {
    const Eigen::Vector2d t = smooth[(k + 1) % m] - smooth[(k + m - 1) % m];
    const double len = t.norm();
    const Eigen::Vector2d normal =
        len > 0 ? Eigen::Vector2d(Eigen::Vector2d(t.y(), -t.x()) / len * outward) : Eigen::Vector2d(0.0, 0.0);
    d[k] = (p[k] - smooth[k]).dot(normal);
  }
  double mean = 0.0;
  for (double v : d) mean += v / static_cast<double>(m);
  std::sort(d.begin(), d.end());
  const auto quantile = [&](double q) { return d[static_cast<std::size_t>(q * static_cast<double>(m - 1))]; };
  MarginSample out;
  out.spacingMm = spacingMm;
  out.outsideMm = std::max(0.0, quantile(0.975) - mean);
  out.insideMm = std::max(0.0, mean - quantile(0.025));
  return out;
}

MarginFromScan marginProfile(const Outline2d& outline) {
  MarginFromScan out;
  for (const double spacing : {5.0, 7.5, 10.0, 15.0, 20.0, 30.0, 45.0, 60.0, 80.0})
    out.push_back(marginFromOutline(outline, spacing));
  return out;
}

}  // namespace leafdig::model
