// Tip (pivot) calibration of a stylus (issue 50; docs/devices.md, "The stylus tip"): a digitizer
// reports its sensor, not the tip the technician presses on the leaf. Pivoting the stylus with its
// tip seated in one divot, every sample i gives the sensor's rotation R_i (its axes in the
// transmitter's frame) and position p_i, and the tip stays where it is:
//
//   p_i + R_i·t = d          t: the tip in the sensor's frame, d: the divot in the transmitter's
//
// three equations per sample in six unknowns, solved in the least-squares sense ([R_i  −I]·[t; d]
// = −p_i, by a QR decomposition). A sample whose residual |p_i + R_i·t − d| is over three times
// the fit's RMS (the tip slipped, the hand knocked the sensor) is left out and the rest fitted
// again, until none is; at least 20 samples must stay, turned at least 30° from each other about
// two axes (a stylus turned about its own axis, or hardly turned, cannot tell its tip's offset
// from the divot's place).
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <vector>

namespace leafdig::model {

struct PivotSample {
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();  // the sensor's axes in the transmitter's frame
  Eigen::Vector3d positionMm = Eigen::Vector3d::Zero();    // the sensor's origin in the transmitter's frame
};

inline constexpr std::size_t kPivotMinSamples = 20;
inline constexpr double kPivotMinSpreadDeg = 30.0;

struct PivotFit {
  Eigen::Vector3d tipMm = Eigen::Vector3d::Zero();    // t: the tip in the sensor's frame
  Eigen::Vector3d pivotMm = Eigen::Vector3d::Zero();  // d: the divot in the transmitter's frame
  double rmsMm = 0, maxMm = 0;                        // the residuals of the samples kept
  std::size_t samples = 0;                            // given
  std::vector<std::size_t> rejected;                  // left out by the 3σ rule, in sample order
  double spreadDeg = 0;      // the stylus' turn between the two samples of the kept ones furthest apart
  double tiltSpreadDeg = 0;  // the same about the axes across the stylus' (not its own turn)
};

// Throws InputError naming what to do: fewer than kPivotMinSamples samples (given, or left after
// the 3σ rule), a spread under kPivotMinSpreadDeg, a non-finite sample.
[[nodiscard]] PivotFit fitPivot(const std::vector<PivotSample>& samples);

}  // namespace leafdig::model
