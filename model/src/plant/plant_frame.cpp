#include "leafdig/model/plant/plant_frame.hpp"

#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>

#include "leafdig/model/errors.hpp"

namespace leafdig::model {

namespace {

constexpr double kPi = std::numbers::pi;

std::string mm(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.1f mm", v);
  return b;
}

std::string nth(std::size_t i) {
  return "landmark " + std::to_string(i + 1);
}

}  // namespace

LandmarkPlane landmarkPlane(const std::vector<Eigen::Vector3d>& landmarks) {
  const std::size_t n = landmarks.size();
  if (n < 3)
    throw InputError("a plant frame needs at least three landmarks on the pot rim (or a board), " + std::to_string(n) +
                     " given: digitize " + std::to_string(3 - n) + " more");
  for (const auto& p : landmarks)
    if (!p.allFinite()) throw InputError("a landmark is not a finite point: digitize it again");
  double spread = 0.0;
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = i + 1; j < n; ++j) {
      const double d = (landmarks[i] - landmarks[j]).norm();
      if (d < kLandmarkMinApartMm)
        throw InputError(nth(j) + " is " + mm(d) + " from " + nth(i) +
                         ": the same point pressed twice? Take each landmark at its own place on the rim");
      spread = std::max(spread, d);
    }
  if (spread < kLandmarkMinSpreadMm)
    throw InputError("the landmarks are at most " + mm(spread) + " apart: take them at least " +
                     mm(kLandmarkMinSpreadMm) + " apart around the pot rim");
  LandmarkPlane plane;
  for (const auto& p : landmarks) plane.centroid += p / static_cast<double>(n);
  Eigen::MatrixXd centred(static_cast<Eigen::Index>(n), 3);
  for (std::size_t i = 0; i < n; ++i)
    centred.row(static_cast<Eigen::Index>(i)) = (landmarks[i] - plane.centroid).transpose();
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(centred, Eigen::ComputeThinV);
  const Eigen::Vector3d line = svd.matrixV().col(0);
  plane.normal = svd.matrixV().col(2);
  // Nearly collinear: every landmark close to the line through their centroid.
  double offLine = 0.0;
  std::size_t farthest = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d d = landmarks[i] - plane.centroid;
    const double off = (d - d.dot(line) * line).norm();
    if (off > offLine) {
      offLine = off;
      farthest = i;
    }
  }
  if (offLine < kLandmarkMinOffLineMm)
    throw InputError("the landmarks lie nearly on one line (" + nth(farthest) + ", the farthest, is " + mm(offLine) +
                     " off it), so they do not fix a plane: take them around the pot rim, not along one edge");
  double sum = 0.0;
  for (const auto& p : landmarks) sum += std::pow((p - plane.centroid).dot(plane.normal), 2);
  plane.flatnessMm = std::sqrt(sum / static_cast<double>(n));
  return plane;
}

PlantFrame plantFrameFromLandmarks(const std::vector<Eigen::Vector3d>& landmarks, const Eigen::Vector3d& collar,
                                   const Eigen::Vector3d& up) {
  const LandmarkPlane plane = landmarkPlane(landmarks);
  if (!collar.allFinite()) throw InputError("the collar is not a finite point: digitize it again");
  Eigen::Vector3d normal = plane.normal;
  const double side = normal.dot(up);
  if (!up.allFinite() || std::abs(side) < 1e-9 * std::max(1.0, up.norm()))
    throw InputError(
        "the direction the stem grows to lies in the landmarks' plane: is the stem's first node above "
        "the pot rim?");
  if (side < 0) normal = -normal;
  const Eigen::Vector3d toFirst = landmarks[0] - collar;
  Eigen::Vector3d x = toFirst - toFirst.dot(normal) * normal;
  if (x.norm() < 1.0)
    throw InputError("landmark 1 is straight above or below the collar (" + mm(x.norm()) +
                     " off its vertical): take landmark 1 on the rim, away from the stem");
  x.normalize();
  const Eigen::Vector3d y = normal.cross(x);
  Eigen::Matrix3d axes;  // columns: the plant frame's axes in the digitizer's frame
  axes << x, y, normal;
  PlantFrame frame;
  frame.fromDigitizer.linear() = axes.transpose();
  frame.fromDigitizer.translation() = -(axes.transpose() * collar);
  frame.flatnessMm = plane.flatnessMm;
  return frame;
}

double azimuthDeg(const Eigen::Vector3d& d) {
  return std::fmod(std::atan2(d.y(), d.x()) * 180.0 / kPi + 360.0, 360.0);
}

double inclinationDeg(const Eigen::Vector3d& d) {
  return std::acos(std::clamp(d.normalized().z(), -1.0, 1.0)) * 180.0 / kPi;
}

double divergenceDeg(double from, double to) {
  const double d = std::fmod(to - from, 360.0);
  return d < 0 ? d + 360.0 : d;
}

LeafPose leafPose(const Eigen::Vector3d& base, const Eigen::Vector3d& tip, const std::optional<Eigen::Vector3d>& side) {
  const Eigen::Vector3d chord = tip - base;
  LeafPose pose;
  pose.lengthMm = chord.norm();
  if (!(pose.lengthMm >= 1.0))
    throw InputError("the leaf's base and tip are " + mm(pose.lengthMm) +
                     " apart: touch the base where the blade joins the petiole, then the tip");
  pose.azimuthDeg = azimuthDeg(chord);
  pose.inclinationDeg = inclinationDeg(chord);
  if (!side) return pose;
  const Eigen::Vector3d a = chord / pose.lengthMm;
  const Eigen::Vector3d s = *side - base;
  const Eigen::Vector3d across = s - s.dot(a) * a;
  const double half = across.norm();
  if (!(half >= 1.0))
    throw InputError("the margin point is " + mm(half) +
                     " from the midrib's chord: touch the margin where the leaf is widest");
  pose.widthMm = 2.0 * half;
  // Roll: the width line against the horizontal across the chord (a vertical chord has no
  // horizontal across it: +X is taken instead), folded to (-90, 90] since either margin may
  // be the one digitized.
  Eigen::Vector3d level = a.cross(Eigen::Vector3d::UnitZ());
  if (level.norm() < 1e-9) level = Eigen::Vector3d::UnitX() - a.x() * a;
  level.normalize();
  const Eigen::Vector3d lift = a.cross(level);
  double roll = std::atan2(across.dot(lift), across.dot(level)) * 180.0 / kPi;
  if (roll > 90.0) roll -= 180.0;
  if (roll <= -90.0) roll += 180.0;
  pose.rollDeg = roll;
  return pose;
}

}  // namespace leafdig::model
