// docs/leaf2d.svg: the flat leaf with its sections, the two curls seen obliquely, and the
// margin profiles with the seed's five points. Plain SVG written by hand (as the study's
// charts): no plotting library in Debian's C++ set is worth a dependency for one figure.
#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>

#include "leafdig/model/leaf2d/leaf2d.hpp"

namespace leafdig::model {

namespace {

constexpr double kPanel = 300.0;
constexpr double kPad = 16.0;

struct View {
  double scale;
  Eigen::Vector2d offset;
};

View fit(const std::vector<Eigen::Vector2d>& pts, double x0) {
  Eigen::Vector2d lo = pts.front();
  Eigen::Vector2d hi = lo;
  for (const auto& p : pts) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const double size = kPanel - 2 * kPad;
  const double scale = size / std::max({hi.x() - lo.x(), hi.y() - lo.y(), 1e-9});
  const Eigen::Vector2d centre = (lo + hi) / 2;
  return {scale, Eigen::Vector2d(x0 + kPanel / 2 - scale * centre.x(), 30 + kPanel / 2 + scale * centre.y())};
}

std::string xy(const View& v, const Eigen::Vector2d& p) {
  std::ostringstream out;
  out << std::fixed << std::setprecision(1) << v.offset.x() + v.scale * p.x() << "," << v.offset.y() - v.scale * p.y();
  return out.str();
}

// Oblique view: turned by `azimuth` about Z, seen from `elevation` above the horizon.
Eigen::Vector3d project(const Eigen::Vector3d& p, double azimuth, double elevation) {
  const double c = std::cos(azimuth);
  const double s = std::sin(azimuth);
  const Eigen::Vector3d r(c * p.x() - s * p.y(), s * p.x() + c * p.y(), p.z());
  // screen x, screen y, depth (larger is farther)
  return {r.x(), r.y() * std::sin(elevation) + r.z() * std::cos(elevation),
          r.y() * std::cos(elevation) - r.z() * std::sin(elevation)};
}

void shadedPanel(std::ostringstream& svg, const Leaf2dModel& leaf, double x0, const std::string& title) {
  constexpr double kAzimuth = -0.6;
  constexpr double kElevation = 0.45;
  std::vector<Eigen::Vector3d> q;
  std::vector<Eigen::Vector2d> flat;
  for (const auto& p : leaf.mesh.positions) {
    q.push_back(project(p, kAzimuth, kElevation));
    flat.emplace_back(q.back().x(), q.back().y());
  }
  const View v = fit(flat, x0);
  std::vector<std::size_t> order(leaf.mesh.triangles.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  const auto depth = [&](std::size_t i) {
    const auto& t = leaf.mesh.triangles[i];
    return q[t[0]].z() + q[t[1]].z() + q[t[2]].z();
  };
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return depth(a) > depth(b); });
  const Eigen::Vector3d light = Eigen::Vector3d(-0.4, -0.5, 1.0).normalized();
  for (std::size_t i : order) {
    const auto& t = leaf.mesh.triangles[i];
    const Eigen::Vector3d n = (leaf.mesh.positions[t[1]] - leaf.mesh.positions[t[0]])
                                  .cross(leaf.mesh.positions[t[2]] - leaf.mesh.positions[t[0]])
                                  .normalized();
    const double s = 0.35 + 0.65 * std::abs(n.dot(light));
    svg << "<polygon points=\"" << xy(v, flat[t[0]]) << " " << xy(v, flat[t[1]]) << " " << xy(v, flat[t[2]])
        << "\" fill=\"rgb(" << static_cast<int>(50 * s) << "," << static_cast<int>(95 + 120 * s) << ","
        << static_cast<int>(40 * s) << ")\" stroke=\"rgb(20,60,20)\" stroke-width=\"0.25\"/>\n";
  }
  svg << "<text x=\"" << x0 + kPanel / 2 << "\" y=\"20\" text-anchor=\"middle\">" << title << "</text>\n";
}

}  // namespace

std::string leaf2dFigureSvg(const Outline2d& outline, double amplitudeMm) {
  Leaf2dOptions coarse;
  coarse.rows = 14;
  coarse.segmentsPerRow = 2;
  coarse.segmentsAcross = 12;
  coarse.amplitudeMm = amplitudeMm;
  coarse.curl = CurlKind::None;
  const Leaf2dModel flat = buildLeaf2d(outline, coarse);
  coarse.curl = CurlKind::Parabola;
  const Leaf2dModel parabola = buildLeaf2d(outline, coarse);
  coarse.curl = CurlKind::Sine;
  const Leaf2dModel sine = buildLeaf2d(outline, coarse);

  std::ostringstream svg;
  svg << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << 4 * kPanel << "\" height=\"" << kPanel + 40
      << "\" font-family=\"DejaVu Sans, sans-serif\" font-size=\"13\">\n<rect width=\"100%\" height=\"100%\" "
         "fill=\"white\"/>\n";
  // Panel 1: the outline in the leaf frame, the flat mesh's sections.
  {
    const Eigen::Vector2d axis = (flat.tipMm - flat.baseMm).normalized();
    const Eigen::Vector2d right(axis.y(), -axis.x());
    std::vector<Eigen::Vector2d> local;
    for (const auto& p : outline.pointsMm)
      local.emplace_back((p - flat.baseMm).dot(right), (p - flat.baseMm).dot(axis));
    const View v = fit(local, 0);
    for (const auto& t : flat.mesh.triangles) {
      svg << "<polygon points=\"";
      for (std::uint32_t k : t) {
        const Eigen::Vector3d& p = flat.mesh.positions[k];
        svg << xy(v, Eigen::Vector2d(p.x() / flat.inPlaneScale, p.y() / flat.inPlaneScale)) << " ";
      }
      svg << "\" fill=\"rgb(200,230,190)\" stroke=\"rgb(90,150,90)\" stroke-width=\"0.4\"/>\n";
    }
    svg << "<polygon points=\"";
    for (const auto& p : local) svg << xy(v, p) << " ";
    svg << "\" fill=\"none\" stroke=\"black\" stroke-width=\"1\"/>\n";
    svg << "<circle cx=\"" << v.offset.x() << "\" cy=\"" << v.offset.y() << "\" r=\"3\" fill=\"red\"/>\n";
    svg << "<text x=\"" << kPanel / 2 << "\" y=\"20\" text-anchor=\"middle\">"
        << (flat.trimmedToOutline ? "outline, flat leaf trimmed to it (base red)"
                                  : "outline, flat bicubic leaf (base red)")
        << "</text>\n";
  }
  shadedPanel(svg, parabola, kPanel, "parabola-like curl");
  shadedPanel(svg, sine, 2 * kPanel, "sine-like curl");
  // Panel 4: the margin profiles h(t) and the seed's five points.
  {
    const double x0 = 3 * kPanel + 40;
    const double w = kPanel - 60;
    const double y0 = 30 + kPanel - 50;
    const double h = kPanel - 130;
    svg << "<line x1=\"" << x0 << "\" y1=\"" << y0 << "\" x2=\"" << x0 + w << "\" y2=\"" << y0
        << "\" stroke=\"black\"/>\n<line x1=\"" << x0 << "\" y1=\"" << y0 << "\" x2=\"" << x0 << "\" y2=\"" << y0 - h
        << "\" stroke=\"black\"/>\n";
    const std::pair<CurlKind, const char*> curves[] = {{CurlKind::Parabola, "rgb(30,120,30)"},
                                                       {CurlKind::Sine, "rgb(170,60,20)"}};
    for (const auto& [kind, colour] : curves) {
      svg << "<polyline fill=\"none\" stroke=\"" << colour << "\" stroke-width=\"1.5\" points=\"";
      for (int i = 0; i <= 100; ++i) {
        svg << std::fixed << std::setprecision(1) << x0 + w * i / 100.0 << "," << y0 - h * curlHeight(kind, i / 100.0)
            << " ";
      }
      svg << "\"/>\n";
      const std::array<double, 5> f = curlFeatureHeights(kind);
      for (int i = 0; i < 5; ++i) {
        svg << "<circle cx=\"" << x0 + w * i / 4.0 << "\" cy=\"" << y0 - h * f[static_cast<std::size_t>(i)]
            << "\" r=\"3.5\" fill=\"" << colour << "\"/>\n";
      }
    }
    svg << "<text x=\"" << x0 + w / 2 << "\" y=\"20\" text-anchor=\"middle\">margin height / A</text>\n"
        << "<text x=\"" << x0 << "\" y=\"" << y0 + 18 << "\">base</text><text x=\"" << x0 + w << "\" y=\"" << y0 + 18
        << "\" text-anchor=\"end\">tip</text><text x=\"" << x0 + w / 2 << "\" y=\"" << y0 + 18
        << "\" text-anchor=\"middle\">t (arc length)</text>\n"
        << "<text x=\"" << x0 << "\" y=\"44\" fill=\"rgb(30,120,30)\">parabola-like: 0, .75, 1, .75, 0</text>\n"
        << "<text x=\"" << x0 << "\" y=\"62\" fill=\"rgb(170,60,20)\">sine-like: 0, 1, 0, 1, 0</text>\n";
  }
  svg << "</svg>\n";
  return svg.str();
}

}  // namespace leafdig::model
