// A blade area's 95 % interval (issue 16): the digitizer's noise by Monte-Carlo draws, the
// rows' interpolation, and the margin between the markers (issue 26). How it is made and how
// often it holds the truth: docs/accuracy.md.
#pragma once

#include <cstdint>
#include <string>

#include "leafdig/model/leaf/blade.hpp"
#include "leafdig/model/leaf/markers.hpp"

namespace leafdig::model {

// The Polhemus FASTRAK's stated static accuracy, 0.03 in RMS for each of X, Y and Z.
inline constexpr double kFastrakSigmaMm = 0.762;

struct AreaUncertaintyOptions {
  double sigmaMm = kFastrakSigmaMm;  // per coordinate, the digitizer's stated accuracy
  int draws = 64;
  std::uint64_t seed = 1;
  BladeKind blade = BladeKind::Interp;
};

struct AreaUncertainty {
  double areaMm2 = 0.0;   // the blade area of the markers as captured
  double low95Mm2 = 0.0;  // the 95 % interval
  double high95Mm2 = 0.0;
  double noiseLowMm2 = 0.0;  // 2.5 % and 97.5 % quantiles of the Monte-Carlo areas
  double noiseHighMm2 = 0.0;
  double interpolationMm2 = 0.0;  // the row-drop interpolation estimate
  double systematicMm2 = 0.0;     // interp's measured under-estimate for this row count, upwards
  // The margin between the markers (issue 26): how much area teeth (or a scan's margin
  // detail) may hold beyond the smooth margin through the markers (upwards) and how much the
  // markers may stand on tooth tips (downwards). Zero when the serration is none or not declared.
  double marginHighMm2 = 0.0;
  double marginLowMm2 = 0.0;
  std::string margin;  // "declared: straight, teeth 3.0 mm deep", "a scan …", "none", "not declared"
  std::string note;    // what the interval leaves out, in words (e.g. undeclared teeth); empty when nothing
  double sigmaMm = 0.0;
  int draws = 0;
  [[nodiscard]] double halfWidthPercent() const { return 50.0 * (high95Mm2 - low95Mm2) / areaMm2; }
};

// Throws InputError for a sigma outside [0, 20] mm or fewer than 8 draws. The same markers,
// options and seed give the same interval on every machine.
[[nodiscard]] AreaUncertainty areaUncertainty(const MarkerSet& markers, const AreaUncertaintyOptions& options = {});

// The interpolation error estimate alone: |A(all rows) − A(every other row, first and last
// kept)|; 0 for fewer than 4 rows.
[[nodiscard]] double interpolationErrorEstimate(const MarkerSet& markers, BladeKind blade);
// The interp blade's under-estimate of the area with N rows that the accuracy study found
// 95 % of synthetic leaves within, as a fraction: 0.0034 + 0.62 / N².
[[nodiscard]] double systematicUnderestimate(int rows);

}  // namespace leafdig::model
