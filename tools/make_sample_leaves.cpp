// Writes the three synthetic tobacco leaves of data/samples/ (see data/samples/README.md).
//
// Each leaf is an analytic shape: a half-width profile along the midrib (a beta-like bump
// widest at `widestAt`, plus wings that stay `wing` wide at the base), a midrib bent into
// an arc in the y-z plane, a blade cupped across and waved along the margin. Markers are
// placed as a technician would: N lateral-vein rows from tip to base, 7 markers per row
// right to left at 0, 1/3, 2/3 and 1 of the way from the midrib to the margin along a
// straight lateral vein at angle `veinAngle` to the midrib. Coordinates are rounded to
// 0.01 mm (a digitizer's resolution), thicknesses to 0.001 mm (a caliper's).
//
// Usage: make_sample_leaves OUTPUT_DIR
#include <Eigen/Geometry>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <numbers>

#include "leafdig/model/files.hpp"
#include "leafdig/model/leaf/markers_json.hpp"

namespace {

namespace m = leafdig::model;

struct LeafShape {
  std::string file;
  std::string id;
  std::string type;
  int position;  // leaf position on the stem, from the bottom
  int rows;
  double lengthMm;
  double halfWidthMm;
  double widestAt;  // 0 tip .. 1 base
  double wing;      // half-width at the base as a fraction of halfWidthMm
  double bendDeg;   // total turn of the midrib from base to tip
  double cupMm;     // rise of the margin above the midrib's plane at full width
  double waveMm;    // margin wave amplitude
  double veinAngleTipDeg;
  double veinAngleBaseDeg;
  bool perRowEdge;
};

double round(double v, double step) {
  return std::round(v / step) * step;
}

// Half-width at x in [0, 1] (0 = tip).
double halfWidth(const LeafShape& s, double x) {
  const double a = 1.4;
  const double b = a * (1.0 - s.widestAt) / s.widestAt;  // maximum of x^a (1-x)^b at widestAt
  auto bump = [&](double t) { return std::pow(t, a) * std::pow(1.0 - t, b); };
  x = std::clamp(x, 0.0, 1.0);
  return s.halfWidthMm * ((1.0 - s.wing) * bump(x) / bump(s.widestAt) + s.wing * std::pow(x, 3));
}

// The midrib bends in the y-z plane; s is the arc length from the tip.
Eigen::Vector3d midrib(const LeafShape& s, double arc) {
  const double kappa = (s.bendDeg * std::numbers::pi / 180.0) / s.lengthMm;
  if (kappa == 0.0) return {0.0, -arc, 0.0};
  // Leaving the tip along -Y and turning upwards: the base is higher than the tip (a
  // drooping leaf).
  return {0.0, -std::sin(kappa * arc) / kappa, (1.0 - std::cos(kappa * arc)) / kappa};
}

Eigen::Vector3d midribTangent(const LeafShape& s, double arc) {
  const double h = 1e-4;
  return (midrib(s, arc + h) - midrib(s, arc - h)).normalized();
}

// A point of the blade at arc length `arc` along the midrib and signed lateral offset x
// (+ is the right half, seen from the adaxial side with the tip up).
Eigen::Vector3d bladePoint(const LeafShape& s, double arc, double x) {
  const Eigen::Vector3d lateral = Eigen::Vector3d::UnitX();
  const Eigen::Vector3d tangent = midribTangent(s, arc);  // towards the base
  const Eigen::Vector3d normal = tangent.cross(lateral);  // adaxial
  const double rel = std::abs(x) / s.halfWidthMm;
  const double height =
      s.cupMm * rel * rel + s.waveMm * rel * rel * std::sin(2.0 * std::numbers::pi * arc / 90.0 + (x > 0 ? 0.0 : 1.3));
  return midrib(s, arc) + x * lateral + height * normal;
}

m::MarkerSet makeLeaf(const LeafShape& s) {
  m::MarkerSet set;
  set.leaf = {s.id, "P-demo", s.position, s.type, std::nullopt, std::nullopt, std::nullopt, std::nullopt};
  set.tipMm = midrib(s, 0.0).unaryExpr([](double v) { return round(v, 0.01); });
  set.edgeThicknessMm = 0.3;

  // Outline area of the flattened leaf: what a leaf area meter would report.
  double outline = 0.0;
  const int steps = 4000;
  for (int k = 0; k < steps; ++k) {
    outline += 2.0 * halfWidth(s, (k + 0.5) / steps) * s.lengthMm / steps;
  }
  set.leaf.measuredAreaMm2 = round(outline, 1.0);

  for (int i = 0; i < s.rows; ++i) {
    const double q = s.rows == 1 ? 0.5 : static_cast<double>(i) / (s.rows - 1);
    const double x = 0.07 + 0.93 * std::pow(q, 1.08);  // row position, 0 tip .. 1 base (the last row at the base)
    const double arc = x * s.lengthMm;
    const double angle = (s.veinAngleTipDeg + (s.veinAngleBaseDeg - s.veinAngleTipDeg) * q) * std::numbers::pi / 180;
    m::MarkerRow row;
    for (int side : {+1, -1}) {
      // Walk out along the lateral vein (towards the tip) until it meets the margin.
      const double asym = side > 0 ? 1.0 : 0.94;
      double lo = 0.0;
      double hi = arc / std::cos(angle);
      for (int it = 0; it < 80; ++it) {
        const double mid = 0.5 * (lo + hi);
        const double reach = mid * std::sin(angle);
        const double width = asym * halfWidth(s, (arc - mid * std::cos(angle)) / s.lengthMm);
        (reach < width ? lo : hi) = mid;
      }
      const double veinLength = lo;
      for (int k = 0; k <= 3; ++k) {
        const double f = k / 3.0;
        const double along = arc - f * veinLength * std::cos(angle);
        const double lateral = side * f * veinLength * std::sin(angle);
        const int column = side > 0 ? 3 - k : 3 + k;  // right: j = 4,3,2,1; left: 4,5,6,7
        row.pointsMm[column] = bladePoint(s, along, lateral).unaryExpr([](double v) { return round(v, 0.01); });
      }
    }
    row.midribThicknessMm = round(1.0 + 3.0 * std::pow(q, 0.9), 0.001);
    row.veinOriginThicknessMm = round(0.5 + 1.5 * std::sin(std::numbers::pi * (0.15 + 0.6 * q)), 0.001);
    if (s.perRowEdge) row.edgeThicknessMm = round(0.3 + 0.09 * std::sin(1.7 * i), 0.001);
    set.rows.push_back(row);
  }
  return set;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: make_sample_leaves OUTPUT_DIR\n";
    return 2;
  }
  const std::filesystem::path dir = argv[1];
  std::filesystem::create_directories(dir);
  const LeafShape shapes[] = {
      // Wide lower leaf with narrow wings.
      {"lower-leaf-n10.markers.json", "S-lower-10", "lower", 4, 10, 620, 165, 0.55, 0.05, 28, 22, 6, 52, 62, false},
      // Small upper leaf with wide wings.
      {"upper-small-leaf-n17.markers.json", "S-upper-17", "upper", 17, 17, 390, 85, 0.62, 0.32, 22, 10, 3, 48, 62,
       false},
      // Strongly curved upper leaf, per-row margin thickness.
      {"upper-curved-leaf-n14.markers.json", "S-curved-14", "upper", 15, 14, 460, 105, 0.5, 0.15, 105, 16, 4, 50, 62,
       true},
  };
  try {
    for (const LeafShape& s : shapes) {
      const auto path = dir / s.file;
      leafdig::model::writeFileAtomically(path, leafdig::model::markersToJson(makeLeaf(s)));
      std::cout << "wrote " << path.string() << "\n";
    }
  } catch (const std::exception& e) {
    std::cerr << "make_sample_leaves: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
