// The truth file and the figures of synthetic leaves (docs/synthetic-leaves.md).
#include <algorithm>
#include <iomanip>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>

#include "json_text.hpp"
#include "leafdig/model/synth/synthetic_leaf.hpp"
#include "xml_text.hpp"

namespace leafdig::model {

namespace {

nlohmann::json point(const Eigen::Vector3d& p) {
  return nlohmann::json::array({p.x(), p.y(), p.z()});
}
nlohmann::json point(const Eigen::Vector2d& p) {
  return nlohmann::json::array({p.x(), p.y()});
}

}  // namespace

std::string truthToJson(const SyntheticLeaf& leaf, double noiseMm, std::uint64_t seed) {
  const SyntheticLeafSpec& s = leaf.spec();
  const OutlineSpec& o = s.outline;
  double estimate = 0.0;
  const double area = leaf.area(&estimate);
  nlohmann::json terms = nlohmann::json::array();
  for (const SineTerm& t : o.widthTerms)
    terms.push_back({{"amplitude", t.amplitude}, {"frequency", t.frequency}, {"phase_rad", t.phaseRad}});
  nlohmann::json doc;
  doc["format"] = "leafdig.truth/1";
  doc["units"] = "mm";
  doc["frame"] = "leaf";
  doc["leaf"] = {{"id", s.id}, {"plant", s.plant}, {"type", s.type}};
  doc["area_mm2"] = area;
  doc["area_relative_error"] = estimate;
  doc["flat_area_mm2"] = leaf.flatArea();
  doc["midrib_length_mm"] = leaf.midribLengthMm();
  doc["length_mm"] = o.lengthMm;
  doc["width_mm"] = leaf.widthMm();
  doc["noise_mm"] = noiseMm;
  doc["seed"] = seed;
  doc["spec"] = {{"shape", toString(o.shape)},
                 {"symmetry", o.symmetry ? nlohmann::json(*o.symmetry) : nlohmann::json(nullptr)},
                 {"width_terms", terms},
                 {"asymmetry", o.asymmetry},
                 {"tip_narrowing", o.tipNarrowing},
                 {"tip_extent", o.tipExtent},
                 {"base_narrowing", o.baseNarrowing},
                 {"base_extent", o.baseExtent},
                 {"serration", toString(o.serration)},
                 {"tooth_depth_mm", o.toothDepthMm},
                 {"teeth_per_side", o.teethPerSide},
                 {"tooth_direction", toString(o.toothDirection)},
                 {"droop_deg", s.bend.droopDeg},
                 {"cup_mm", s.bend.cupMm},
                 {"twist_deg", s.bend.twistDeg},
                 {"wave_mm", s.bend.waveMm},
                 {"wavelength_mm", s.bend.wavelengthMm},
                 {"rows", s.rows},
                 {"vein_angle_tip_deg", s.veinAngleTipDeg},
                 {"vein_angle_base_deg", s.veinAngleBaseDeg}};
  nlohmann::json outline = nlohmann::json::array();
  for (const Eigen::Vector2d& p : leaf.outline(512)) outline.push_back(point(p));
  doc["outline_flat"] = outline;
  nlohmann::json midrib = nlohmann::json::array();
  for (const Eigen::Vector3d& p : leaf.midrib()) midrib.push_back(point(p));
  doc["midrib"] = midrib;
  const MarkerSet exact = leaf.markers(0.0, seed);
  nlohmann::json rows = nlohmann::json::array();
  for (const MarkerRow& r : exact.rows) {
    nlohmann::json pts = nlohmann::json::array();
    for (const Eigen::Vector3d& p : r.pointsMm) pts.push_back(point(p));
    rows.push_back(pts);
  }
  doc["markers_exact"] = {{"tip", point(exact.tipMm)}, {"rows", rows}};
  nlohmann::json veins = nlohmann::json::array();
  for (const TruthVein& v : leaf.veins()) {
    nlohmann::json pts = nlohmann::json::array();
    for (const Eigen::Vector3d& p : v.points) pts.push_back(point(p));
    veins.push_back({{"row", v.row},
                     {"side", v.side > 0 ? "right" : "left"},
                     {"flat", {point(v.flatStart), point(v.flatEnd)}},
                     {"points", pts}});
  }
  doc["veins"] = veins;
  return detail::dumpFinite(doc, 1) + "\n";
}

FigurePanel figurePanel(const SyntheticLeaf& leaf, const std::string& caption) {
  FigurePanel p;
  p.caption = caption;
  p.outline = leaf.outline(600);
  for (const TruthVein& v : leaf.veins(2)) {
    p.veins.push_back({v.flatStart, v.flatEnd});
    for (int k = 1; k <= 3; ++k) p.markers.push_back(v.flatStart + (k / 3.0) * (v.flatEnd - v.flatStart));
    if (v.side > 0) p.markers.push_back(v.flatStart);
  }
  p.markers.push_back({0.0, leaf.spec().outline.lengthMm});
  p.veins.push_back({Eigen::Vector2d(0.0, 0.0), Eigen::Vector2d(0.0, leaf.spec().outline.lengthMm)});
  return p;
}

std::string figureSvg(const std::vector<FigurePanel>& panels, int columns) {
  const double cellW = 200.0, cellH = 260.0, pad = 14.0, caption = 22.0;
  const int cols = std::max(1, columns);
  const int rowsN =
      static_cast<int>((panels.size() + static_cast<std::size_t>(cols) - 1) / static_cast<std::size_t>(cols));
  // One scale for every panel, so sizes compare.
  double extent = 1e-9;
  for (const FigurePanel& p : panels) {
    double minX = std::numeric_limits<double>::max(), maxX = -minX, minY = minX, maxY = -minX;
    for (const Eigen::Vector2d& q : p.outline) {
      minX = std::min(minX, q.x());
      maxX = std::max(maxX, q.x());
      minY = std::min(minY, q.y());
      maxY = std::max(maxY, q.y());
    }
    extent = std::max({extent, (maxX - minX) / (cellW - 2 * pad), (maxY - minY) / (cellH - 2 * pad - caption)});
  }
  const double scale = 1.0 / extent;
  std::ostringstream out;
  out << std::fixed << std::setprecision(2);
  out << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << cellW * cols << "\" height=\"" << cellH * rowsN
      << "\" viewBox=\"0 0 " << cellW * cols << " " << cellH * rowsN << "\" font-family=\"sans-serif\">\n";
  out << "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  for (std::size_t i = 0; i < panels.size(); ++i) {
    const FigurePanel& p = panels[i];
    const double ox = cellW * static_cast<double>(i % static_cast<std::size_t>(cols)) + cellW / 2;
    const double oy = cellH * static_cast<double>(i / static_cast<std::size_t>(cols)) + cellH - pad - caption;
    const auto map = [&](const Eigen::Vector2d& q) {
      std::ostringstream s;
      s << std::fixed << std::setprecision(2) << ox + scale * q.x() << "," << oy - scale * q.y();
      return s.str();
    };
    out << "<g>\n<polygon fill=\"#cfe8b8\" stroke=\"#2f6b1f\" stroke-width=\"1\" points=\"";
    for (const Eigen::Vector2d& q : p.outline) out << map(q) << " ";
    out << "\"/>\n";
    for (const auto& v : p.veins) {
      const std::string a = map(v[0]), b = map(v[1]);
      const auto ca = a.find(','), cb = b.find(',');
      out << "<line x1=\"" << a.substr(0, ca) << "\" y1=\"" << a.substr(ca + 1) << "\" x2=\"" << b.substr(0, cb)
          << "\" y2=\"" << b.substr(cb + 1) << "\" stroke=\"#5b8f3a\" stroke-width=\"0.7\"/>\n";
    }
    for (const Eigen::Vector2d& m : p.markers) {
      const std::string a = map(m);
      const auto c = a.find(',');
      out << "<circle cx=\"" << a.substr(0, c) << "\" cy=\"" << a.substr(c + 1) << "\" r=\"1.6\" fill=\"#c0392b\"/>\n";
    }
    const std::string text = detail::xmlText(p.caption);
    out << "<text x=\"" << ox << "\" y=\"" << oy + pad + caption / 2 << "\" font-size=\"12\" text-anchor=\"middle\">"
        << text << "</text>\n</g>\n";
  }
  out << "</svg>\n";
  return out.str();
}

}  // namespace leafdig::model
