#include "leafdig/model/leaf2d/leaf2d.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>
#include <map>
#include <optional>
#include <sstream>
#include <stdexcept>

#include "json_text.hpp"
#include "leaf2d/outline_check.hpp"
#include "leaf2d/sections.hpp"
#include "leafdig/model/errors.hpp"
#include "leafdig/model/files.hpp"
#include "leafdig/model/limits.hpp"
#include "leafdig/model/metrics/metrics.hpp"
#include "leafdig/model/spline/interpolation.hpp"
#include "mesh/planar_triangulation.hpp"
#include "segment.hpp"

namespace leafdig::model {

using nlohmann::json;

using detail::crossingsAt;
using detail::sectionExtent;

// ---------------------------------------------------------------------------- the 2-D leaf

namespace {

double trianglesArea(const std::vector<Eigen::Vector3d>& p, const std::vector<std::array<std::uint32_t, 3>>& tris,
                     double sxy) {
  double area = 0.0;
  for (const auto& t : tris) {
    const Eigen::Vector3d a(sxy * p[t[0]].x(), sxy * p[t[0]].y(), p[t[0]].z());
    const Eigen::Vector3d b(sxy * p[t[1]].x(), sxy * p[t[1]].y(), p[t[1]].z());
    const Eigen::Vector3d c(sxy * p[t[2]].x(), sxy * p[t[2]].y(), p[t[2]].z());
    area += 0.5 * (b - a).cross(c - a).norm();
  }
  return area;
}

// The in-plane factor s with area(s x, s y, z) = target (area grows with s from 0 at s = 0,
// so a root always exists): bracketed regula falsi (Illinois), to 1e-10 relative.
double constrainArea(const Mesh& mesh, double target) {
  auto f = [&](double s) { return trianglesArea(mesh.positions, mesh.triangles, s) - target; };
  double lo = 0.0;
  double flo = f(lo);
  double hi = 1.0;
  double fhi = f(hi);
  while (fhi < 0.0) {
    lo = hi;
    flo = fhi;
    hi *= 2.0;
    fhi = f(hi);
    if (hi > 1e6) throw InputError("the area constraint cannot be met: the measured area is far above the model's");
  }
  // f(0) = -target: at s = 0 every vertex lies on the Z axis, the surface has no area.
  int side = 0;
  double s = hi;
  for (int it = 0; it < 100; ++it) {
    s = (lo * fhi - hi * flo) / (fhi - flo);
    const double fs = f(s);
    if (std::abs(fs) <= 1e-10 * target) break;
    if (fs < 0.0) {
      lo = s;
      flo = fs;
      if (side == -1) fhi /= 2.0;
      side = -1;
    } else {
      hi = s;
      fhi = fs;
      if (side == 1) flo /= 2.0;
      side = 1;
    }
  }
  return s;
}

struct FlatLeaf {
  BladeSurface blade;
  Mesh mesh;  // z = 0
  std::vector<std::uint32_t> margin;
  std::vector<double> marginT;
  double widthMm = 0.0;
};

// Appends one side of the margin, given as its mesh vertices from the base to the tip, with
// t by arc length from the base: the right side whole, base to tip; the left side tip to
// base without the tip and the base (the right side has them).
void addMarginSide(FlatLeaf& flat, const std::vector<std::uint32_t>& baseToTip, bool right) {
  const auto& p = flat.mesh.positions;
  std::vector<double> s(baseToTip.size(), 0.0);
  for (std::size_t k = 1; k < baseToTip.size(); ++k) s[k] = s[k - 1] + (p[baseToTip[k]] - p[baseToTip[k - 1]]).norm();
  if (right) {
    for (std::size_t k = 0; k < baseToTip.size(); ++k) {
      flat.margin.push_back(baseToTip[k]);
      flat.marginT.push_back(s[k] / s.back());
    }
  } else {
    for (std::size_t k = baseToTip.size() - 2; k >= 1; --k) {
      flat.margin.push_back(baseToTip[k]);
      flat.marginT.push_back(s[k] / s.back());
    }
  }
}

FlatLeaf flatLeaf(const std::vector<Eigen::Vector2d>& local, const Leaf2dOptions& o) {
  double ymin = std::numeric_limits<double>::infinity();
  double ymax = -ymin;
  Eigen::Vector2d lowest = local[0];
  Eigen::Vector2d highest = local[0];
  for (const auto& p : local) {
    if (p.y() < ymin) {
      ymin = p.y();
      lowest = p;
    }
    if (p.y() > ymax) {
      ymax = p.y();
      highest = p;
    }
  }
  const int n = o.rows;
  FlatLeaf flat;
  MarkerGrid grid;
  for (int i = 0; i < n; ++i) {
    std::array<Eigen::Vector3d, kMarkersPerRow> row;
    if (i == 0 || i == n - 1) {
      const Eigen::Vector2d end = i == 0 ? highest : lowest;
      row.fill(Eigen::Vector3d(end.x(), end.y(), 0.0));
    } else {
      // Cosine spacing: sections crowd towards tip and base, where the margin turns.
      const double y = ymax - (ymax - ymin) * (1.0 - std::cos(M_PI * i / (n - 1))) / 2.0;
      const auto e =
          sectionExtent(local, Eigen::Vector2d::Zero(), Eigen::Vector2d::UnitY(), Eigen::Vector2d::UnitX(), y);
      if (!e || e->second - e->first <= 0.0) {
        throw InputError("the outline has no width " + std::to_string(y) + " mm from the base; is it one closed leaf?");
      }
      const double right = e->second;  // +X is the leaf's right (docs/method.md §5: X = Y x Z)
      const double left = e->first;
      const double mid = (0.0 < right && 0.0 > left) ? 0.0 : (left + right) / 2.0;
      const std::array<double, kMarkersPerRow> xs{right, right + (mid - right) / 3, right + 2 * (mid - right) / 3,
                                                  mid,   mid + (left - mid) / 3,    mid + 2 * (left - mid) / 3,
                                                  left};
      for (std::size_t c = 0; c < kMarkersPerRow; ++c) row[c] = Eigen::Vector3d(xs[c], y, 0.0);
      flat.widthMm = std::max(flat.widthMm, right - left);
    }
    grid.push_back(row);
  }
  flat.blade = buildBlade(grid, BladeKind::Interp);
  const int rowSpans = n - 1;
  const std::vector<double> us = subdivideSpans(flat.blade.rowParameters, o.segmentsPerRow * rowSpans);
  const std::vector<double> vs = subdivideSpans(flat.blade.columnParameters, o.segmentsAcross);
  PointGrid pts = sampleSurface(flat.blade, us, vs);
  const auto nu = static_cast<std::uint32_t>(us.size());
  const auto nv = static_cast<std::uint32_t>(vs.size());
  Mesh& mesh = flat.mesh;
  // Vertex 0: the tip; then rows 1..nu-2 of nv; last: the base.
  mesh.positions.push_back(pts[0][0]);
  for (std::uint32_t i = 1; i + 1 < nu; ++i) {
    for (std::uint32_t j = 0; j < nv; ++j) mesh.positions.push_back(pts[i][j]);
  }
  mesh.positions.push_back(pts[nu - 1][0]);
  for (auto& p : mesh.positions) p.z() = 0.0;
  const auto baseIndex = static_cast<std::uint32_t>(mesh.positions.size() - 1);
  auto index = [&](std::uint32_t i, std::uint32_t j) -> std::uint32_t {
    if (i == 0) return 0;
    if (i == nu - 1) return baseIndex;
    return 1 + (i - 1) * nv + j;
  };
  for (std::uint32_t i = 0; i + 1 < nu; ++i) {
    for (std::uint32_t j = 0; j + 1 < nv; ++j) {
      const std::uint32_t a = index(i, j);
      const std::uint32_t b = index(i, j + 1);
      const std::uint32_t c = index(i + 1, j + 1);
      const std::uint32_t d = index(i + 1, j);
      if (a != b && b != c) mesh.triangles.push_back({a, b, c});
      if (a != c && c != d) mesh.triangles.push_back({a, c, d});
      ++mesh.quads;
    }
  }
  // Faces up (+Z, the adaxial side): S_v x S_u with v right to left and u tip to base.
  double nz = 0.0;
  for (const auto& t : mesh.triangles) {
    nz += (mesh.positions[t[1]] - mesh.positions[t[0]]).cross(mesh.positions[t[2]] - mesh.positions[t[0]]).z();
  }
  if (nz < 0.0) {
    for (auto& t : mesh.triangles) std::swap(t[1], t[2]);
  }
  // Margins: right base to tip, then left tip to base (tip and base once), t by arc length.
  for (int side = 0; side < 2; ++side) {
    std::vector<std::uint32_t> chain{baseIndex};
    for (std::uint32_t i = nu - 2; i >= 1; --i) chain.push_back(index(i, side == 0 ? 0 : nv - 1));
    chain.push_back(0);
    addMarginSide(flat, chain, side == 0);
  }
  return flat;
}

// Whether some line across the midrib (y = const in the leaf frame) crosses the outline more
// than twice over a gap wider than `gapMm`: a sinus or a lobe that sections taken from one
// margin to the other would fill.
bool hasSinus(const std::vector<Eigen::Vector2d>& local, double gapMm) {
  double ymin = std::numeric_limits<double>::infinity();
  double ymax = -ymin;
  for (const auto& p : local) {
    ymin = std::min(ymin, p.y());
    ymax = std::max(ymax, p.y());
  }
  constexpr int kLevels = 400;
  for (int i = 1; i < kLevels; ++i) {
    const std::vector<double> xs = crossingsAt(local, ymin + (ymax - ymin) * i / kLevels);
    for (std::size_t k = 1; k + 2 < xs.size(); k += 2) {
      if (xs[k + 1] - xs[k] > gapMm) return true;
    }
  }
  return false;
}

// The point of the closed polygon nearest p, as a parameter along it: segment i + t.
double nearestParameter(const std::vector<Eigen::Vector2d>& poly, const Eigen::Vector2d& p) {
  double best = std::numeric_limits<double>::infinity();
  double at = 0.0;
  for (std::size_t i = 0; i < poly.size(); ++i) {
    const Eigen::Vector2d& a = poly[i];
    const Eigen::Vector2d& b = poly[(i + 1) % poly.size()];
    const double t = detail::nearestOnSegment(a, b, p);
    const double d = (a + t * (b - a) - p).squaredNorm();
    if (d < best) {
      best = d;
      at = static_cast<double>(i) + t;
    }
  }
  return at >= static_cast<double>(poly.size()) ? 0.0 : at;
}

// from, the polygon's corners strictly between parameters sa and sb going forward, to: a
// margin chain.
std::vector<Eigen::Vector2d> chainBetween(const std::vector<Eigen::Vector2d>& poly, double sa, double sb,
                                          const Eigen::Vector2d& from, const Eigen::Vector2d& to) {
  const auto n = static_cast<double>(poly.size());
  if (sb <= sa) sb += n;
  std::vector<Eigen::Vector2d> chain{from};
  for (auto k = static_cast<long>(std::floor(sa)) + 1; static_cast<double>(k) < sb; ++k) {
    chain.push_back(poly[static_cast<std::size_t>(k % static_cast<long>(poly.size()))]);
  }
  chain.push_back(to);
  return chain;
}

// The chain resampled at equal arc length, no piece longer than `spacing`, ends kept.
std::vector<Eigen::Vector2d> resampleChain(const std::vector<Eigen::Vector2d>& chain, double spacing) {
  std::vector<double> s(chain.size(), 0.0);
  for (std::size_t k = 1; k < chain.size(); ++k) s[k] = s[k - 1] + (chain[k] - chain[k - 1]).norm();
  const int pieces = std::max(2, static_cast<int>(std::ceil(s.back() / spacing)));
  std::vector<Eigen::Vector2d> out{chain.front()};
  std::size_t seg = 1;
  for (int i = 1; i < pieces; ++i) {
    const double target = s.back() * i / pieces;
    while (seg + 1 < chain.size() && s[seg] < target) ++seg;
    const double len = s[seg] - s[seg - 1];
    const double t = len > 0.0 ? (target - s[seg - 1]) / len : 0.0;
    out.push_back(chain[seg - 1] + t * (chain[seg] - chain[seg - 1]));
  }
  out.push_back(chain.back());
  return out;
}

// The flat leaf trimmed to the outline: the flat surface is the plane z = 0, so the sections'
// B-spline surface cut along the outline is the outline's own region. Meshed by a constrained
// Delaunay triangulation of the outline (resampled every h / 2, base and tip corners) and a
// hexagonal lattice of interior points every h, where h gives about as many vertices as the
// sections' mesh. Tip first, base last, margin and t as flatLeaf's.
FlatLeaf trimmedFlatLeaf(const std::vector<Eigen::Vector2d>& local, double lengthMm, double widthMm,
                         const Leaf2dOptions& o) {
  const double h = std::sqrt(lengthMm * widthMm / (o.segmentsPerRow * (o.rows - 1) * o.segmentsAcross));
  const Eigen::Vector2d base(0.0, 0.0);
  const Eigen::Vector2d tip(0.0, lengthMm);
  const double sBase = nearestParameter(local, base);
  const double sTip = nearestParameter(local, tip);
  if (sBase == sTip) throw InputError("the base and the tip meet the outline at one point");
  std::vector<Eigen::Vector2d> one = resampleChain(chainBetween(local, sBase, sTip, base, tip), h / 2);
  std::vector<Eigen::Vector2d> other = resampleChain(chainBetween(local, sTip, sBase, tip, base), h / 2);
  std::reverse(other.begin(), other.end());  // base to tip as well
  double meanOne = 0.0;
  double meanOther = 0.0;
  for (const auto& p : one) meanOne += p.x() / static_cast<double>(one.size());
  for (const auto& p : other) meanOther += p.x() / static_cast<double>(other.size());
  const std::vector<Eigen::Vector2d>& right = meanOne >= meanOther ? one : other;  // +X: docs/method.md §5
  const std::vector<Eigen::Vector2d>& left = meanOne >= meanOther ? other : one;

  // Vertices: the tip, the right margin (tip to base), the left margin (tip to base), the
  // interior lattice, the base.
  FlatLeaf flat;
  flat.widthMm = widthMm;
  std::vector<Eigen::Vector2d> points{tip};
  for (std::size_t k = right.size() - 2; k >= 1; --k) points.push_back(right[k]);
  for (std::size_t k = left.size() - 2; k >= 1; --k) points.push_back(left[k]);
  const auto marginCount = points.size();
  // The polygon, counter-clockwise: base, up the right margin, tip, down the left.
  std::vector<Eigen::Vector2d> polygon(right.begin(), right.end());
  for (std::size_t k = left.size() - 2; k >= 1; --k) polygon.push_back(left[k]);

  double xmin = std::numeric_limits<double>::infinity();
  double xmax = -xmin;
  double ymin = xmin;
  double ymax = -xmin;
  for (const auto& p : polygon) {
    xmin = std::min(xmin, p.x());
    xmax = std::max(xmax, p.x());
    ymin = std::min(ymin, p.y());
    ymax = std::max(ymax, p.y());
  }
  // Edges bucketed by cell (side h) for the distance test: a point nearer than h / 2 to an
  // edge meets it within its own cell or a neighbour.
  const auto cols = static_cast<long>(std::ceil((xmax - xmin) / h)) + 1;
  const auto rows = static_cast<long>(std::ceil((ymax - ymin) / h)) + 1;
  std::vector<std::vector<std::uint32_t>> cells(static_cast<std::size_t>(cols * rows));
  auto cellOf = [&](double v, double lo, long count) {
    return std::clamp(static_cast<long>(std::floor((v - lo) / h)), 0L, count - 1);
  };
  for (std::uint32_t i = 0; i < polygon.size(); ++i) {
    const Eigen::Vector2d& a = polygon[i];
    const Eigen::Vector2d& b = polygon[(i + 1) % polygon.size()];
    for (long cy = cellOf(std::min(a.y(), b.y()), ymin, rows); cy <= cellOf(std::max(a.y(), b.y()), ymin, rows); ++cy) {
      for (long cx = cellOf(std::min(a.x(), b.x()), xmin, cols); cx <= cellOf(std::max(a.x(), b.x()), xmin, cols);
           ++cx) {
        cells[static_cast<std::size_t>(cy * cols + cx)].push_back(i);
      }
    }
  }
  auto nearEdge = [&](const Eigen::Vector2d& p) {
    const long cx = cellOf(p.x(), xmin, cols);
    const long cy = cellOf(p.y(), ymin, rows);
    for (long y = std::max(0L, cy - 1); y <= std::min(rows - 1, cy + 1); ++y) {
      for (long x = std::max(0L, cx - 1); x <= std::min(cols - 1, cx + 1); ++x) {
        for (std::uint32_t i : cells[static_cast<std::size_t>(y * cols + x)]) {
          if (std::sqrt(detail::squaredDistanceToSegment(polygon[i], polygon[(i + 1) % polygon.size()], p)) < h / 2)
            return true;
        }
      }
    }
    return false;
  };
  const double rowStep = h * std::sqrt(3.0) / 2.0;
  for (long j = 0; ymin + (static_cast<double>(j) + 0.5) * rowStep < ymax; ++j) {
    const double y = ymin + (static_cast<double>(j) + 0.5) * rowStep;
    const std::vector<double> xs = crossingsAt(polygon, y);
    for (std::size_t k = 0; k + 1 < xs.size(); k += 2) {  // the inside spans of this row
      const double offset = (j % 2 == 0 ? 0.0 : 0.5) * h;
      for (auto i = static_cast<long>(std::ceil((xs[k] - xmin - offset) / h));; ++i) {
        const Eigen::Vector2d p(xmin + offset + static_cast<double>(i) * h, y);
        if (p.x() >= xs[k + 1]) break;
        if (!nearEdge(p)) points.push_back(p);
      }
    }
  }
  points.push_back(base);

  const detail::PlanarTriangulation tri = detail::triangulatePolygon(
      polygon, std::vector<Eigen::Vector2d>(points.begin() + static_cast<long>(marginCount), points.end() - 1));
  std::map<std::pair<double, double>, std::uint32_t> indexOf;
  for (std::uint32_t i = 0; i < points.size(); ++i) indexOf[{points[i].x(), points[i].y()}] = i;
  std::vector<std::uint32_t> mine(tri.points.size());
  for (std::size_t i = 0; i < tri.points.size(); ++i) {
    const auto it = indexOf.find({tri.points[i].x(), tri.points[i].y()});
    if (it == indexOf.end()) throw std::logic_error("trimmedFlatLeaf: the triangulation moved a point");
    mine[i] = it->second;
  }
  Mesh& mesh = flat.mesh;
  for (const auto& p : points) mesh.positions.emplace_back(p.x(), p.y(), 0.0);
  for (const auto& t : tri.triangles) mesh.triangles.push_back({mine[t[0]], mine[t[1]], mine[t[2]]});  // +Z up

  // Margins as flatLeaf's: right base to tip, then left tip to base, t by arc length.
  const auto baseIndex = static_cast<std::uint32_t>(points.size() - 1);
  for (int side = 0; side < 2; ++side) {
    const std::vector<Eigen::Vector2d>& chain = side == 0 ? right : left;
    const std::uint32_t first =
        side == 0 ? 1 : static_cast<std::uint32_t>(right.size() - 1);  // its vertex nearest the tip
    std::vector<std::uint32_t> ids{baseIndex};
    for (std::size_t k = 1; k + 1 < chain.size(); ++k) {
      ids.push_back(first + static_cast<std::uint32_t>(chain.size() - 2 - k));
    }
    ids.push_back(0);
    addMarginSide(flat, ids, side == 0);
  }
  return flat;
}

}  // namespace

Leaf2dModel buildLeaf2d(const Outline2d& outline, const Leaf2dOptions& o) {
  detail::checkOutline(outline, outline.id.empty() ? "outline" : outline.id);
  if (o.rows < 6) throw InputError("--rows must be at least 6 (sections from tip to base)");
  if (o.segmentsPerRow < 1 || o.segmentsAcross < 6) throw InputError("mesh segments: at least 1 per row and 6 across");
  if (o.amplitudeMm && !(*o.amplitudeMm >= 0.0)) throw InputError("--amplitude must be >= 0 mm");
  if (!(o.light.norm() > 0.0)) throw InputError("--light must be a non-zero direction");
  Leaf2dModel model;
  const auto [base, tip] = findBaseAndTip(outline);
  model.baseMm = base;
  model.tipMm = tip;
  model.lengthMm = (tip - base).norm();
  if (!(model.lengthMm > 0.0)) throw InputError("the leaf's base and tip coincide; give them apart");
  // Leaf frame (docs/method.md §5): origin at the base, +Y to the tip, +Z up, X = Y x Z.
  const Eigen::Vector2d axis = (tip - base) / model.lengthMm;
  const Eigen::Vector2d right(axis.y(), -axis.x());
  std::vector<Eigen::Vector2d> local;
  local.reserve(outline.pointsMm.size());
  for (const auto& p : outline.pointsMm) local.emplace_back((p - base).dot(right), (p - base).dot(axis));

  FlatLeaf flat = flatLeaf(local, o);
  model.flatBlade = flat.blade;
  model.widthMm = flat.widthMm;
  model.outlineAreaMm2 = polygonArea(outline.pointsMm);
  model.flatModelAreaMm2 = meshArea(flat.mesh);
  if (model.flatModelAreaMm2 > 1.01 * model.outlineAreaMm2 && hasSinus(local, 0.02 * flat.widthMm)) {
    // The sections span a sinus or lobes the leaf does not have: mesh inside the outline.
    // A given base so far off the margin that the outline would cross itself keeps the
    // sections' leaf, with the warning below.
    try {
      FlatLeaf trimmed = trimmedFlatLeaf(local, model.lengthMm, flat.widthMm, o);
      trimmed.blade = std::move(flat.blade);
      flat = std::move(trimmed);
      model.trimmedToOutline = true;
      model.flatModelAreaMm2 = meshArea(flat.mesh);
    } catch (const InputError&) {
    }
  }
  model.marginVertices = flat.margin;
  model.marginT = flat.marginT;
  if (const double d = model.flatModelAreaMm2 / model.outlineAreaMm2 - 1.0; std::abs(d) > 0.02) {
    std::ostringstream msg;
    msg << std::fixed << std::setprecision(1) << "the flat B-spline leaf is " << std::abs(100.0 * d) << " % "
        << (d > 0 ? "larger" : "smaller") << " than the outline: "
        << (d > 0 ? "its sections span a sinus or deep lobes (a cordate base, a lobed margin) that the leaf does not "
                    "have, and the area constraint draws the whole leaf in to compensate (the outline could not be "
                    "meshed as it is: check that the base lies on the margin)"
                  : "the outline has detail the sections miss; raise --rows")
        << ".";
    model.warnings.push_back({"flat-leaf-differs-from-outline", msg.str()});
  }
  model.measuredAreaMm2 = o.measuredAreaMm2         ? *o.measuredAreaMm2
                          : outline.measuredAreaMm2 ? *outline.measuredAreaMm2
                                                    : model.outlineAreaMm2;
  if (!(model.measuredAreaMm2 > 0.0)) throw InputError("the measured area must be positive (mm^2)");
  model.amplitudeMm = o.amplitudeMm ? *o.amplitudeMm : 0.1 * model.widthMm;
  const Eigen::Vector3d light = o.light.normalized();

  std::vector<CurlKind> kinds{o.curl};
  if (o.curl == CurlKind::Auto) kinds = {CurlKind::Parabola, CurlKind::Sine};
  std::optional<Mesh> best;
  for (CurlKind kind : kinds) {
    Mesh mesh = flat.mesh;
    if (kind != CurlKind::None && model.amplitudeMm > 0.0) {
      std::vector<std::pair<std::uint32_t, Eigen::Vector3d>> handles;
      for (std::size_t k = 0; k < flat.margin.size(); ++k) {
        Eigen::Vector3d p = flat.mesh.positions[flat.margin[k]];
        p.z() = model.amplitudeMm * curlHeight(kind, flat.marginT[k]);
        handles.emplace_back(flat.margin[k], p);
      }
      mesh.positions = laplacianDeform(flat.mesh, handles);
    }
    const double s = constrainArea(mesh, model.measuredAreaMm2);
    for (auto& p : mesh.positions) {
      p.x() *= s;
      p.y() *= s;
    }
    setAreaWeightedNormals(mesh);
    const CurlCandidate c{kind, s, meshArea(mesh), projectedArea(mesh, light)};
    model.candidates.push_back(c);
    if (!best || c.projectedAreaMm2 > model.projectedAreaMm2) {
      best = std::move(mesh);
      model.curl = kind;
      model.inPlaneScale = c.inPlaneScale;
      model.modelAreaMm2 = c.areaMm2;
      model.projectedAreaMm2 = c.projectedAreaMm2;
    }
  }
  model.mesh = std::move(*best);
  model.silhouetteAreaMm2 = silhouetteArea({&model.mesh}, light);
  if (model.inPlaneScale < 0.9 && model.curl != CurlKind::None) {
    std::ostringstream msg;
    msg << std::fixed << std::setprecision(1) << "holding the measured area drew the leaf in to "
        << 100.0 * model.inPlaneScale << " % of its outline: an amplitude of " << model.amplitudeMm
        << " mm is large for a leaf " << model.widthMm << " mm wide; check --amplitude";
    model.warnings.push_back({"curl-draws-leaf-in", msg.str()});
  }
  return model;
}

std::string leaf2dToJson(const Leaf2dModel& m) {
  json j;
  j["base_mm"] = {m.baseMm.x(), m.baseMm.y()};
  j["tip_mm"] = {m.tipMm.x(), m.tipMm.y()};
  j["length_mm"] = m.lengthMm;
  j["width_mm"] = m.widthMm;
  j["outline_area_mm2"] = m.outlineAreaMm2;
  j["flat_model_area_mm2"] = m.flatModelAreaMm2;
  j["flat_leaf"] = m.trimmedToOutline ? "trimmed-to-outline" : "sections";
  j["measured_area_mm2"] = m.measuredAreaMm2;
  j["model_area_mm2"] = m.modelAreaMm2;
  j["area_difference_percent"] = 100.0 * (m.modelAreaMm2 - m.measuredAreaMm2) / m.measuredAreaMm2;
  j["projected_area_mm2"] = m.projectedAreaMm2;
  j["silhouette_area_mm2"] = m.silhouetteAreaMm2;
  j["curl"] = toString(m.curl);
  j["amplitude_mm"] = m.amplitudeMm;
  j["in_plane_scale"] = m.inPlaneScale;
  j["candidates"] = json::array();
  for (const auto& c : m.candidates) {
    j["candidates"].push_back({{"curl", toString(c.kind)},
                               {"in_plane_scale", c.inPlaneScale},
                               {"area_mm2", c.areaMm2},
                               {"projected_area_mm2", c.projectedAreaMm2}});
  }
  j["warnings"] = json::array();
  for (const Warning& w : m.warnings) j["warnings"].push_back({{"name", w.name}, {"message", w.message}});
  j["vertices"] = m.mesh.positions.size();
  j["triangles"] = m.mesh.triangles.size();
  return detail::dumpFinite(j);
}

}  // namespace leafdig::model
