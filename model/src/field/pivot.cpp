#include "leafdig/model/field/pivot.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>

#include "leafdig/model/errors.hpp"

namespace leafdig::model {
namespace {

double angleDeg(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b) {
  const double c = std::clamp(((a.transpose() * b).trace() - 1.0) / 2.0, -1.0, 1.0);
  return std::acos(c) * 180.0 / std::numbers::pi;
}

// How far two orientations tilt the stylus' axis apart (degrees): the turn that is not about its
// own axis. The axis is the direction of t in the sensor's frame, so the tilt is measured after
// the fit.
double tiltDeg(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b, const Eigen::Vector3d& axis) {
  const Eigen::Vector3d u = (a * axis).normalized(), v = (b * axis).normalized();
  return std::acos(std::clamp(u.dot(v), -1.0, 1.0)) * 180.0 / std::numbers::pi;
}

struct Solved {
  Eigen::Vector3d t, d;
};

Solved solve(const std::vector<PivotSample>& s, const std::vector<std::size_t>& use) {
  Eigen::MatrixXd a(3 * use.size(), 6);
  Eigen::VectorXd b(3 * use.size());
  for (std::size_t k = 0; k < use.size(); ++k) {
    const PivotSample& x = s[use[k]];
    const auto r = static_cast<Eigen::Index>(3 * k);
    a.block<3, 3>(r, 0) = x.rotation;
    a.block<3, 3>(r, 3) = -Eigen::Matrix3d::Identity();
    b.segment<3>(r) = -x.positionMm;
  }
  const Eigen::VectorXd x = a.colPivHouseholderQr().solve(b);
  return {x.head<3>(), x.tail<3>()};
}

}  // namespace

PivotFit fitPivot(const std::vector<PivotSample>& samples) {
  const auto more = [](std::size_t n) {
    return "pivot the stylus with its tip in one divot until at least " + std::to_string(kPivotMinSamples) +
           " samples are taken (" + std::to_string(n) + " now), turning it about ±45° each way";
  };
  if (samples.size() < kPivotMinSamples)
    throw InputError("too few samples for a tip calibration: " + more(samples.size()));
  for (std::size_t i = 0; i < samples.size(); ++i)
    if (!samples[i].rotation.allFinite() || !samples[i].positionMm.allFinite() ||
        std::abs(samples[i].rotation.determinant() - 1.0) > 1e-3)
      throw InputError("sample " + std::to_string(i + 1) +
                       " of the tip calibration has no valid position or orientation: the digitizer must report "
                       "both (its output list with the Euler angles or the quaternion)");
  PivotFit fit;
  fit.samples = samples.size();
  std::vector<std::size_t> use(samples.size());
  for (std::size_t i = 0; i < use.size(); ++i) use[i] = i;
  std::vector<double> residual(samples.size());
  Solved x{};
  for (;;) {
    x = solve(samples, use);
    double sum = 0;
    for (std::size_t i = 0; i < samples.size(); ++i) {
      residual[i] = (samples[i].positionMm + samples[i].rotation * x.t - x.d).norm();
    }
    for (const std::size_t i : use) sum += residual[i] * residual[i];
    const double rms = std::sqrt(sum / static_cast<double>(use.size()));
    std::vector<std::size_t> kept;
    for (const std::size_t i : use)
      if (residual[i] <= 3.0 * rms) kept.push_back(i);
    if (kept.size() == use.size() || rms == 0.0) {
      fit.rmsMm = rms;
      break;
    }
    if (kept.size() < kPivotMinSamples)
      throw InputError("the tip slipped in too many samples (" + std::to_string(use.size() - kept.size()) +
                       " over three times the fit's RMS): " + more(kept.size()));
    use = kept;
  }
  fit.tipMm = x.t;
  fit.pivotMm = x.d;
  for (std::size_t i = 0, k = 0; i < samples.size(); ++i) {
    if (k < use.size() && use[k] == i) {
      ++k;
      fit.maxMm = std::max(fit.maxMm, residual[i]);
    } else {
      fit.rejected.push_back(i);
    }
  }
  const Eigen::Vector3d axis = x.t.norm() > 1e-9 ? Eigen::Vector3d(x.t) : Eigen::Vector3d::UnitZ();
  for (std::size_t i = 0; i < use.size(); ++i)
    for (std::size_t j = i + 1; j < use.size(); ++j) {
      fit.spreadDeg = std::max(fit.spreadDeg, angleDeg(samples[use[i]].rotation, samples[use[j]].rotation));
      fit.tiltSpreadDeg =
          std::max(fit.tiltSpreadDeg, tiltDeg(samples[use[i]].rotation, samples[use[j]].rotation, axis));
    }
  if (fit.tiltSpreadDeg < kPivotMinSpreadDeg) {
    char turned[32];
    std::snprintf(turned, sizeof turned, "%.0f", fit.tiltSpreadDeg);
    throw InputError(std::string("the stylus was tilted only ") + turned + "° between its samples (at least " +
                     std::to_string(static_cast<int>(kPivotMinSpreadDeg)) +
                     "° needed): pivot it about ±45° each way with its tip in the divot, not only about its own axis");
  }
  return fit;
}

}  // namespace leafdig::model
