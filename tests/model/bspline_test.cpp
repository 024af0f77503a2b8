#include "leafdig/model/spline/bspline.hpp"

#include <gtest/gtest.h>

#include <Eigen/Dense>

#include "leafdig/model/spline/banded.hpp"
#include "leafdig/model/spline/interpolation.hpp"

namespace leafdig::model {
namespace {

const KnotVector kNonUniform{0, 0, 0, 0, 0.1, 0.35, 0.4, 0.8, 1, 1, 1, 1};

TEST(BSplineBasis, partitionOfUnityOnNonUniformKnots) {
  for (double t = 0.0; t <= 1.0; t += 0.013) {
    const int span = findSpan(3, kNonUniform, t);
    const Eigen::MatrixXd d = basisDerivatives(span, 3, kNonUniform, t, 2);
    EXPECT_NEAR(d.row(0).sum(), 1.0, 1e-14) << "t=" << t;
    EXPECT_NEAR(d.row(1).sum(), 0.0, 1e-10) << "t=" << t;
    EXPECT_NEAR(d.row(2).sum(), 0.0, 1e-8) << "t=" << t;
    EXPECT_GE(d.row(0).minCoeff(), -1e-15);
  }
}

TEST(BSplineBasis, findSpanMapsTheLastKnotToTheLastSpan) {
  EXPECT_EQ(findSpan(3, kNonUniform, 1.0), 7);
  EXPECT_EQ(findSpan(3, kNonUniform, 0.0), 3);
  EXPECT_EQ(findSpan(3, kNonUniform, 0.35), 5);
}

TEST(BSplineCurve, derivativesMatchFiniteDifferences) {
  Eigen::MatrixXd ctrl(8, 2);
  ctrl << 0, 0, 1, 2, 2, -1, 3, 3, 4, 0, 5, 1, 6, -2, 7, 0;
  const BSplineCurve curve(3, kNonUniform, ctrl);
  const double h = 1e-6;
  for (double t : {0.05, 0.2, 0.37, 0.6, 0.9}) {
    const Eigen::MatrixXd d = curve.derivatives(t, 2);
    const Eigen::VectorXd fd1 = (curve.evaluate(t + h) - curve.evaluate(t - h)) / (2 * h);
    const Eigen::VectorXd fd2 = (curve.derivatives(t + h, 1).row(1) - curve.derivatives(t - h, 1).row(1)) / (2 * h);
    EXPECT_LT((d.row(1).transpose() - fd1).norm(), 1e-5) << "t=" << t;
    EXPECT_LT((d.row(2).transpose() - fd2).norm(), 1e-4) << "t=" << t;
  }
}

TEST(BSplineCurve, rejectsKnotsThatDoNotFitTheControlPoints) {
  EXPECT_THROW(BSplineCurve(3, {0, 0, 0, 0, 1, 1, 1}, Eigen::MatrixXd::Zero(4, 3)), std::invalid_argument);
  EXPECT_THROW(BSplineCurve(3, {0, 0, 0, 0.5, 1, 1, 1, 1}, Eigen::MatrixXd::Zero(4, 3)), std::invalid_argument);
}

TEST(BandedMatrix, solvesLikeADenseSolverIncludingRowSwaps) {
  const int n = 12;
  BandedMatrix band(n, 1, 1);
  Eigen::MatrixXd dense = Eigen::MatrixXd::Zero(n, n);
  for (int i = 0; i < n; ++i) {
    for (int j = std::max(0, i - 1); j <= std::min(n - 1, i + 1); ++j) {
      // Small diagonal entries force partial pivoting.
      const double v = (i == j) ? 0.01 * (i + 1) : 1.0 + 0.1 * i - 0.05 * j;
      band.set(i, j, v);
      dense(i, j) = v;
    }
  }
  const Eigen::MatrixXd rhs = Eigen::MatrixXd::Random(n, 4);
  const Eigen::MatrixXd expected = dense.fullPivLu().solve(rhs);
  const Eigen::MatrixXd actual = std::move(band).solve(rhs);
  EXPECT_LT((actual - expected).norm(), 1e-9);
}

TEST(BandedMatrix, reportsASingularMatrix) {
  BandedMatrix band(3, 1, 1);
  band.set(0, 0, 1.0);
  band.set(1, 0, 1.0);
  band.set(2, 2, 1.0);
  EXPECT_THROW(std::move(band).solve(Eigen::MatrixXd::Ones(3, 1)), std::runtime_error);
}

TEST(NaturalInterpolation, reproducesACubicWhoseEndsAreStraight) {
  // f(t) = t on uneven parameters: a natural spline reproduces linear data exactly.
  const std::vector<double> params{0, 0.15, 0.2, 0.55, 0.9, 1};
  Eigen::MatrixXd pts(6, 1);
  for (int k = 0; k < 6; ++k) pts(k, 0) = 3.0 * params[k] - 1.0;
  const BSplineCurve c = interpolateNaturalCubic(params, pts);
  for (double t = 0; t <= 1; t += 0.05) EXPECT_NEAR(c.evaluate(t)(0), 3.0 * t - 1.0, 1e-12);
}

TEST(NaturalInterpolation, matchesTheClassicNaturalSplineSolution) {
  // Values of the natural cubic spline through (0,0), (1,1), (2,0) at x = 0.5: the
  // textbook result S(x) = 1.5 x - 0.5 x^3 on [0, 1] gives 0.6875.
  const std::vector<double> params{0, 0.5, 1};
  Eigen::MatrixXd pts(3, 1);
  pts << 0, 1, 0;
  const BSplineCurve c = interpolateNaturalCubic(params, pts);
  EXPECT_NEAR(c.evaluate(0.25)(0), 0.6875, 1e-12);
}

TEST(NaturalInterpolation, chordLengthParametersRejectCoincidentPoints) {
  Eigen::MatrixXd pts(3, 3);
  pts << 0, 0, 0, 1, 1, 1, 1, 1, 1;
  EXPECT_THROW(static_cast<void>(chordLengthParameters(pts, 3)), std::invalid_argument);
}

}  // namespace
}  // namespace leafdig::model
