#include "leafdig/acquisition/protocol/relocation.hpp"

#include <Eigen/SVD>
#include <cmath>

#include "words.hpp"

namespace leafdig::acquisition {

namespace {

using detail::mm;

Eigen::Vector3d centroid(const std::vector<Eigen::Vector3d>& points) {
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& p : points) c += p;
  return c / static_cast<double>(points.size());
}

// How far the points stand off the line that fits them best: the root of the centred set's
// second-largest principal variance (times the count), in mm.
double spreadOffLine(const std::vector<Eigen::Vector3d>& points) {
  const Eigen::Vector3d c = centroid(points);
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  for (const Eigen::Vector3d& p : points) scatter += (p - c) * (p - c).transpose();
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(scatter);
  return std::sqrt(std::max(0.0, svd.singularValues()(1)));
}

}  // namespace

RelocationFit fitRelocation(const std::vector<Eigen::Vector3d>& before, const std::vector<Eigen::Vector3d>& after,
                            const RelocationSettings& settings, const std::vector<int>& numbers) {
  RelocationFit fit;
  if (before.size() != after.size()) {
    fit.refusal = "the " + settings.noun + "s taken again (" + std::to_string(after.size()) +
                  ") are not those taken before (" + std::to_string(before.size()) + "): take each one again";
    return fit;
  }
  if (before.size() < 3) {
    fit.refusal = "take at least three of the " + settings.noun + "s again after moving the transmitter (" +
                  std::to_string(before.size()) + " so far)";
    return fit;
  }
  for (const auto& p : before)
    if (!p.allFinite()) fit.refusal = "a " + settings.noun + " is not a number: take it again";
  for (const auto& p : after)
    if (!p.allFinite()) fit.refusal = "a " + settings.noun + " is not a number: take it again";
  if (fit.refusal) return fit;
  const double spreadBefore = spreadOffLine(before);
  if (spreadBefore < settings.minSpreadMm || spreadOffLine(after) < settings.minSpreadMm) {
    fit.refusal = "the " + settings.noun + "s are nearly on one line (" + mm(spreadBefore) +
                  " off it): they cannot fix the transmitter's turn; " + settings.lineRemedy;
    return fit;
  }
  // Kabsch: the rotation R minimising Σ |R (a_i − ā) − (b_i − b̄)|² from the SVD of the
  // cross-covariance H = Σ (a_i − ā)(b_i − b̄)ᵀ, R = V diag(1, 1, d) Uᵀ with d = sign det(V Uᵀ).
  const Eigen::Vector3d a0 = centroid(after), b0 = centroid(before);
  Eigen::Matrix3d h = Eigen::Matrix3d::Zero();
  for (std::size_t i = 0; i < before.size(); ++i) h += (after[i] - a0) * (before[i] - b0).transpose();
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(h, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d d = Eigen::Matrix3d::Identity();
  d(2, 2) = (svd.matrixV() * svd.matrixU().transpose()).determinant() < 0 ? -1.0 : 1.0;
  const Eigen::Matrix3d r = svd.matrixV() * d * svd.matrixU().transpose();
  fit.newToOld.linear() = r;
  fit.newToOld.translation() = b0 - r * a0;

  double sum = 0.0;
  for (std::size_t i = 0; i < before.size(); ++i) {
    const double e = (fit.newToOld * after[i] - before[i]).norm();
    sum += e * e;
    if (e > fit.worstMm) {
      fit.worstMm = e;
      fit.worst = i;
    }
  }
  fit.rmsMm = std::sqrt(sum / static_cast<double>(before.size()));
  fit.worstLandmark = fit.worst < numbers.size() ? numbers[fit.worst] : static_cast<int>(fit.worst) + 1;
  if (fit.rmsMm > settings.toleranceMm)
    fit.refusal = "the " + settings.noun + "s do not agree after the move (RMS " + mm(fit.rmsMm) + ", more than " +
                  mm(settings.toleranceMm) + "): " + settings.noun + " " + std::to_string(fit.worstLandmark) + " is " +
                  mm(fit.worstMm) + " off — it moved, or was pressed elsewhere; take it again";
  return fit;
}

}  // namespace leafdig::acquisition
