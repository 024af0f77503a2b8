#include "leafdig/model/mesh/mesh_compare.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <numeric>
#include <thread>

#include "leafdig/model/errors.hpp"
#include "segment.hpp"

namespace leafdig::model {

TriangleSoup soupOf(const Mesh& mesh) {
  return {mesh.positions, mesh.triangles};
}

TriangleSoup soupOf(const LeafMesh& mesh) {
  TriangleSoup out;
  for (const Organ& organ : mesh.organs) {
    const auto offset = static_cast<std::uint32_t>(out.positions.size());
    out.positions.insert(out.positions.end(), organ.mesh.positions.begin(), organ.mesh.positions.end());
    for (const auto& t : organ.mesh.triangles) out.triangles.push_back({t[0] + offset, t[1] + offset, t[2] + offset});
  }
  return out;
}

double surfaceArea(const TriangleSoup& soup) {
  double area = 0.0;
  for (const auto& t : soup.triangles) {
    const Eigen::Vector3d& a = soup.positions[t[0]];
    area += 0.5 * (soup.positions[t[1]] - a).cross(soup.positions[t[2]] - a).norm();
  }
  return area;
}

namespace {

// Squared distance from p to triangle abc (Ericson, Real-Time Collision Detection 5.1.5:
// Voronoi regions of the vertices, edges and face).
double squaredDistanceToTriangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                 const Eigen::Vector3d& c) {
  const Eigen::Vector3d ab = b - a;
  const Eigen::Vector3d ac = c - a;
  const Eigen::Vector3d ap = p - a;
  const double d1 = ab.dot(ap);
  const double d2 = ac.dot(ap);
  if (d1 <= 0.0 && d2 <= 0.0) return ap.squaredNorm();
  const Eigen::Vector3d bp = p - b;
  const double d3 = ab.dot(bp);
  const double d4 = ac.dot(bp);
  if (d3 >= 0.0 && d4 <= d3) return bp.squaredNorm();
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
    const double v = d1 / (d1 - d3);
    return (p - (a + v * ab)).squaredNorm();
  }
  const Eigen::Vector3d cp = p - c;
  const double d5 = ab.dot(cp);
  const double d6 = ac.dot(cp);
  if (d6 >= 0.0 && d5 <= d6) return cp.squaredNorm();
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
    const double w = d2 / (d2 - d6);
    return (p - (a + w * ac)).squaredNorm();
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) {
    const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return (p - (b + w * (c - b))).squaredNorm();
  }
  const double denominator = va + vb + vc;
  if (!(denominator > 0.0)) {  // degenerate triangle: its three edges
    return std::min({detail::squaredDistanceToSegment(a, b, p), detail::squaredDistanceToSegment(b, c, p),
                     detail::squaredDistanceToSegment(c, a, p)});
  }
  const double v = vb / denominator;
  const double w = vc / denominator;
  return (p - (a + v * ab + w * ac)).squaredNorm();
}

struct Box {
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d hi = Eigen::Vector3d::Constant(-std::numeric_limits<double>::infinity());
  void grow(const Eigen::Vector3d& p) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  [[nodiscard]] double squaredDistance(const Eigen::Vector3d& p) const {
    const Eigen::Vector3d d = (lo - p).cwiseMax(p - hi).cwiseMax(0.0);
    return d.squaredNorm();
  }
};

// SplitMix64: a counter-based source, so each sample's numbers depend on its index only
// and any number of threads gives the same samples.
std::uint64_t mix(std::uint64_t x) {
  x += 0x9E3779B97F4A7C15ULL;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ULL;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBULL;
  return x ^ (x >> 31);
}
double unit(std::uint64_t x) {
  return static_cast<double>(x >> 11) * 0x1.0p-53;
}

}  // namespace

struct TriangleDistance::Impl {
  struct Node {
    Box box;
    std::uint32_t first = 0;  // leaf: first triangle in `order`; inner: left child index
    std::uint32_t count = 0;  // leaf: triangles; inner: 0 (right child = left + 1)
  };
  std::vector<Eigen::Vector3d> a, b, c;  // triangle corners in hierarchy order
  std::vector<Node> nodes;

  explicit Impl(const TriangleSoup& soup) {
    const std::size_t n = soup.triangles.size();
    std::vector<std::uint32_t> order(n);
    std::iota(order.begin(), order.end(), 0U);
    std::vector<Eigen::Vector3d> centroid(n);
    for (std::size_t i = 0; i < n; ++i) {
      const auto& t = soup.triangles[i];
      centroid[i] = (soup.positions[t[0]] + soup.positions[t[1]] + soup.positions[t[2]]) / 3.0;
    }
    nodes.reserve(2 * n / 2 + 1);
    nodes.push_back({});
    build(soup, order, centroid, 0, 0, static_cast<std::uint32_t>(n));
    a.reserve(n);
    b.reserve(n);
    c.reserve(n);
    for (std::uint32_t i : order) {
      const auto& t = soup.triangles[i];
      a.push_back(soup.positions[t[0]]);
      b.push_back(soup.positions[t[1]]);
      c.push_back(soup.positions[t[2]]);
    }
  }

  void build(const TriangleSoup& soup, std::vector<std::uint32_t>& order, const std::vector<Eigen::Vector3d>& centroid,
             std::size_t node, std::uint32_t first, std::uint32_t count) {
    Box box;
    Box centres;
    for (std::uint32_t k = first; k < first + count; ++k) {
      const auto& t = soup.triangles[order[k]];
      for (std::uint32_t v : t) box.grow(soup.positions[v]);
      centres.grow(centroid[order[k]]);
    }
    nodes[node].box = box;
    if (count <= 4) {
      nodes[node].first = first;
      nodes[node].count = count;
      return;
    }
    int axis = 0;
    (centres.hi - centres.lo).maxCoeff(&axis);
    const std::uint32_t half = count / 2;
    std::nth_element(order.begin() + first, order.begin() + first + half, order.begin() + first + count,
                     [&](std::uint32_t x, std::uint32_t y) { return centroid[x][axis] < centroid[y][axis]; });
    const auto left = static_cast<std::uint32_t>(nodes.size());
    nodes[node].first = left;
    nodes[node].count = 0;
    nodes.push_back({});
    nodes.push_back({});
    build(soup, order, centroid, left, first, half);
    build(soup, order, centroid, left + 1, first + half, count - half);
  }

  [[nodiscard]] double query(const Eigen::Vector3d& p, double best2) const {
    if (nodes.empty() || a.empty()) return std::numeric_limits<double>::infinity();
    std::uint32_t stack[128];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
      const Node& node = nodes[stack[--top]];
      if (node.box.squaredDistance(p) >= best2) continue;
      if (node.count > 0) {
        for (std::uint32_t k = node.first; k < node.first + node.count; ++k)
          best2 = std::min(best2, squaredDistanceToTriangle(p, a[k], b[k], c[k]));
        continue;
      }
      const std::uint32_t l = node.first;
      const double dl = nodes[l].box.squaredDistance(p);
      const double dr = nodes[l + 1].box.squaredDistance(p);
      // Push the farther child first so the nearer one is searched first.
      if (dl < dr) {
        if (dr < best2) stack[top++] = l + 1;
        if (dl < best2) stack[top++] = l;
      } else {
        if (dl < best2) stack[top++] = l;
        if (dr < best2) stack[top++] = l + 1;
      }
    }
    return best2;
  }
};

TriangleDistance::TriangleDistance(const TriangleSoup& soup) : impl_(new Impl(soup)) {}
TriangleDistance::~TriangleDistance() {
  delete impl_;
}

double TriangleDistance::distance(const Eigen::Vector3d& p, double upperBound) const {
  // A bound that is exactly the answer must not prune the triangle that attains it.
  const double bound = std::isfinite(upperBound) ? upperBound * (1.0 + 1e-9) + 1e-12 : upperBound;
  return std::sqrt(impl_->query(p, bound * bound));
}

OneSidedDistance oneSidedDistance(const TriangleSoup& from, const TriangleDistance& to, const CompareOptions& o) {
  const std::size_t n = from.triangles.size();
  std::vector<double> cumulative(n);
  double total = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const auto& t = from.triangles[i];
    const Eigen::Vector3d& a = from.positions[t[0]];
    total += 0.5 * (from.positions[t[1]] - a).cross(from.positions[t[2]] - a).norm();
    cumulative[i] = total;
  }
  if (!(total > 0.0)) throw InputError("a mesh to compare has no triangle of positive area");
  const auto areaSamples =
      std::max(o.samples, static_cast<std::size_t>(std::ceil(o.perTriangle * static_cast<double>(n))));
  // Every vertex, or, when there are more vertices than area samples, an evenly spread
  // `areaSamples` of them (a fine reference mesh would otherwise dominate the cost).
  const std::size_t vertices = from.positions.size();
  const std::size_t vertexSamples = std::min(vertices, areaSamples);
  const std::size_t count = vertexSamples + areaSamples;

  // Sample k < vertexSamples is a vertex; the others are stratified over the cumulative
  // area (sample j in [j/N, (j+1)/N)), with barycentric (1-sqrt r1, sqrt r1 (1-r2), sqrt r1 r2).
  auto samplePoint = [&](std::size_t k) -> Eigen::Vector3d {
    if (k < vertexSamples) return from.positions[vertexSamples == vertices ? k : k * vertices / vertexSamples];
    const std::size_t j = k - vertexSamples;
    const std::uint64_t h = mix(o.seed * 0x100000001B3ULL + j);
    const double target = (static_cast<double>(j) + unit(h)) / static_cast<double>(areaSamples) * total;
    const std::size_t i = std::min<std::size_t>(
        std::lower_bound(cumulative.begin(), cumulative.end(), target) - cumulative.begin(), n - 1);
    const double r1 = std::sqrt(unit(mix(h)));
    const double r2 = unit(mix(h ^ 0xD1B54A32D192ED03ULL));
    const auto& t = from.triangles[i];
    return (1.0 - r1) * from.positions[t[0]] + r1 * (1.0 - r2) * from.positions[t[1]] + r1 * r2 * from.positions[t[2]];
  };

  struct Partial {
    double max = 0.0, sum = 0.0, sum2 = 0.0;
  };
  const int threads = std::max(1, o.threads);
  std::vector<Partial> partial(static_cast<std::size_t>(threads));
  auto work = [&](int w) {
    const std::size_t begin = count * static_cast<std::size_t>(w) / static_cast<std::size_t>(threads);
    const std::size_t end = count * static_cast<std::size_t>(w + 1) / static_cast<std::size_t>(threads);
    Partial& r = partial[static_cast<std::size_t>(w)];
    Eigen::Vector3d previous = Eigen::Vector3d::Zero();
    double previousDistance = std::numeric_limits<double>::infinity();
    for (std::size_t k = begin; k < end; ++k) {
      const Eigen::Vector3d p = samplePoint(k);
      // Consecutive samples are near each other: the last answer bounds this one.
      const double bound = std::isfinite(previousDistance) ? previousDistance + (p - previous).norm()
                                                           : std::numeric_limits<double>::infinity();
      const double d = to.distance(p, bound);
      r.max = std::max(r.max, d);
      r.sum += d;
      r.sum2 += d * d;
      previous = p;
      previousDistance = d;
    }
  };
  std::vector<std::thread> pool;
  for (int w = 1; w < threads; ++w) pool.emplace_back(work, w);
  work(0);
  for (auto& t : pool) t.join();
  OneSidedDistance out;
  double sum = 0.0;
  double sum2 = 0.0;
  for (const Partial& r : partial) {
    out.max = std::max(out.max, r.max);
    sum += r.sum;
    sum2 += r.sum2;
  }
  out.samples = count;
  out.mean = sum / static_cast<double>(count);
  out.rms = std::sqrt(sum2 / static_cast<double>(count));
  return out;
}

MeshDistance compareMeshes(const TriangleSoup& a, const TriangleSoup& b, const CompareOptions& o) {
  MeshDistance out;
  out.trianglesA = a.triangles.size();
  out.trianglesB = b.triangles.size();
  if (a.triangles.empty() || b.triangles.empty()) throw InputError("a mesh to compare has no triangles");
  const TriangleDistance toB(b);
  const TriangleDistance toA(a);
  out.aToB = oneSidedDistance(a, toB, o);
  out.bToA = oneSidedDistance(b, toA, o);
  out.hausdorff = std::max(out.aToB.max, out.bToA.max);
  const auto na = static_cast<double>(out.aToB.samples);
  const auto nb = static_cast<double>(out.bToA.samples);
  out.mean = (out.aToB.mean * na + out.bToA.mean * nb) / (na + nb);
  out.rms = std::sqrt((out.aToB.rms * out.aToB.rms * na + out.bToA.rms * out.bToA.rms * nb) / (na + nb));
  return out;
}

}  // namespace leafdig::model
