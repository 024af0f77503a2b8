// The plant frame from landmarks and the collar, under random transmitter poses, its refusals
// in words, and the angles of a leaf measured in it.
#include "leafdig/model/plant/plant_frame.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>

#include "leafdig/model/errors.hpp"

using namespace leafdig::model;
using Eigen::Vector3d;

namespace {

constexpr double kPi = 3.14159265358979323846;

Vector3d onRim(double deg, double radius = 110.0, double height = 25.0) {
  return {radius * std::cos(deg * kPi / 180), radius * std::sin(deg * kPi / 180), height};
}

// A random pose of the transmitter: where the plant frame's points are in the digitizer's.
Eigen::Isometry3d randomPose(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const Eigen::Quaterniond q = Eigen::Quaterniond(u(rng), u(rng), u(rng), u(rng)).normalized();
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() = q.toRotationMatrix();
  t.translation() = Vector3d(400 * u(rng), 400 * u(rng), 400 * u(rng));
  return t;
}

std::string refusal(const std::vector<Vector3d>& landmarks, const Vector3d& collar, const Vector3d& up) {
  try {
    (void)plantFrameFromLandmarks(landmarks, collar, up);
  } catch (const InputError& e) {
    return e.what();
  }
  return "accepted";
}

}  // namespace

TEST(PlantFrame, UnderAnyTransmitterPoseThePlantComesOutInItsOwnFrame) {
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0.0, 0.3);  // the stylus's noise, mm per axis
  const std::vector<Vector3d> rim{onRim(0), onRim(100), onRim(200), onRim(290)};
  const Vector3d node(3, -2, 180), tip(140, 90, 260);
  for (int trial = 0; trial < 50; ++trial) {
    const Eigen::Isometry3d pose = randomPose(rng);
    std::vector<Vector3d> landmarks;
    for (const Vector3d& p : rim) landmarks.push_back(pose * p + Vector3d(noise(rng), noise(rng), noise(rng)));
    const Vector3d collar = pose * Vector3d::Zero();
    const Vector3d up = pose.linear() * Vector3d::UnitZ() + Vector3d(0.2, -0.1, 0.0);  // any vector on the stem's side
    const PlantFrame f = plantFrameFromLandmarks(landmarks, collar, up);
    EXPECT_LT(f.point(collar).norm(), 1e-9);
    // The landmarks' noise tilts and turns the frame by about σ / (rim radius): a point
    // 180 mm up moves by about 1 mm, the tip 310 mm away by about 1.5 mm (bounds at 3σ).
    EXPECT_LT((f.point(pose * node) - node).norm(), 2.5) << trial;
    EXPECT_LT((f.point(pose * tip) - tip).norm(), 4.0) << trial;
    // Without noise, exactly.
    const PlantFrame exact =
        plantFrameFromLandmarks({pose * rim[0], pose * rim[1], pose * rim[2], pose * rim[3]}, collar, up);
    EXPECT_LT((exact.point(pose * tip) - tip).norm(), 1e-9) << trial;
    EXPECT_LT(f.flatnessMm, 1.0);
    EXPECT_NEAR(f.fromDigitizer.linear().determinant(), 1.0, 1e-9);  // a rotation, not a mirror
    // The leaf's angles come out as measured in the plant's own frame.
    const LeafPose p = leafPose(f.point(pose * node), f.point(pose * tip));
    const LeafPose truth = leafPose(node, tip);
    EXPECT_NEAR(p.azimuthDeg, truth.azimuthDeg, 1.0);
    EXPECT_NEAR(p.inclinationDeg, truth.inclinationDeg, 1.0);
  }
}

TEST(PlantFrame, ZIsTheStemsSideAndXPointsToTheFirstLandmark) {
  const std::vector<Vector3d> rim{onRim(30), onRim(150), onRim(270)};
  const PlantFrame f = plantFrameFromLandmarks(rim, Vector3d(0, 0, 0), Vector3d(0, 0, 1));
  const Vector3d first = f.point(rim[0]);
  EXPECT_NEAR(first.y(), 0.0, 1e-9);
  EXPECT_GT(first.x(), 100.0);
  EXPECT_NEAR(first.z(), 25.0, 1e-9);
  EXPECT_NEAR(azimuthDeg(f.point(rim[1])), 120.0, 1e-9);  // counterclockwise seen from above
  // The stem growing the other way turns the frame over: +Z follows the stem.
  const PlantFrame down = plantFrameFromLandmarks(rim, Vector3d(0, 0, 0), Vector3d(0, 0, -1));
  EXPECT_NEAR(down.point(Vector3d(0, 0, -50)).z(), 50.0, 1e-9);
  EXPECT_NEAR(down.fromDigitizer.linear().determinant(), 1.0, 1e-9);
}

TEST(PlantFrame, LandmarksThatCannotFixAFrameAreRefusedWithWhatToDo) {
  const Vector3d up(0, 0, 1), collar(0, 0, 0);
  EXPECT_NE(refusal({onRim(0), onRim(120)}, collar, up).find("at least three landmarks"), std::string::npos);
  EXPECT_NE(refusal({onRim(0), onRim(120), onRim(120) + Vector3d(0.5, 0, 0)}, collar, up)
                .find("landmark 3 is 0.5 mm from landmark 2: the same point pressed twice?"),
            std::string::npos);
  EXPECT_NE(refusal({onRim(0, 6), onRim(120, 6), onRim(240, 6)}, collar, up).find("at least 20.0 mm apart"),
            std::string::npos);
  EXPECT_NE(refusal({Vector3d(0, 0, 0), Vector3d(50, 1, 0), Vector3d(100, 0, 0)}, Vector3d(50, -80, 0), up)
                .find("nearly on one line"),
            std::string::npos);
  EXPECT_NE(refusal({onRim(0), onRim(120), onRim(240)}, collar, Vector3d(1, 0, 0)).find("lies in the landmarks' plane"),
            std::string::npos);
  EXPECT_NE(
      refusal({Vector3d(0, 0, 25), onRim(120), onRim(240)}, collar, up).find("straight above or below the collar"),
      std::string::npos);
  EXPECT_NE(refusal({onRim(0), onRim(120), Vector3d(NAN, 0, 0)}, collar, up).find("not a finite point"),
            std::string::npos);
  EXPECT_EQ(refusal({onRim(0), onRim(120), onRim(240)}, collar, up), "accepted");
}

TEST(PlantFrame, AzimuthInclinationAndDivergenceFollowTheirConventions) {
  EXPECT_NEAR(azimuthDeg({1, 0, 0}), 0.0, 1e-12);
  EXPECT_NEAR(azimuthDeg({0, 1, 5}), 90.0, 1e-12);
  EXPECT_NEAR(azimuthDeg({0, -1, 0}), 270.0, 1e-12);
  EXPECT_NEAR(inclinationDeg({0, 0, 3}), 0.0, 1e-12);
  EXPECT_NEAR(inclinationDeg({1, 1, 0}), 90.0, 1e-12);
  EXPECT_NEAR(inclinationDeg({1, 0, -1}), 135.0, 1e-12);
  EXPECT_NEAR(divergenceDeg(300.0, 77.5), 137.5, 1e-12);
  EXPECT_NEAR(divergenceDeg(77.5, 300.0), 222.5, 1e-12);
  EXPECT_NEAR(divergenceDeg(10.0, 10.0), 0.0, 1e-12);
}

TEST(PlantFrame, AQuickLeafsThreePointsGiveLengthWidthAnglesAndRoll) {
  // A leaf 200 mm long at azimuth 30°, 60° from +Z, 90 mm wide, rolled 20° about its chord.
  const double az = 30 * kPi / 180, inc = 60 * kPi / 180, roll = 20 * kPi / 180;
  const Vector3d a(std::sin(inc) * std::cos(az), std::sin(inc) * std::sin(az), std::cos(inc));
  const Vector3d level = a.cross(Vector3d::UnitZ()).normalized();
  const Vector3d across = std::cos(roll) * level + std::sin(roll) * a.cross(level);
  const Vector3d base(5, 3, 300), tip = base + 200 * a;
  for (const double side : {1.0, -1.0}) {  // either margin: the same roll
    const LeafPose p = leafPose(base, tip, base + 80 * a + side * 45 * across);
    EXPECT_NEAR(p.lengthMm, 200.0, 1e-9);
    EXPECT_NEAR(p.azimuthDeg, 30.0, 1e-9);
    EXPECT_NEAR(p.inclinationDeg, 60.0, 1e-9);
    ASSERT_TRUE(p.widthMm && p.rollDeg);
    EXPECT_NEAR(*p.widthMm, 90.0, 1e-9);
    EXPECT_NEAR(*p.rollDeg, 20.0, 1e-9);
  }
  EXPECT_FALSE(leafPose(base, tip).widthMm);
  EXPECT_THROW((void)leafPose(base, base + Vector3d(0.2, 0, 0)), InputError);
  EXPECT_THROW((void)leafPose(base, tip, base + 50 * a), InputError);  // a "margin" on the midrib
}
