// A calibration jig and its rigid fit (issue 50; docs/devices.md, "The field"): a board with
// divots at known positions, digitized point by point, tells how far the field the digitizer
// measures in is from true. The jig file, `leafdig.jig/1`:
//
//   {"format": "leafdig.jig/1", "units": "mm", "name": "…",
//    "points": [{"id": "A1", "point": [x, y, z]}, …]}     // in the jig's own frame
//
// fitJig places the jig on the points measured (in its points' order) by the rigid motion that
// fits them best in the least-squares sense (no scale: a field that stretches space shows as
// residuals), and gives each point's residual, the RMS, the largest and which point it is.
#pragma once

#include <Eigen/Geometry>
#include <string>
#include <vector>

namespace leafdig::model {

inline constexpr const char* kJigFormat = "leafdig.jig/1";

struct JigPoint {
  std::string id;           // unique, printable, at most 32 characters
  Eigen::Vector3d pointMm;  // in the jig's frame
};

struct Jig {
  std::string name;
  std::vector<JigPoint> points;  // at least 4, not all in one plane
};

// Throws InputError naming the source, where in it and what to fix (the format, units mm, cm
// or in, a unique id per point, at most 1000 points, a jig of at least four points that are
// not all in one plane: a flat jig cannot tell a field's height error from a tilt).
[[nodiscard]] Jig parseJig(const std::string& json, const std::string& source);
[[nodiscard]] Jig readJigFile(const std::string& path);

struct JigFit {
  Eigen::Isometry3d jigToDigitizer = Eigen::Isometry3d::Identity();
  std::vector<Eigen::Vector3d> residualsMm;  // measured − fitted, one per jig point, in its order
  double rmsMm = 0, maxMm = 0;
  std::string worstId;  // the point of the largest residual
};

// `measuredMm` holds one position per jig point, in the jig's order; InputError when the counts
// differ.
[[nodiscard]] JigFit fitJig(const Jig& jig, const std::vector<Eigen::Vector3d>& measuredMm);

}  // namespace leafdig::model
