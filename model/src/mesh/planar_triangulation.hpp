#pragma once
// Planar constrained Delaunay triangulation and refinement: our own small interface over
// CGAL (the only file that includes CGAL is planar_triangulation.cpp, so the 2-core build
// compiles CGAL's templates once).
#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <functional>
#include <vector>

namespace leafdig::model::detail {

struct PlanarTriangulation {
  std::vector<Eigen::Vector2d> points;
  std::vector<std::array<std::uint32_t, 3>> triangles;  // counter-clockwise, inside the polygon
};

// The constrained Delaunay triangulation of a simple polygon (its corners in order, the
// first not repeated at the end; collinear corners allowed): every polygon edge is an edge
// of the result, no point is added, only triangles inside the polygon are returned. Throws
// InputError when the polygon has fewer than three corners or is not simple.
[[nodiscard]] PlanarTriangulation triangulatePolygon(const std::vector<Eigen::Vector2d>& polygon);

// The same with `inside` points added as vertices (each strictly inside the polygon; none
// repeated or on an edge): every point of the result is one of the polygon's corners or one
// of `inside`, with exactly its coordinates. Throws InputError as above, and when a point
// repeats another or lies outside.
[[nodiscard]] PlanarTriangulation triangulatePolygon(const std::vector<Eigen::Vector2d>& polygon,
                                                     const std::vector<Eigen::Vector2d>& inside);

// How much too coarse a triangle is: 1 or less is fine.
using Coarseness = std::function<double(const Eigen::Vector2d&, const Eigen::Vector2d&, const Eigen::Vector2d&)>;

// Constrained Delaunay refinement (CGAL's Delaunay_mesher_2, Ruppert/Shewchuk style) of a
// convex polygon: Steiner points (circumcentres, and midpoints of encroached polygon edges)
// are inserted until every triangle has coarseness <= 1 and its smallest angle is at least
// 20.7 degrees. `chains` are extra constraint polylines inside the polygon (kept as edges).
// Throws InputError when more than `maxPoints` points would be needed.
[[nodiscard]] PlanarTriangulation refineConvexPolygon(const std::vector<Eigen::Vector2d>& polygon,
                                                      const std::vector<std::vector<Eigen::Vector2d>>& chains,
                                                      const Coarseness& coarseness, std::size_t maxPoints);

}  // namespace leafdig::model::detail
