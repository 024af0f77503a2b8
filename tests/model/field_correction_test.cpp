// A correction of a bent field (issue 50): a smooth error put on a jig's points is taken away on
// points the fit never saw, a clean field gets no correction (a polynomial fitted to noise does
// worse on unseen points, and the choice says so), the correction's file is refused by name when
// it is not one, and the error map draws an arrow per divot in the colour of its size.
#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <random>

#include "leafdig/model/errors.hpp"
#include "leafdig/model/field/correction.hpp"

namespace m = leafdig::model;
using Eigen::Vector3d;

namespace {

// A jig of three levels, 7 × 5 divots on the lowest and fewer above, 600 × 400 × 200 mm.
m::Jig bigJig() {
  m::Jig jig{"test jig", {}};
  int k = 0;
  for (int level = 0; level < 3; ++level)
    for (int y = 0; y < 5 - level; ++y)
      for (int x = 0; x < 7 - 2 * level; ++x)
        jig.points.push_back({"P" + std::to_string(++k), Vector3d(100.0 * x + 50 * level, 100.0 * y, 100.0 * level)});
  return jig;
}

// A field that pushes points out and down, more the lower they are (as a plate below does).
Vector3d bend(const Vector3d& p) {
  const double depth = (300 - p.z()) / 300;  // 1 at z = 0, 0 at z = 300
  return p + Vector3d(0.004 * p.x() * depth, 0.003 * p.y() * depth, -2.5 * depth * depth);
}

std::vector<Vector3d> measure(const m::Jig& jig, const Eigen::Isometry3d& pose, double noiseMm, bool bent,
                              unsigned seed = 7) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0, noiseMm);
  std::vector<Vector3d> out;
  for (const auto& p : jig.points) {
    const Vector3d truth = pose * p.pointMm;
    out.push_back((bent ? bend(truth) : truth) + Vector3d(noise(rng), noise(rng), noise(rng)));
  }
  return out;
}

Eigen::Isometry3d somewhere() {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.rotate(Eigen::AngleAxisd(0.4, Vector3d::UnitZ()));
  pose.pretranslate(Vector3d(-250, -150, -100));
  return pose;
}

}  // namespace

TEST(FieldCorrection, ABentFieldIsCorrectedOnPointsTheFitNeverSaw) {
  const m::Jig jig = bigJig();
  ASSERT_EQ(jig.points.size(), 35U + 20U + 9U);
  const auto measured = measure(jig, somewhere(), 0.1, true);
  const m::JigFit rigid = m::fitJig(jig, measured);
  EXPECT_GT(rigid.rmsMm, 1.0) << "the bend is larger than a clean field's error";
  const m::CorrectionChoice choice = m::chooseCorrection(jig, measured);
  ASSERT_EQ(choice.candidates.size(), 4U);
  EXPECT_EQ(choice.candidates[0].model, "none");
  EXPECT_TRUE(choice.candidates[2].tried);
  EXPECT_GE(choice.correction.degree, 2) << "a bend that grows downwards is not affine";
  // Honest: the held-out error is of points outside each fit, worse than the fit's own, and far
  // better than no correction's held-out error.
  EXPECT_LT(choice.holdoutRmsMm, choice.candidates[0].holdoutRmsMm / 3);
  EXPECT_GE(choice.holdoutRmsMm, choice.corrected.rmsMm);
  EXPECT_LT(choice.corrected.rmsMm, 0.4);
  // Applied to a point inside the jig's volume it never saw, the correction brings it home (up to
  // where the pose of the bent points put the jig).
  const Vector3d inside = somewhere() * Vector3d(330, 170, 60);
  const Vector3d seen = bend(inside);
  const Vector3d corrected = choice.correction.apply(seen);
  const Vector3d expected = choice.corrected.jigToDigitizer * (somewhere().inverse() * inside);
  EXPECT_LT((corrected - expected).norm(), 0.5) << (seen - expected).norm();
  EXPECT_TRUE(choice.correction.inside(seen));
  EXPECT_FALSE(choice.correction.inside(seen + Vector3d(0, 0, 900)));
}

TEST(FieldCorrection, ACleanFieldGetsNoCorrection) {
  const m::Jig jig = bigJig();
  const auto measured = measure(jig, somewhere(), 0.3, false, 11);
  const m::CorrectionChoice choice = m::chooseCorrection(jig, measured);
  EXPECT_EQ(choice.correction.name(), "none");
  EXPECT_EQ(choice.correction.apply(Vector3d(1, 2, 3)), Vector3d(1, 2, 3));
  EXPECT_NEAR(choice.holdoutRmsMm, choice.candidates[0].holdoutRmsMm, 1e-12);
  EXPECT_LT(choice.holdoutRmsMm, 0.8);
}

TEST(FieldCorrection, FewPointsTryOnlyLowDegrees) {
  m::Jig small = bigJig();
  small.points.resize(12);
  small.points.push_back({"top", Vector3d(100, 100, 100)});
  const auto measured = measure(small, somewhere(), 0.1, true);
  const m::CorrectionChoice choice = m::chooseCorrection(small, measured);
  EXPECT_TRUE(choice.candidates[1].tried);   // 13 points: 10 fitted, ≥ 1.5 × 4
  EXPECT_FALSE(choice.candidates[2].tried);  // not ≥ 1.5 × 10
  EXPECT_FALSE(choice.candidates[3].tried);
  EXPECT_LE(choice.correction.degree, 1);
}

TEST(FieldCorrection, ItsFileReadsBackAndIsRefusedByNameWhenItIsNotOne) {
  const m::Jig jig = bigJig();
  const m::CorrectionChoice choice = m::chooseCorrection(jig, measure(jig, somewhere(), 0.1, true));
  const std::string text = m::encodeCorrection(choice.correction);
  const m::FieldCorrection back = m::parseCorrection(text, "c.json");
  const Vector3d p(10, -40, -30);
  EXPECT_LT((back.apply(p) - choice.correction.apply(p)).norm(), 1e-9);
  const auto refusal = [](const nlohmann::json& doc) {
    try {
      (void)m::parseCorrection(doc.dump(), "c.json");
    } catch (const m::InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  nlohmann::json doc = nlohmann::json::parse(text);
  EXPECT_EQ(refusal(doc), "");
  nlohmann::json bad = doc;
  bad["degree"] = 7;
  EXPECT_NE(refusal(bad).find("degree: must be a whole number from 0 to 3"), std::string::npos) << refusal(bad);
  bad = doc;
  bad["coefficients"][1].erase(0);
  EXPECT_NE(refusal(bad).find("coefficients[1]: must hold"), std::string::npos) << refusal(bad);
  bad = doc;
  bad["coefficients"][0][0] = 1e300;
  EXPECT_NE(refusal(bad).find("within a metre"), std::string::npos) << refusal(bad);
  bad = doc;
  bad["model"] = "none";
  EXPECT_NE(refusal(bad).find("model: does not match"), std::string::npos) << refusal(bad);
  bad = doc;
  bad["box_mm"]["low"][2] = 1e4;
  EXPECT_NE(refusal(bad).find("box_mm"), std::string::npos) << refusal(bad);
  EXPECT_NE(refusal(nlohmann::json::array()).find("not a JSON object"), std::string::npos);
}

TEST(FieldCorrection, TheErrorMapDrawsAnArrowPerDivotInTheColourOfItsSize) {
  const m::Jig jig = bigJig();
  const auto measured = measure(jig, somewhere(), 0.05, true);
  const m::JigFit fit = m::fitJig(jig, measured);
  const std::string svg = m::fieldErrorMapSvg({&jig, &fit, 1.5, "fail", "Field check <3>"});
  std::size_t arrows = 0;
  for (std::size_t at = svg.find("marker-end"); at != std::string::npos; at = svg.find("marker-end", at + 1)) ++arrows;
  EXPECT_EQ(arrows, 2 * jig.points.size());  // from above and from the side
  EXPECT_NE(svg.find("Field check &lt;3&gt;"), std::string::npos) << "text is escaped";
  EXPECT_NE(svg.find("#d73027"), std::string::npos) << "a divot beyond tolerance is red";
  EXPECT_NE(svg.find("#1a9850"), std::string::npos) << "one within half of it green";
  EXPECT_NE(svg.find("at " + fit.worstId), std::string::npos);
}
