#include "leafdig/model/metrics/area_interval.hpp"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>
#include <vector>

#include "draws.hpp"
#include "leafdig/model/errors.hpp"
#include "leafdig/model/leaf/leaf_model.hpp"
#include "leafdig/model/metrics/blade_area.hpp"

namespace leafdig::model {

namespace {

const Eigen::Vector3d kUp(0.0, 0.0, 1.0);

// The blade area of a marker set at a fixed resolution (per row span, across).
double bladeAreaAt(const MarkerSet& markers, BladeKind kind, int perRow, int across) {
  return bladeGridArea(buildBlade(markerGrid(markers), kind), perRow, across);
}

// Every other row, the first and the last always kept.
MarkerSet everyOtherRow(const MarkerSet& markers) {
  MarkerSet out = markers;
  out.rows.clear();
  const std::size_t n = markers.rows.size();
  for (std::size_t i = 0; i < n; ++i) {
    if (i % 2 == 0 || i + 1 == n) out.rows.push_back(markers.rows[i]);
  }
  return out;
}

double quantile(std::vector<double> values, double q) {
  std::sort(values.begin(), values.end());
  const double pos = q * static_cast<double>(values.size() - 1);
  const auto lo = static_cast<std::size_t>(std::floor(pos));
  const std::size_t hi = std::min(lo + 1, values.size() - 1);
  return values[lo] + (pos - static_cast<double>(lo)) * (values[hi] - values[lo]);
}

}  // namespace

double systematicUnderestimate(int rows) {
  const double n = std::max(2, rows);
  return (0.34 + 62.0 / (n * n)) / 100.0;
}

double interpolationErrorEstimate(const MarkerSet& markers, BladeKind blade) {
  if (markers.rows.size() < 4) return 0.0;
  const LeafModel full = buildLeafModel(markers, {blade, nullptr});
  const BladeAreaEstimate est = convergedBladeArea(full.blade, kUp);
  const MarkerSet half = everyOtherRow(markers);
  // The half-row blade at the same sampling density per millimetre of leaf: twice the
  // segments per (now twice as long) row span.
  const double halfArea = bladeAreaAt(half, blade, 2 * est.segmentsPerRow, est.segmentsAcross);
  return std::abs(est.areaMm2 - halfArea);
}

namespace {

// The margin's length through the markers (tip to each row's end, both sides) and the widest
// row's width.
std::pair<double, double> marginLengthAndWidth(const MarkerSet& markers) {
  double width = 0.0;
  for (const MarkerRow& row : markers.rows)
    width = std::max(width, (row.pointsMm[0] - row.pointsMm[kMarkersPerRow - 1]).norm());
  return {marginSpacingMm(markers) * 2.0 * static_cast<double>(markers.rows.size()), width};
}

std::string millimetres(double v) {
  std::ostringstream out;
  out << std::fixed << std::setprecision(v < 1 ? 2 : 1) << v;
  return out.str();
}

void addMarginTerm(const MarkerSet& markers, AreaUncertainty& u) {
  const auto [length, width] = marginLengthAndWidth(markers);
  const LeafInfo& leaf = markers.leaf;
  if (leaf.marginFromScan && !leaf.marginFromScan->empty()) {
    // Measured: the markers may stand anywhere between the margin's sinuses and its tips.
    const MarginSample at = marginAt(*leaf.marginFromScan, marginSpacingMm(markers));
    u.marginHighMm2 = length * at.insideMm;
    u.marginLowMm2 = length * at.outsideMm;
    u.margin = "a scan of the leaf: its margin runs " + millimetres(at.outsideMm) + " mm outside and " +
               millimetres(at.insideMm) + " mm inside a smooth margin at the markers' spacing (" +
               millimetres(at.spacingMm) + " mm)";
    return;
  }
  if (!leaf.serration) {
    u.margin = "not declared";
    u.note =
        "the leaf's serration was not declared: teeth between the markers are not in this interval (declare it, "
        "none if the margin is entire, or give a scan of the leaf)";
    return;
  }
  if (*leaf.serration == Serration::None) {
    u.margin = "none (an entire margin)";
    return;
  }
  // Declared teeth of depth D along the margin's length: the markers sample the profile at
  // unknown phases, so the model's margin lies anywhere from the sinuses (0) to the tips
  // (max) while the truth holds the profile's mean: the interval reaches up by length × D ×
  // mean and down by length × D × (max − mean) (docs/accuracy.md, "Toothed margins").
  const double depth = leaf.toothDepthMm.value_or(kDefaultToothDepthFraction * width);
  const ToothSpread spread = toothSpread(*leaf.serration);
  u.marginHighMm2 = length * depth * spread.mean;
  u.marginLowMm2 = length * depth * (spread.max - spread.mean);
  u.margin = std::string("declared: ") + toString(*leaf.serration) + " teeth " + millimetres(depth) + " mm deep" +
             (leaf.toothDepthMm ? "" : " (1.5 % of the width: the depth was not given)");
}

}  // namespace
AreaUncertainty areaUncertainty(const MarkerSet& markers, const AreaUncertaintyOptions& options) {
  if (!(options.sigmaMm >= 0.0 && options.sigmaMm <= 20.0)) {
    throw InputError("the digitizer accuracy (sigma) must be between 0 and 20 mm");
  }
  if (options.draws < 8) throw InputError("the area uncertainty needs at least 8 Monte-Carlo draws");
  const LeafModel model = buildLeafModel(markers, {options.blade, nullptr});
  const BladeAreaEstimate est = convergedBladeArea(model.blade, kUp);
  AreaUncertainty u;
  u.areaMm2 = est.areaMm2;
  u.sigmaMm = options.sigmaMm;
  u.draws = options.draws;
  std::vector<double> deltas;
  deltas.reserve(static_cast<std::size_t>(options.draws));
  // The nominal at the draws' resolution, so the interval holds the spread alone.
  const double nominal = bladeAreaAt(markers, options.blade, est.segmentsPerRow, est.segmentsAcross);
  detail::Draws draws(options.seed, 0x75e7);
  for (int k = 0; k < options.draws; ++k) {
    MarkerSet noisy = markers;
    for (MarkerRow& row : noisy.rows) {
      for (Eigen::Vector3d& p : row.pointsMm) {
        for (int c = 0; c < 3; ++c) p[c] += options.sigmaMm * draws.gaussian();
      }
    }
    for (int c = 0; c < 3; ++c) noisy.tipMm[c] += options.sigmaMm * draws.gaussian();
    deltas.push_back(bladeAreaAt(noisy, options.blade, est.segmentsPerRow, est.segmentsAcross) - nominal);
  }
  // The basic (reflected) bootstrap interval: noise on the markers biases the area upwards
  // (a rougher surface is larger), and the draws, noisier still, show by how much; the
  // interval reflects their spread about the captured area and so removes that bias.
  u.noiseLowMm2 = u.areaMm2 - quantile(deltas, 0.975);
  u.noiseHighMm2 = u.areaMm2 - quantile(deltas, 0.025);
  u.interpolationMm2 = interpolationErrorEstimate(markers, options.blade);
  // Rows cost area on one side: the blade's margin is a spline through the row ends, and the
  // lobes below the last row's veins at the base are not sampled at all. For interp the
  // accuracy study measured the 95th percentile of that under-estimate as 0.34 % + 62 % / N²
  // over five shapes and four lengths (docs/accuracy.md); the interval reaches up by the
  // larger of it and the row-drop estimate (every blade kind loses area to its rows, none
  // gains it: the interval is not widened downwards).
  u.systematicMm2 = options.blade == BladeKind::Interp
                        ? systematicUnderestimate(static_cast<int>(markers.rows.size())) * u.areaMm2
                        : 0.0;
  addMarginTerm(markers, u);
  u.low95Mm2 = std::max(0.0, u.noiseLowMm2 - u.marginLowMm2);  // an area is never negative
  u.high95Mm2 = u.noiseHighMm2 + std::max(u.interpolationMm2, u.systematicMm2) + u.marginHighMm2;
  // An interval holds its value, ends in order: a blade so thin that the draws' bias exceeds
  // it (the reflected bootstrap's ends can then cross) is widened to hold the captured area.
  u.low95Mm2 = std::min(u.low95Mm2, std::max(0.0, u.areaMm2));
  u.high95Mm2 = std::max(u.high95Mm2, u.areaMm2);
  if (!(0.0 <= u.low95Mm2 && u.low95Mm2 <= u.areaMm2 && u.areaMm2 <= u.high95Mm2))
    throw InputError("the leaf's area interval cannot be made (area " + std::to_string(u.areaMm2) +
                     " mm²): check the markers");
  return u;
}

}  // namespace leafdig::model
