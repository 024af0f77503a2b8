#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <numbers>

#include "leafdig/model/leaf/leaf_model.hpp"
#include "leafdig/model/mesh/mesh.hpp"
#include "leafdig/model/spline/ball_bspline_curve.hpp"

namespace leafdig::model {
namespace {

// A wavy vein with unevenly spaced data balls of varying radius.
std::vector<Ball> wavyVein() {
  std::vector<Ball> balls;
  const double xs[] = {0, 7, 11, 25, 31, 48, 60};
  for (int k = 0; k < 7; ++k) {
    balls.push_back(
        {Eigen::Vector3d(xs[k], 6 * std::sin(xs[k] / 9), 2 * std::cos(xs[k] / 13)), 1.0 + 0.3 * std::sin(k)});
  }
  return balls;
}

TEST(BallBSplineCurve, reproducesEveryDataBallToANanometre) {
  const auto balls = wavyVein();
  const auto curve = BallBSplineCurve::interpolate(balls);
  for (std::size_t k = 0; k < balls.size(); ++k) {
    const double t = curve.dataParameters()[k];
    EXPECT_LT((curve.center(t) - balls[k].center).norm(), 1e-9) << "ball " << k;
    EXPECT_NEAR(curve.radius(t), balls[k].radius, 1e-9) << "ball " << k;
  }
}

TEST(BallBSplineCurve, secondDerivativesVanishAtBothEnds) {
  const auto curve = BallBSplineCurve::interpolate(wavyVein());
  for (double t : {0.0, 1.0}) {
    const Eigen::MatrixXd d = curve.spline().derivatives(t, 2);
    EXPECT_LT(d.row(2).norm(), 1e-9 * d.row(1).norm()) << "t=" << t;
  }
}

TEST(BallBSplineCurve, parametersAreChordLengthsOfTheCentres) {
  const auto balls = wavyVein();
  const auto curve = BallBSplineCurve::interpolate(balls);
  double total = 0.0;
  std::vector<double> cumulative{0.0};
  for (std::size_t k = 1; k < balls.size(); ++k) {
    total += (balls[k].center - balls[k - 1].center).norm();
    cumulative.push_back(total);
  }
  ASSERT_EQ(curve.dataParameters().size(), balls.size());
  for (std::size_t k = 0; k < balls.size(); ++k) {
    EXPECT_NEAR(curve.dataParameters()[k], cumulative[k] / total, 1e-15);
  }
}

TEST(BallBSplineCurve, knotsAreClampedWithTheInteriorDataParameters) {
  const auto balls = wavyVein();
  const auto curve = BallBSplineCurve::interpolate(balls);
  const auto& knots = curve.spline().knots();
  const auto& t = curve.dataParameters();
  const std::size_t m = balls.size() - 1;
  ASSERT_EQ(knots.size(), m + 7);
  EXPECT_EQ(curve.spline().controlPoints().rows(), static_cast<Eigen::Index>(m + 3));
  for (int i = 0; i < 4; ++i) {
    EXPECT_EQ(knots[i], 0.0);
    EXPECT_EQ(knots[knots.size() - 1 - i], 1.0);
  }
  for (std::size_t k = 1; k < m; ++k) EXPECT_EQ(knots[3 + k], t[k]);
}

TEST(BallBSplineCurve, constantRadiusGivesAPipeOfThatRadius) {
  auto balls = wavyVein();
  for (auto& b : balls) b.radius = 1.25;
  const auto curve = BallBSplineCurve::interpolate(balls);
  std::vector<double> ts;
  for (int i = 0; i <= 200; ++i) ts.push_back(i / 200.0);
  const auto frames = rotationMinimisingFrames(curve, ts);
  for (std::size_t i = 0; i < ts.size(); i += 7) {
    const auto circle = curve.envelopeCircle(ts[i]);
    ASSERT_TRUE(circle.exists);
    EXPECT_NEAR(circle.radius, 1.25, 1e-9);
    for (double theta = 0; theta < 6.28; theta += 0.5) {
      const Eigen::Vector3d p = curve.envelopePoint(ts[i], theta, frames[i]);
      EXPECT_NEAR((p - curve.center(ts[i])).norm(), 1.25, 1e-9);
      // ... and it sits on the plane normal to the centre curve.
      EXPECT_NEAR((p - curve.center(ts[i])).dot(frames[i].tangent), 0.0, 1e-9);
    }
  }
}

TEST(BallBSplineCurve, twoBallsGiveAStraightConeTangentToBothBalls) {
  const std::vector<Ball> balls{{Eigen::Vector3d(0, 0, 0), 1.0}, {Eigen::Vector3d(10, 0, 0), 3.0}};
  const auto curve = BallBSplineCurve::interpolate(balls);
  const double sinAlpha = (3.0 - 1.0) / 10.0;  // half-angle of the tangent cone
  const double cosAlpha = std::sqrt(1 - sinAlpha * sinAlpha);
  const std::vector<double> ts{0.0, 0.3, 0.7, 1.0};
  const auto frames = rotationMinimisingFrames(curve, ts);
  for (double theta : {0.0, 1.0, 2.5, 4.0}) {
    std::vector<Eigen::Vector3d> generator;
    for (std::size_t i = 0; i < ts.size(); ++i) {
      generator.push_back(curve.envelopePoint(ts[i], theta, frames[i]));
    }
    // A cone's generators are straight lines...
    const Eigen::Vector3d dir = (generator.back() - generator.front()).normalized();
    for (const auto& p : generator) {
      EXPECT_LT((p - generator.front()).cross(dir).norm(), 1e-9);
    }
    // ... at the cone's half-angle to the axis, touching both end balls.
    EXPECT_NEAR(std::abs(dir.dot(Eigen::Vector3d::UnitX())), cosAlpha, 1e-12);
    EXPECT_NEAR(generator.front().norm(), 1.0, 1e-9);
    EXPECT_NEAR((generator.back() - Eigen::Vector3d(10, 0, 0)).norm(), 3.0, 1e-9);
  }
  EXPECT_NEAR(curve.envelopeCircle(0.0).radius, 1.0 * cosAlpha, 1e-12);
}

TEST(BallBSplineCurve, envelopeTouchesTheUnionOfBallsFromOutside) {
  const auto curve = BallBSplineCurve::interpolate(wavyVein());
  std::vector<double> dense;
  for (int i = 0; i <= 800; ++i) dense.push_back(i / 800.0);  // includes every ts below
  std::vector<double> ts;
  for (int i = 0; i <= 40; ++i) ts.push_back(i / 40.0);
  const auto frames = rotationMinimisingFrames(curve, ts);
  for (std::size_t i = 0; i < ts.size(); ++i) {
    for (double theta = 0; theta < 6.28; theta += 0.4) {
      const Eigen::Vector3d p = curve.envelopePoint(ts[i], theta, frames[i]);
      // On its own ball ...
      EXPECT_NEAR((p - curve.center(ts[i])).norm(), curve.radius(ts[i]), 1e-9);
      // ... and inside no other ball: its signed distance to the union is zero.
      double signedDistance = 1e9;
      for (double s : dense) {
        signedDistance = std::min(signedDistance, (p - curve.center(s)).norm() - curve.radius(s));
      }
      EXPECT_NEAR(signedDistance, 0.0, 1e-6) << "t=" << ts[i] << " theta=" << theta;
    }
  }
}

TEST(BallBSplineCurve, rotationMinimisingFrameDoesNotTwistOnAPlanarCurve) {
  std::vector<Ball> balls;
  for (int k = 0; k < 9; ++k) {
    balls.push_back({Eigen::Vector3d(10 * k, 15 * std::sin(k * 0.7), 0), 1.0});
  }
  const auto curve = BallBSplineCurve::interpolate(balls);
  std::vector<double> ts;
  for (int i = 0; i <= 300; ++i) ts.push_back(i / 300.0);
  const Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
  const auto frames = rotationMinimisingFrames(curve, ts, &up);
  for (const Frame& f : frames) {
    EXPECT_NEAR(f.normal.dot(up), 1.0, 1e-9);
    EXPECT_NEAR(f.tangent.dot(f.normal), 0.0, 1e-12);
  }
}

TEST(BallBSplineCurve, warnsInsteadOfProducingNaNWhenTheEnvelopeDoesNotExist) {
  // A huge jump in radius between close balls: |r'| > |c'| and a negative overshoot.
  const std::vector<Ball> balls{{Eigen::Vector3d(0, 0, 0), 0.1},
                                {Eigen::Vector3d(1, 0, 0), 6.0},
                                {Eigen::Vector3d(2, 0, 0), 0.1},
                                {Eigen::Vector3d(30, 0, 0), 0.1}};
  const Vein vein{"midrib", BallBSplineCurve::interpolate(balls)};
  std::vector<Warning> warnings;
  std::vector<double> ts;
  for (int i = 0; i <= 100; ++i) ts.push_back(i / 100.0);
  const Mesh mesh = meshVein(vein, ts, 8, CapStyle::Sphere, 3, warnings);
  ASSERT_FALSE(warnings.empty());
  EXPECT_EQ(warnings.front().organ, "midrib");
  for (const auto& p : mesh.positions) EXPECT_TRUE(p.allFinite());
  for (const auto& n : mesh.normals) {
    EXPECT_TRUE(n.allFinite());
    EXPECT_NEAR(n.norm(), 1.0, 1e-9);
  }
}

TEST(BallBSplineCurve, rejectsCoincidentConsecutiveCentres) {
  const std::vector<Ball> balls{
      {Eigen::Vector3d(0, 0, 0), 1}, {Eigen::Vector3d(0, 0, 0), 1}, {Eigen::Vector3d(1, 0, 0), 1}};
  EXPECT_THROW(static_cast<void>(BallBSplineCurve::interpolate(balls)), std::invalid_argument);
}

TEST(VeinMesh, isClosedWithSphericalCapsAndOutwardNormals) {
  const Vein vein{"lateral-1-right", BallBSplineCurve::interpolate(wavyVein())};
  std::vector<Warning> warnings;
  std::vector<double> ts;
  for (int i = 0; i <= 30; ++i) ts.push_back(i / 30.0);
  const Mesh mesh = meshVein(vein, ts, 12, CapStyle::Sphere, 4, warnings);
  // Closed surface: every edge is shared by exactly two triangles, and the signed volume
  // is positive (outward orientation).
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> edges;
  double volume = 0.0;
  for (const auto& t : mesh.triangles) {
    for (int e = 0; e < 3; ++e) {
      const auto a = t[e];
      const auto b = t[(e + 1) % 3];
      edges[{std::min(a, b), std::max(a, b)}]++;
    }
    volume += mesh.positions[t[0]].dot(mesh.positions[t[1]].cross(mesh.positions[t[2]])) / 6.0;
  }
  for (const auto& [edge, count] : edges) EXPECT_EQ(count, 2);
  EXPECT_GT(volume, 0.0);
  EXPECT_TRUE(warnings.empty());
}

}  // namespace
}  // namespace leafdig::model
