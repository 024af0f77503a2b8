// The only translation unit that includes CGAL (see planar_triangulation.hpp).
#include "mesh/planar_triangulation.hpp"

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Delaunay_mesh_criteria_2.h>
#include <CGAL/Delaunay_mesh_face_base_2.h>
#include <CGAL/Delaunay_mesh_vertex_base_2.h>
#include <CGAL/Delaunay_mesher_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_face_base_with_info_2.h>

#include <deque>
#include <string>
#include <unordered_map>

#include "leafdig/model/errors.hpp"

namespace leafdig::model::detail {

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_2;

Point toCgal(const Eigen::Vector2d& p) {
  return {p.x(), p.y()};
}

// Collects the triangles of `cdt` for which inDomain(face) holds, numbering vertices in
// the order they are first met; counter-clockwise as CGAL stores them.
template <class Cdt, class InDomain>
PlanarTriangulation collect(const Cdt& cdt, InDomain inDomain) {
  PlanarTriangulation out;
  std::unordered_map<typename Cdt::Vertex_handle, std::uint32_t> index;
  auto id = [&](typename Cdt::Vertex_handle v) {
    auto [it, inserted] = index.try_emplace(v, static_cast<std::uint32_t>(out.points.size()));
    if (inserted) out.points.emplace_back(v->point().x(), v->point().y());
    return it->second;
  };
  for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f) {
    if (!inDomain(f)) continue;
    out.triangles.push_back({id(f->vertex(0)), id(f->vertex(1)), id(f->vertex(2))});
  }
  return out;
}

// ---- plain constrained Delaunay triangulation of a simple polygon --------------------

struct FaceInfo {
  int nesting = -1;  // polygon boundaries crossed from the outside; odd = inside
};
using PolyFb =
    CGAL::Constrained_triangulation_face_base_2<Kernel, CGAL::Triangulation_face_base_with_info_2<FaceInfo, Kernel>>;
using PolyTds = CGAL::Triangulation_data_structure_2<CGAL::Triangulation_vertex_base_2<Kernel>, PolyFb>;
using PolyCdt = CGAL::Constrained_Delaunay_triangulation_2<Kernel, PolyTds, CGAL::Exact_predicates_tag>;

// Flood fill from the infinite face: crossing a constrained edge adds one nesting level.
void markNesting(PolyCdt& cdt) {
  std::deque<std::pair<PolyCdt::Face_handle, int>> queue{{cdt.infinite_face(), 0}};
  while (!queue.empty()) {
    auto [start, level] = queue.front();
    queue.pop_front();
    if (start->info().nesting != -1) continue;
    std::deque<PolyCdt::Face_handle> region{start};
    start->info().nesting = level;
    while (!region.empty()) {
      PolyCdt::Face_handle f = region.front();
      region.pop_front();
      for (int i = 0; i < 3; ++i) {
        PolyCdt::Face_handle n = f->neighbor(i);
        if (n->info().nesting != -1) continue;
        if (cdt.is_constrained({f, i})) {
          queue.emplace_back(n, level + 1);
        } else {
          n->info().nesting = level;
          region.push_back(n);
        }
      }
    }
  }
}

// ---- refinement under a caller's coarseness measure -----------------------------------

using MeshFb = CGAL::Delaunay_mesh_face_base_2<Kernel>;
using MeshTds = CGAL::Triangulation_data_structure_2<CGAL::Delaunay_mesh_vertex_base_2<Kernel>, MeshFb>;
using MeshCdt = CGAL::Constrained_Delaunay_triangulation_2<Kernel, MeshTds>;

// MeshingCriteria_2: a face is imperatively bad when the caller's coarseness exceeds 1
// (refined first, largest first), bad when its smallest angle is under CGAL's default bound
// (squared sine 0.125, about 20.7 degrees), good otherwise.
class CoarsenessCriteria {
 public:
  using Face_handle = MeshCdt::Face_handle;
  struct Quality {
    double squaredSine = 1.0;
    double coarseness = 0.0;
    // q1 < q2: q1 is refined before q2.
    bool operator<(const Quality& q) const {
      const bool coarse = coarseness > 1.0;
      const bool otherCoarse = q.coarseness > 1.0;
      if (coarse != otherCoarse) return coarse;
      if (coarse) return coarseness > q.coarseness;
      return squaredSine < q.squaredSine;
    }
  };

  explicit CoarsenessCriteria(const Coarseness* coarseness) : coarseness_(coarseness) {}

  class Is_bad {
   public:
    explicit Is_bad(const Coarseness* coarseness) : coarseness_(coarseness) {}
    CGAL::Mesh_2::Face_badness operator()(const Quality& q) const {
      if (q.coarseness > 1.0) return CGAL::Mesh_2::IMPERATIVELY_BAD;
      return q.squaredSine < kAngleBound ? CGAL::Mesh_2::BAD : CGAL::Mesh_2::NOT_BAD;
    }
    CGAL::Mesh_2::Face_badness operator()(const Face_handle& f, Quality& q) const {
      const Eigen::Vector2d a(f->vertex(0)->point().x(), f->vertex(0)->point().y());
      const Eigen::Vector2d b(f->vertex(1)->point().x(), f->vertex(1)->point().y());
      const Eigen::Vector2d c(f->vertex(2)->point().x(), f->vertex(2)->point().y());
      q.coarseness = (*coarseness_)(a, b, c);
      // Squared sine of the smallest angle: (2 area)^2 / (longest^2 second-longest^2).
      double e[3] = {(b - c).squaredNorm(), (c - a).squaredNorm(), (a - b).squaredNorm()};
      std::sort(e, e + 3);
      const Eigen::Vector2d ab = b - a;
      const Eigen::Vector2d ac = c - a;
      const double twiceArea = ab.x() * ac.y() - ab.y() * ac.x();
      q.squaredSine = e[1] > 0.0 ? twiceArea * twiceArea / (e[2] * e[1]) : 0.0;
      return (*this)(q);
    }

   private:
    static constexpr double kAngleBound = 0.125;
    const Coarseness* coarseness_;
  };

  [[nodiscard]] Is_bad is_bad_object() const { return Is_bad(coarseness_); }

 private:
  const Coarseness* coarseness_;
};

}  // namespace

PlanarTriangulation triangulatePolygon(const std::vector<Eigen::Vector2d>& polygon) {
  return triangulatePolygon(polygon, {});
}

PlanarTriangulation triangulatePolygon(const std::vector<Eigen::Vector2d>& polygon,
                                       const std::vector<Eigen::Vector2d>& inside) {
  if (polygon.size() < 3) throw InputError("a polygon to triangulate needs at least three corners");
  PolyCdt cdt;
  try {
    std::vector<Point> corners;
    corners.reserve(polygon.size());
    for (const auto& p : polygon) corners.push_back(toCgal(p));
    cdt.insert_constraint(corners.begin(), corners.end(), /*close=*/true);
  } catch (const PolyCdt::Intersection_of_constraints_exception&) {
    throw InputError("the polygon to triangulate crosses itself");
  }
  if (cdt.number_of_vertices() != polygon.size())
    throw InputError("the polygon to triangulate repeats a corner (" + std::to_string(polygon.size()) + " corners, " +
                     std::to_string(cdt.number_of_vertices()) + " distinct)");
  for (const auto& p : inside) cdt.insert(toCgal(p));
  if (cdt.number_of_vertices() != polygon.size() + inside.size())
    throw InputError("a point to triangulate repeats another or lies on the polygon");
  markNesting(cdt);
  PlanarTriangulation out = collect(cdt, [](PolyCdt::Finite_faces_iterator f) { return f->info().nesting % 2 == 1; });
  if (out.points.size() != polygon.size() + inside.size())
    throw InputError("a point to triangulate lies outside the polygon");
  return out;
}

PlanarTriangulation refineConvexPolygon(const std::vector<Eigen::Vector2d>& polygon,
                                        const std::vector<std::vector<Eigen::Vector2d>>& chains,
                                        const Coarseness& coarseness, std::size_t maxPoints) {
  if (polygon.size() < 3) throw InputError("a polygon to refine needs at least three corners");
  MeshCdt cdt;
  std::vector<Point> corners;
  for (const auto& p : polygon) corners.push_back(toCgal(p));
  cdt.insert_constraint(corners.begin(), corners.end(), /*close=*/true);
  for (const auto& chain : chains) {
    std::vector<Point> points;
    for (const auto& p : chain) points.push_back(toCgal(p));
    cdt.insert_constraint(points.begin(), points.end(), /*close=*/false);
  }
  CoarsenessCriteria criteria(&coarseness);
  CGAL::Delaunay_mesher_2<MeshCdt, CoarsenessCriteria> mesher(cdt, criteria);
  mesher.init();  // no seeds: the convex hull (our convex polygon) is the domain
  while (!mesher.is_refinement_done()) {
    mesher.step_by_step_refine_mesh();
    if (cdt.number_of_vertices() > maxPoints)
      throw InputError("refining the triangulation needs more than " + std::to_string(maxPoints) +
                       " points: the error bound is too small for this surface; use a larger one");
  }
  return collect(cdt, [](MeshCdt::Finite_faces_iterator f) { return f->is_in_domain(); });
}

}  // namespace leafdig::model::detail
