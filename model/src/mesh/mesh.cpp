#include "leafdig/model/mesh/mesh.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>

#include "mesh/vein_rings.hpp"

namespace leafdig::model {

MeshResolution MeshResolution::preset(const std::string& name) {
  if (name == "paper") return {"paper", 5, 20, 10, 10, 30, 5, CapStyle::None, 0};
  if (name == "preview") return {"preview", 8, 9, 4, 4, 18, 3, CapStyle::Sphere, 3};
  if (name == "export") return {"export", 16, 30, 12, 12, 60, 10, CapStyle::Sphere, 6};
  if (name == "reference") return {"reference", 48, 90, 36, 36, 180, 30, CapStyle::Sphere, 12};
  throw InputError("unknown resolution \"" + name + "\": use paper, preview, export or reference");
}

std::vector<double> subdivideSpans(const std::vector<double>& breaks, int segments) {
  const int spans = static_cast<int>(breaks.size()) - 1;
  std::vector<double> ts{breaks.front()};
  for (int s = 0; s < spans; ++s) {
    const int here = segments / spans + (s < segments % spans ? 1 : 0);
    const int count = std::max(here, 1);
    for (int k = 1; k <= count; ++k) {
      const double f = static_cast<double>(k) / count;
      ts.push_back(k == count ? breaks[s + 1] : breaks[s] + f * (breaks[s + 1] - breaks[s]));
    }
  }
  return ts;
}

namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;

void addWarning(std::vector<Warning>& warnings, const std::string& organ, double t, const std::string& message) {
  for (const Warning& w : warnings) {
    if (w.organ == organ && w.message == message) return;  // first occurrence is enough
  }
  warnings.push_back({.message = message, .organ = organ, .parameter = t});
}

Eigen::Vector3d safeNormal(const Eigen::Vector3d& v, const Eigen::Vector3d& fallback) {
  const double n = v.norm();
  return n > 1e-12 ? Eigen::Vector3d(v / n) : fallback;
}

// Appends triangle (a, b, c), turned to face `outward` if it does not.
void addOrientedTriangle(Mesh& mesh, std::uint32_t a, std::uint32_t b, std::uint32_t c,
                         const Eigen::Vector3d& outward) {
  const Eigen::Vector3d& pa = mesh.positions[a];
  const Eigen::Vector3d n = (mesh.positions[b] - pa).cross(mesh.positions[c] - pa);
  if (n.dot(outward) < 0.0) std::swap(b, c);
  mesh.triangles.push_back({a, b, c});
}

// A hemispherical cap closing the tube at one end. `ring0` is the first vertex of the end
// ring; `axis` points out of the tube.
void addCap(Mesh& mesh, const Vein& vein, double t, const Frame& frame, const Eigen::Vector3d& axis,
            std::uint32_t ring0, int ringVertices, int capRings) {
  const auto jet = vein.curve.jet(t);
  const double r = std::max(jet.r, 0.0);
  if (r <= 0.0 || capRings < 1) return;
  const double speed = jet.dc.norm();
  // Polar angle of the envelope circle from the cap's axis: cos(phi0) = +-r'/|c'|.
  double cosPhi0 = speed > 0.0 ? (axis.dot(frame.tangent) < 0 ? jet.dr : -jet.dr) / speed : 0.0;
  // Where the envelope does not exist the tube ends in the ball's great circle.
  if (!vein.curve.envelopeCircle(t).exists) cosPhi0 = 0.0;
  cosPhi0 = std::clamp(cosPhi0, -1.0, 1.0);
  const double phi0 = std::acos(cosPhi0);
  std::uint32_t previous = ring0;
  for (int m = 1; m < capRings; ++m) {
    const double phi = phi0 * (1.0 - static_cast<double>(m) / capRings);
    const auto start = static_cast<std::uint32_t>(mesh.positions.size());
    for (int j = 0; j < ringVertices; ++j) {
      const double theta = kTwoPi * j / ringVertices;
      const Eigen::Vector3d dir =
          std::cos(phi) * axis + std::sin(phi) * (std::cos(theta) * frame.normal + std::sin(theta) * frame.binormal);
      mesh.positions.push_back(jet.c + r * dir);
      mesh.normals.push_back(dir.normalized());
    }
    for (int j = 0; j < ringVertices; ++j) {
      const auto j1 = static_cast<std::uint32_t>((j + 1) % ringVertices);
      const auto a = previous + static_cast<std::uint32_t>(j);
      const auto b = previous + j1;
      const auto c = start + j1;
      const auto d = start + static_cast<std::uint32_t>(j);
      const Eigen::Vector3d out = (mesh.positions[a] + mesh.positions[c]) / 2 - jet.c;
      addOrientedTriangle(mesh, a, b, c, out);
      addOrientedTriangle(mesh, a, c, d, out);
      ++mesh.quads;
    }
    previous = start;
  }
  const auto pole = static_cast<std::uint32_t>(mesh.positions.size());
  mesh.positions.push_back(jet.c + r * axis);
  mesh.normals.push_back(axis);
  for (int j = 0; j < ringVertices; ++j) {
    const auto a = previous + static_cast<std::uint32_t>(j);
    const auto b = previous + static_cast<std::uint32_t>((j + 1) % ringVertices);
    addOrientedTriangle(mesh, a, b, pole, mesh.positions[a] - jet.c + axis * r);
  }
}

}  // namespace

Mesh meshVein(const Vein& vein, const std::vector<double>& ts, int ringVertices, CapStyle caps, int capRings,
              std::vector<Warning>& warnings) {
  Mesh mesh;
  // Each parameter is evaluated once; frames, circles and checks share the jets.
  std::vector<BallBSplineCurve::Jet> jets;
  std::vector<Eigen::Vector3d> centres;
  std::vector<Eigen::Vector3d> derivatives;
  jets.reserve(ts.size());
  for (double t : ts) {
    jets.push_back(vein.curve.jet(t));
    centres.push_back(jets.back().c);
    derivatives.push_back(jets.back().dc);
  }
  const std::vector<Frame> frames = rotationMinimisingFrames(centres, derivatives);
  const auto k = static_cast<std::uint32_t>(ringVertices);
  mesh.positions.reserve(ts.size() * k);
  mesh.normals.reserve(ts.size() * k);
  mesh.triangles.reserve(2 * ts.size() * k);
  for (std::size_t s = 0; s < ts.size(); ++s) {
    const double t = ts[s];
    const auto& jet = jets[s];
    const auto circle = BallBSplineCurve::envelopeCircle(jet);
    if (jet.r <= 0.0) {
      std::ostringstream msg;
      msg << "radius spline overshoots to " << jet.r
          << " mm (a thickness reading much smaller than its neighbours?); drawn with radius 0 "
             "there — check the thickness readings of this vein";
      addWarning(warnings, vein.name, t, msg.str());
    } else if (!circle.exists) {
      addWarning(warnings, vein.name, t,
                 "the vein's radius changes faster than its length (|r'| >= |c'|), so the ball "
                 "envelope does not exist here; drawn with the ball's great circle — check the "
                 "markers and thicknesses of this vein");
    } else {
      const double speed = jet.dc.norm();
      const double curvature = jet.dc.cross(jet.ddc).norm() / (speed * speed * speed);
      if (circle.radius * curvature >= 1.0) {
        addWarning(warnings, vein.name, t,
                   "the vein bends more tightly than its own radius, so its surface folds onto "
                   "itself here; check for a mis-placed marker");
      }
    }
    const Frame& f = frames[s];
    for (std::uint32_t j = 0; j < k; ++j) {
      const double theta = kTwoPi * j / ringVertices;
      const Eigen::Vector3d p =
          circle.center + circle.radius * (std::cos(theta) * f.normal + std::sin(theta) * f.binormal);
      const Eigen::Vector3d radial = std::cos(theta) * f.normal + std::sin(theta) * f.binormal;
      // On the envelope the surface normal points from the ball's centre to the point.
      mesh.positions.push_back(p);
      mesh.normals.push_back(safeNormal(p - jet.c, radial));
    }
  }
  for (std::uint32_t s = 0; s + 1 < ts.size(); ++s) {
    for (std::uint32_t j = 0; j < k; ++j) {
      const std::uint32_t a = s * k + j;
      const std::uint32_t b = s * k + (j + 1) % k;
      const std::uint32_t c = (s + 1) * k + (j + 1) % k;
      const std::uint32_t d = (s + 1) * k + j;
      // a->b turns with theta (towards B), b->c runs along T: (B x T) = N, outward.
      mesh.triangles.push_back({a, b, c});
      mesh.triangles.push_back({a, c, d});
      ++mesh.quads;
    }
  }
  if (caps == CapStyle::Sphere && ts.size() >= 2) {
    addCap(mesh, vein, ts.front(), frames.front(), -frames.front().tangent, 0, ringVertices, capRings);
    const auto lastRing = static_cast<std::uint32_t>((ts.size() - 1) * k);
    addCap(mesh, vein, ts.back(), frames.back(), frames.back().tangent, lastRing, ringVertices, capRings);
  }
  return mesh;
}

Mesh meshBlade(const BladeSurface& blade, int segmentsPerRow, int segmentsAcross) {
  const int rowSpans = static_cast<int>(blade.rowParameters.size()) - 1;
  const std::vector<double> us = subdivideSpans(blade.rowParameters, segmentsPerRow * rowSpans);
  const std::vector<double> vs = subdivideSpans(blade.columnParameters, segmentsAcross);
  const PointGrid grid = sampleSurface(blade, us, vs);
  Mesh mesh;
  const auto nv = static_cast<std::uint32_t>(vs.size());
  for (const auto& row : grid) {
    for (const auto& p : row) mesh.positions.push_back(p);
  }
  auto addIfNotDegenerate = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c) {
    const Eigen::Vector3d& pa = mesh.positions[a];
    const Eigen::Vector3d& pb = mesh.positions[b];
    const Eigen::Vector3d& pc = mesh.positions[c];
    const Eigen::Vector3d n = (pb - pa).cross(pc - pa);
    // Degenerate when its height is below 1e-9 of its longest edge (|n| = height x longest):
    // scale-free, so the tip row's repeated points, equal in the digitizer frame and a few
    // 1e-13 mm apart after a rigid motion, never make a sliver that an export rounds to zero.
    const double longest2 = std::max({(pb - pa).squaredNorm(), (pc - pb).squaredNorm(), (pa - pc).squaredNorm()});
    if (n.norm() <= 1e-9 * longest2) return;
    mesh.triangles.push_back({a, b, c});
  };
  for (std::uint32_t i = 0; i + 1 < us.size(); ++i) {
    for (std::uint32_t j = 0; j + 1 < nv; ++j) {
      const std::uint32_t a = i * nv + j;
      const std::uint32_t b = a + 1;
      const std::uint32_t c = a + nv + 1;
      const std::uint32_t d = a + nv;
      // a->b runs along v (right to left), b->c along u (tip to base): S_v x S_u faces the
      // adaxial side when the markers were taken on the front of the leaf.
      addIfNotDegenerate(a, b, c);
      addIfNotDegenerate(a, c, d);
      ++mesh.quads;
    }
  }
  setAreaWeightedNormals(mesh);
  return mesh;
}

void setAreaWeightedNormals(Mesh& mesh) {
  mesh.normals.assign(mesh.positions.size(), Eigen::Vector3d::Zero());
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const auto& t : mesh.triangles) {
    const Eigen::Vector3d n =
        (mesh.positions[t[1]] - mesh.positions[t[0]]).cross(mesh.positions[t[2]] - mesh.positions[t[0]]);
    for (std::uint32_t v : t) mesh.normals[v] += n;  // |n| is twice the area: area-weighted
    mean += n;
  }
  const Eigen::Vector3d fallback = safeNormal(mean, Eigen::Vector3d::UnitZ());
  for (auto& n : mesh.normals) n = safeNormal(n, fallback);
}

std::vector<double> detail::uniformVeinParameters(const Vein& vein, const MeshResolution& res) {
  const auto spans = static_cast<int>(vein.curve.dataParameters().size()) - 1;
  int segments = res.lateralSegments;
  if (vein.name == "midrib") segments = res.midribSegmentsPerRow * spans;
  if (vein.name == "contour") segments = res.contourSegmentsPerRow * spans;
  return subdivideSpans(vein.curve.dataParameters(), segments);
}

LeafMesh meshLeaf(const LeafModel& model, const MeshResolution& res) {
  LeafMesh out;
  for (const Vein& vein : model.veins) {
    const std::vector<double> ts = detail::uniformVeinParameters(vein, res);
    out.organs.push_back(
        {vein.name, OrganKind::Vein, meshVein(vein, ts, res.ringVertices, res.caps, res.capRings, out.warnings), 0});
  }
  if (!model.blade.controlNet.empty())  // a partial leaf (live preview) may have no blade yet
    out.organs.push_back(
        {"blade", OrganKind::Blade, meshBlade(model.blade, res.bladeSegmentsPerRow, res.bladeSegmentsAcross), 0});
  return out;
}

namespace {
MeshCounts countKind(const LeafMesh& mesh, OrganKind kind) {
  MeshCounts c;
  for (const Organ& o : mesh.organs) {
    if (o.kind != kind) continue;
    c.vertices += o.mesh.positions.size();
    c.quads += o.mesh.quads;
    c.triangles += o.mesh.triangles.size();
  }
  return c;
}
}  // namespace

MeshCounts countVeins(const LeafMesh& mesh) {
  return countKind(mesh, OrganKind::Vein);
}
MeshCounts countBlade(const LeafMesh& mesh) {
  return countKind(mesh, OrganKind::Blade);
}

}  // namespace leafdig::model
