// Moving the transmitter: the rigid fit of landmarks taken again (Kabsch), checked against
// Eigen's umeyama, and every refusal naming what to do.
#include "leafdig/acquisition/protocol/relocation.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <random>
#include <vector>

namespace {

using leafdig::acquisition::fitRelocation;
using leafdig::acquisition::RelocationFit;

std::vector<Eigen::Vector3d> rim(int count) {
  std::vector<Eigen::Vector3d> out;
  for (int i = 0; i < count; ++i) {
    const double a = 2.0 * 3.141592653589793 * i / count + 0.3 * i;  // uneven, as a technician takes them
    out.emplace_back(110.0 * std::cos(a), 110.0 * std::sin(a), 25.0 + 3.0 * (i % 2));
  }
  return out;
}

Eigen::Isometry3d randomPose(std::mt19937_64& rng) {
  std::normal_distribution<double> g;
  Eigen::Quaterniond q(g(rng), g(rng), g(rng), g(rng));
  q.normalize();
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() = q.toRotationMatrix();
  t.translation() = Eigen::Vector3d(g(rng), g(rng), g(rng)) * 300.0;
  return t;
}

std::vector<Eigen::Vector3d> seenFrom(const Eigen::Isometry3d& oldToNew, const std::vector<Eigen::Vector3d>& points,
                                      std::mt19937_64& rng, double noise) {
  std::normal_distribution<double> g(0.0, noise);
  std::vector<Eigen::Vector3d> out;
  for (const auto& p : points) out.push_back(oldToNew * p + Eigen::Vector3d(g(rng), g(rng), g(rng)));
  return out;
}

Eigen::Matrix3Xd columns(const std::vector<Eigen::Vector3d>& points) {
  Eigen::Matrix3Xd m(3, static_cast<Eigen::Index>(points.size()));
  for (std::size_t i = 0; i < points.size(); ++i) m.col(static_cast<Eigen::Index>(i)) = points[i];
  return m;
}

TEST(Relocation, TheFitRecoversTheMoveAndAgreesWithEigensUmeyama) {
  std::mt19937_64 rng(29);
  for (int trial = 0; trial < 50; ++trial) {
    const auto before = rim(3 + trial % 4);
    const Eigen::Isometry3d move = randomPose(rng);
    const double noise = trial % 2 ? 0.3 : 0.0;
    const auto after = seenFrom(move, before, rng, noise);
    const RelocationFit fit = fitRelocation(before, after);
    ASSERT_FALSE(fit.refusal) << trial << ": " << *fit.refusal;
    EXPECT_NEAR(fit.newToOld.linear().determinant(), 1.0, 1e-12);
    const Eigen::Matrix4d umeyama = Eigen::umeyama(columns(after), columns(before), false);
    EXPECT_LT((fit.newToOld.matrix() - umeyama).cwiseAbs().maxCoeff(), 1e-9) << trial;
    if (noise == 0.0) {
      EXPECT_LT((fit.newToOld.matrix() - move.inverse().matrix()).cwiseAbs().maxCoeff(), 1e-9);
      EXPECT_LT(fit.rmsMm, 1e-9);
    } else {
      EXPECT_LT(fit.rmsMm, 1.0);  // σ 0.3 mm per coordinate
      // A point on the plant 500 mm up lands within 3σ(2 + d / R) of where it was: the rim's
      // noise turns the fit by about σ / R (docs/plants.md, "How exact").
      const Eigen::Vector3d stemTop(0, 0, 500);
      EXPECT_LT((fit.newToOld * (move * stemTop) - stemTop).norm(), 3.0 * noise * (2.0 + 500.0 / 110.0));
    }
  }
}

TEST(Relocation, MovesChainThroughEachOther) {
  std::mt19937_64 rng(7);
  const auto first = rim(4);
  const Eigen::Isometry3d move1 = randomPose(rng), move2 = randomPose(rng);
  const auto second = seenFrom(move1, first, rng, 0.0);
  const auto third = seenFrom(move2, second, rng, 0.0);
  const RelocationFit a = fitRelocation(first, second), b = fitRelocation(second, third);
  ASSERT_FALSE(a.refusal || b.refusal);
  const Eigen::Isometry3d thirdToFirst = a.newToOld * b.newToOld;
  for (std::size_t i = 0; i < first.size(); ++i) EXPECT_LT((thirdToFirst * third[i] - first[i]).norm(), 1e-9);
}

TEST(Relocation, ALandmarkThatMovedIsNamedAndTheFitRefused) {
  std::mt19937_64 rng(3);
  const auto before = rim(5);
  auto after = seenFrom(randomPose(rng), before, rng, 0.2);
  after[2] += Eigen::Vector3d(6.0, -4.0, 2.0);  // the pot was knocked at landmark 3
  const RelocationFit fit = fitRelocation(before, after);
  ASSERT_TRUE(fit.refusal);
  EXPECT_EQ(fit.worst, 2u);
  EXPECT_NE(fit.refusal->find("landmark 3 is"), std::string::npos) << *fit.refusal;
  EXPECT_NE(fit.refusal->find("more than 1.5 mm"), std::string::npos) << *fit.refusal;
  // With a looser tolerance the same readings pass, and say how far off they were.
  const RelocationFit loose = fitRelocation(before, after, {.toleranceMm = 10.0, .minSpreadMm = 5.0});
  EXPECT_FALSE(loose.refusal);
  EXPECT_GT(loose.rmsMm, 1.5);
}

TEST(Relocation, LandmarksThatCannotFixATurnAreRefused) {
  const std::vector<Eigen::Vector3d> line{{0, 0, 0}, {50, 0.5, 0}, {100, -0.5, 0}, {150, 0, 0}};
  const RelocationFit collinear = fitRelocation(line, line);
  ASSERT_TRUE(collinear.refusal);
  EXPECT_NE(collinear.refusal->find("nearly on one line"), std::string::npos) << *collinear.refusal;
  const auto three = rim(3);
  const std::vector<Eigen::Vector3d> two(three.begin(), three.begin() + 2);
  EXPECT_NE(fitRelocation(two, two).refusal->find("at least three"), std::string::npos);
  EXPECT_NE(fitRelocation(rim(4), rim(3)).refusal->find("are not those taken before"), std::string::npos);
  auto bad = rim(4);
  bad[1].x() = std::nan("");
  EXPECT_NE(fitRelocation(rim(4), bad).refusal->find("not a number"), std::string::npos);
  // A mirror image is not a move: no reflection is fitted, and the residual refuses it.
  auto mirrored = rim(5);
  for (auto& p : mirrored) p.x() = -p.x();
  const RelocationFit mirror = fitRelocation(rim(5), mirrored);
  EXPECT_NEAR(mirror.newToOld.linear().determinant(), 1.0, 1e-12);
  EXPECT_TRUE(mirror.refusal);
}

}  // namespace
