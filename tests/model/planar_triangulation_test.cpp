// Our interface over CGAL's constrained Delaunay triangulation and refinement.
#include "../../model/src/mesh/planar_triangulation.hpp"

#include <gtest/gtest.h>

#include <Eigen/LU>
#include <cmath>
#include <numbers>
#include <random>

#include "leafdig/model/errors.hpp"

namespace leafdig::model::detail {
namespace {

// True when d lies strictly inside the circumcircle of the counter-clockwise a, b, c.
bool inCircumcircle(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c,
                    const Eigen::Vector2d& d) {
  Eigen::Matrix3d m;
  m << a.x() - d.x(), a.y() - d.y(), (a - d).squaredNorm(), b.x() - d.x(), b.y() - d.y(), (b - d).squaredNorm(),
      c.x() - d.x(), c.y() - d.y(), (c - d).squaredNorm();
  const double scale = std::max({(a - d).squaredNorm(), (b - d).squaredNorm(), (c - d).squaredNorm()});
  return m.determinant() > 1e-9 * scale * scale;
}

double twiceArea(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c) {
  return (b - a).x() * (c - a).y() - (b - a).y() * (c - a).x();
}

// A convex polygon: a circle's points at random angles (the seed's blade halves are convex
// in the (u, v) domain, with many points along each side).
std::vector<Eigen::Vector2d> convexPolygon(std::uint64_t seed, int n) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> angle(0.0, 2.0 * std::numbers::pi);
  std::vector<double> as;
  for (int k = 0; k < n; ++k) as.push_back(angle(rng));
  std::sort(as.begin(), as.end());
  std::vector<Eigen::Vector2d> p;
  for (double a : as) p.emplace_back(30.0 * std::cos(a), 20.0 * std::sin(a));
  return p;
}

TEST(PlanarTriangulation, AConvexPolygonGetsItsDelaunayTriangulationWithNoPointAdded) {
  for (std::uint64_t seed = 1; seed <= 5; ++seed) {
    const auto polygon = convexPolygon(seed, 40);
    const PlanarTriangulation t = triangulatePolygon(polygon);
    EXPECT_EQ(t.points.size(), polygon.size());
    EXPECT_EQ(t.triangles.size(), polygon.size() - 2);  // any triangulation of an n-gon
    double area = 0.0;
    for (const auto& tri : t.triangles) {
      const auto& a = t.points[tri[0]];
      const auto& b = t.points[tri[1]];
      const auto& c = t.points[tri[2]];
      ASSERT_GT(twiceArea(a, b, c), 0.0);  // counter-clockwise
      area += twiceArea(a, b, c) / 2.0;
      // Every vertex is visible inside a convex polygon: constrained Delaunay is Delaunay.
      for (const auto& d : t.points) EXPECT_FALSE(inCircumcircle(a, b, c, d));
    }
    double polygonArea = 0.0;
    for (std::size_t k = 0; k < polygon.size(); ++k)
      polygonArea += twiceArea(Eigen::Vector2d::Zero(), polygon[k], polygon[(k + 1) % polygon.size()]) / 2.0;
    EXPECT_NEAR(area, polygonArea, 1e-9 * polygonArea);
  }
}

TEST(PlanarTriangulation, ANonConvexPolygonIsTriangulatedInsideOnly) {
  // An L shape: area 3.
  const std::vector<Eigen::Vector2d> l{{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}};
  const PlanarTriangulation t = triangulatePolygon(l);
  double area = 0.0;
  for (const auto& tri : t.triangles) area += twiceArea(t.points[tri[0]], t.points[tri[1]], t.points[tri[2]]) / 2.0;
  EXPECT_NEAR(area, 3.0, 1e-12);
  EXPECT_EQ(t.triangles.size(), 4U);
}

TEST(PlanarTriangulation, InsidePointsBecomeVerticesExactlyAndOutsidePointsAreRefused) {
  // An L-shaped (non-convex) polygon and points inside it: n + k vertices, n + 2k - 2
  // triangles (Euler), every inside point kept with its very coordinates, none across the
  // notch.
  const std::vector<Eigen::Vector2d> l{{0, 0}, {4, 0}, {4, 1}, {1, 1}, {1, 4}, {0, 4}};
  const std::vector<Eigen::Vector2d> inside{{0.5, 0.5}, {2.25, 0.5}, {0.5, 2.5}, {0.3, 3.7}};
  const PlanarTriangulation t = triangulatePolygon(l, inside);
  ASSERT_EQ(t.points.size(), l.size() + inside.size());
  EXPECT_EQ(t.triangles.size(), l.size() + 2 * inside.size() - 2);
  for (const auto& p : inside) {
    EXPECT_EQ(std::count_if(t.points.begin(), t.points.end(), [&](const Eigen::Vector2d& q) { return q == p; }), 1);
  }
  double area = 0.0;
  for (const auto& tri : t.triangles) {
    const double a2 = twiceArea(t.points[tri[0]], t.points[tri[1]], t.points[tri[2]]);
    ASSERT_GT(a2, 0.0);
    area += a2 / 2.0;
  }
  EXPECT_NEAR(area, 7.0, 1e-12);                                        // the L's area: the notch is not covered
  EXPECT_THROW((void)triangulatePolygon(l, {{2.5, 2.5}}), InputError);  // in the notch
  EXPECT_THROW((void)triangulatePolygon(l, {{0.5, 0.5}, {0.5, 0.5}}), InputError);
}

TEST(PlanarTriangulation, ACrossingOrDegeneratePolygonIsAnInputError) {
  EXPECT_THROW((void)triangulatePolygon({{0, 0}, {1, 1}, {1, 0}, {0, 1}}), InputError);  // a bow tie
  EXPECT_THROW((void)triangulatePolygon({{0, 0}, {1, 0}}), InputError);
  EXPECT_THROW((void)triangulatePolygon({{0, 0}, {1, 0}, {1, 1}, {1, 0}}), InputError);  // repeats a corner
}

TEST(PlanarTriangulation, RefinementMeetsTheCoarsenessAndTheAngleBoundAndStaysDelaunay) {
  const std::vector<Eigen::Vector2d> square{{0, 0}, {100, 0}, {100, 50}, {0, 50}};
  // Finer towards x = 100: a triangle's longest edge must be under 2 + x / 10.
  const Coarseness coarseness = [](const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c) {
    const double longest = std::max({(a - b).norm(), (b - c).norm(), (c - a).norm()});
    const double x = (a.x() + b.x() + c.x()) / 3.0;
    return longest / (12.0 - x / 10.0);
  };
  const PlanarTriangulation t = refineConvexPolygon(square, {}, coarseness, 100'000);
  double area = 0.0;
  std::size_t left = 0;
  std::size_t right = 0;
  for (const auto& tri : t.triangles) {
    const auto& a = t.points[tri[0]];
    const auto& b = t.points[tri[1]];
    const auto& c = t.points[tri[2]];
    ASSERT_GT(twiceArea(a, b, c), 0.0);
    area += twiceArea(a, b, c) / 2.0;
    EXPECT_LE(coarseness(a, b, c), 1.0);
    // Smallest angle at least 20.7 degrees (CGAL's bound B = 0.125 on its squared sine).
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector2d u = t.points[tri[(k + 1) % 3]] - t.points[tri[k]];
      const Eigen::Vector2d v = t.points[tri[(k + 2) % 3]] - t.points[tri[k]];
      EXPECT_GT(std::acos(u.dot(v) / (u.norm() * v.norm())), 20.6 * std::numbers::pi / 180.0);
    }
    for (const auto& d : t.points) EXPECT_FALSE(inCircumcircle(a, b, c, d));
    ((a.x() + b.x() + c.x()) / 3.0 < 50.0 ? left : right)++;
  }
  EXPECT_NEAR(area, 5000.0, 1e-9 * 5000.0);
  EXPECT_GT(right, 2 * left);  // finer where asked
  EXPECT_THROW((void)refineConvexPolygon(square, {}, coarseness, 50), InputError);
}

}  // namespace
}  // namespace leafdig::model::detail
