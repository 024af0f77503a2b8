// The field check's error map (correction.hpp, fieldErrorMapSvg): plain SVG written by hand, as
// the study's charts and the flat leaf's figure are — one figure is not worth a plotting library.
#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>

#include "leafdig/model/field/correction.hpp"
#include "xml_text.hpp"

namespace leafdig::model {
namespace {

constexpr double kPanel = 360.0, kPad = 30.0, kTop = 56.0;

using detail::xmlText;

// Green within half the tolerance, amber within it, red beyond.
const char* colourOf(double mm, double tolerance) {
  if (mm <= tolerance / 2) return "#1a9850";
  if (mm <= tolerance) return "#f39c12";
  return "#d73027";
}

struct Panel {
  int u, v;  // the axes drawn across and up
  std::string title;
  double x0;
  bool labels;  // the divots' ids (from the side they would stand on each other)
};

}  // namespace

FieldMapLayout fieldErrorMapLayout(const FieldMapInput& in) {
  const Jig& jig = *in.jig;
  const JigFit& fit = *in.fit;
  std::vector<Eigen::Vector3d> at;  // where the jig says each divot is, in the digitizer's frame
  for (const JigPoint& p : jig.points) at.push_back(fit.jigToDigitizer * p.pointMm);
  Eigen::Vector3d lo = at.front(), hi = at.front();
  for (const auto& p : at) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const double extent = std::max((hi - lo).maxCoeff(), 1.0);
  const double scale = (kPanel - 2 * kPad) / extent;  // px per mm
  // Arrows drawn so the largest is a tenth of the view (at least 1×: never shrunk).
  const double exaggeration = fit.maxMm > 0 ? std::max(1.0, extent / 10 / fit.maxMm) : 1.0;
  const std::vector<Panel> panels = {{0, 1, "from above (x across, y up)", 0, true},
                                     {0, 2, "from the side (x across, z up)", kPanel + 20, false}};
  FieldMapLayout out;
  out.width = 2 * kPanel + 20;
  out.height = kTop + kPanel + 70;
  out.title = in.title;
  std::ostringstream line;
  line << std::fixed << std::setprecision(2) << "RMS " << fit.rmsMm << " mm, largest " << fit.maxMm << " mm at "
       << fit.worstId << "; tolerance " << in.toleranceMm << " mm RMS: " << in.verdict << ". Arrows ×"
       << std::setprecision(0) << exaggeration << '.';
  out.summary = line.str();
  for (const Panel& p : panels) {
    FieldMapPanel panel{p.x0, kTop, kPanel, p.title, {}};
    // The points centred in the panel.
    const double midX = p.x0 + kPanel / 2, midY = kTop + kPanel / 2 + 8;
    const double cu = (lo[p.u] + hi[p.u]) / 2, cv = (lo[p.v] + hi[p.v]) / 2;
    const auto px = [&](const Eigen::Vector3d& q) {
      return std::pair{midX + (q[p.u] - cu) * scale, midY - (q[p.v] - cv) * scale};
    };
    for (std::size_t i = 0; i < at.size(); ++i) {
      const Eigen::Vector3d& r = fit.residualsMm[i];
      const auto [x, y] = px(at[i]);
      const auto [tx, ty] = px(at[i] + r * exaggeration);
      panel.arrows.push_back({x, y, tx, ty, colourOf(r.norm(), in.toleranceMm), p.labels ? jig.points[i].id : ""});
    }
    out.panels.push_back(std::move(panel));
  }
  // The legend: the three colours and a scale bar of 100 mm.
  out.legendY = kTop + kPanel + 24;
  std::ostringstream half, tol;
  half << std::setprecision(2) << in.toleranceMm / 2;
  tol << std::setprecision(2) << in.toleranceMm;
  out.legend = {{"#1a9850", "≤ " + half.str() + " mm"},
                {"#f39c12", "≤ " + tol.str() + " mm"},
                {"#d73027", "> " + tol.str() + " mm"}};
  out.scaleBarPx = 100 * scale;
  return out;
}

std::string fieldErrorMapSvg(const FieldMapInput& in) {
  const FieldMapLayout map = fieldErrorMapLayout(in);
  std::ostringstream svg;
  svg << std::fixed << std::setprecision(1);
  svg << R"(<svg xmlns="http://www.w3.org/2000/svg" width=")" << map.width << R"(" height=")" << map.height
      << R"(" viewBox="0 0 )" << map.width << ' ' << map.height << R"(" font-family="sans-serif" font-size="12">)"
      << '\n';
  svg << R"(<rect width="100%" height="100%" fill="white"/>)" << '\n';
  svg << R"(<defs><marker id="head" markerUnits="userSpaceOnUse" markerWidth="7" markerHeight="7" refX="6" refY="3.5" orient="auto">)"
      << R"(<path d="M0,0 L7,3.5 L0,7 z" fill="context-stroke"/></marker></defs>)" << '\n';
  svg << R"(<text x="10" y="20" font-size="15" font-weight="bold">)" << xmlText(map.title) << "</text>\n";
  svg << R"(<text x="10" y="40">)" << xmlText(map.summary) << "</text>\n";
  for (const FieldMapPanel& p : map.panels) {
    svg << R"(<rect x=")" << p.x0 << R"(" y=")" << p.y0 << R"(" width=")" << p.size << R"(" height=")" << p.size
        << R"(" fill="none" stroke="#999"/>)" << '\n';
    svg << R"(<text x=")" << p.x0 + 6 << R"(" y=")" << p.y0 + 16 << R"(">)" << xmlText(p.title) << "</text>\n";
    for (const FieldMapArrow& a : p.arrows) {
      svg << R"(<circle cx=")" << a.x << R"(" cy=")" << a.y << R"(" r="2.5" fill=")" << a.colour << R"("/>)";
      svg << R"(<line x1=")" << a.x << R"(" y1=")" << a.y << R"(" x2=")" << a.tipX << R"(" y2=")" << a.tipY
          << R"(" stroke=")" << a.colour << R"svg(" stroke-width="1.6" marker-end="url(#head)"/>)svg";
      if (!a.label.empty())
        svg << R"(<text x=")" << a.x + 4 << R"(" y=")" << a.y - 4 << R"(" font-size="9" fill="#555">)"
            << xmlText(a.label) << "</text>";
      svg << '\n';
    }
  }
  const double ly = map.legendY;
  double lx = 10;
  for (const auto& [colour, words] : map.legend) {
    svg << R"(<rect x=")" << lx << R"(" y=")" << ly - 9 << R"(" width="12" height="12" fill=")" << colour << R"("/>)";
    svg << R"(<text x=")" << lx + 16 << R"(" y=")" << ly + 1 << R"(">)" << xmlText(words) << "</text>\n";
    lx += 110;
  }
  svg << R"(<line x1=")" << lx + 10 << R"(" y1=")" << ly - 3 << R"(" x2=")" << lx + 10 + map.scaleBarPx << R"(" y2=")"
      << ly - 3 << R"(" stroke="black" stroke-width="2"/>)";
  svg << R"(<text x=")" << lx + 16 + map.scaleBarPx << R"(" y=")" << ly + 1 << R"(">100 mm (positions)</text>)" << '\n';
  svg << R"(<text x="10" y=")" << ly + 24
      << R"(" fill="#555">Each arrow runs from where the jig puts a divot to where the digitizer reported it.</text>)"
      << '\n';
  svg << "</svg>\n";
  return svg.str();
}

}  // namespace leafdig::model
