// A calibration jig (issue 50): the leafdig.jig/1 file refused by name where it is not one (a
// flat jig included), the rigid fit recovering a jig placed anywhere with no residual, and a
// bent field showing as residuals — RMS, the largest and which point — that no rigid motion
// takes away.
#include "leafdig/model/field/jig.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <string>

#include "leafdig/model/errors.hpp"

namespace m = leafdig::model;
using nlohmann::json;

namespace {

std::string refusal(const json& doc) {
  try {
    (void)m::parseJig(doc.dump(), "j.json");
  } catch (const m::InputError& e) {
    return e.what();
  }
  return {};
}

json jigDoc() {
  json points = json::array();
  int k = 0;
  for (double z : {0.0, 100.0})
    for (double y : {0.0, 200.0})
      for (double x : {0.0, 300.0}) points.push_back({{"id", "P" + std::to_string(++k)}, {"point", {x, y, z}}});
  return {{"format", "leafdig.jig/1"}, {"units", "mm"}, {"name", "test board"}, {"points", points}};
}

}  // namespace

TEST(Jig, AFileThatIsNotAJigIsRefusedByName) {
  EXPECT_EQ(refusal(jigDoc()), "");
  json d = jigDoc();
  d["format"] = "leafdig.markers/1";
  EXPECT_NE(refusal(d).find("this is not a jig file"), std::string::npos) << refusal(d);
  d = jigDoc();
  d["points"][3]["id"] = "P1";
  EXPECT_NE(refusal(d).find("points[3]: its id \"P1\" is used twice"), std::string::npos) << refusal(d);
  d = jigDoc();
  d["points"][2]["id"] = "a b";
  EXPECT_NE(refusal(d).find("without spaces"), std::string::npos) << refusal(d);
  d = jigDoc();
  d["points"][1]["point"] = {0, 1e9, 0};
  EXPECT_NE(refusal(d).find("points[1]"), std::string::npos) << refusal(d);
  d = jigDoc();
  for (auto& p : d["points"]) p["point"][2] = 5.0;  // every divot on one level
  EXPECT_NE(refusal(d).find("all lie in one plane"), std::string::npos) << refusal(d);
  d = jigDoc();
  d["points"].erase(d["points"].begin() + 3, d["points"].end());  // three divots left
  EXPECT_NE(refusal(d).find("at least 4 points"), std::string::npos) << refusal(d);
  d = jigDoc();
  d["units"] = "cm";
  EXPECT_EQ(m::parseJig(d.dump(), "j").points[1].pointMm.x(), 3000.0);
  // The sample shipped reads: 22 divots on three levels.
  const m::Jig sample = m::readJigFile(std::string(LEAFDIG_SOURCE_DIR) + "/data/fields/three-level.jig.json");
  EXPECT_EQ(sample.points.size(), 22u);
  EXPECT_EQ(sample.points.front().id, "A1");
}

TEST(Jig, TheRigidFitFindsTheJigAnywhereAndABentFieldShowsAsResiduals) {
  const m::Jig jig = m::parseJig(jigDoc().dump(), "j");
  // Placed anywhere: turned 30° about a tilted axis and moved; the fit finds it, nothing left over.
  const Eigen::Isometry3d pose =
      Eigen::Translation3d(420, -150, 80) * Eigen::AngleAxisd(0.52, Eigen::Vector3d(0.2, -0.3, 1).normalized());
  std::vector<Eigen::Vector3d> measured;
  for (const auto& p : jig.points) measured.push_back(pose * p.pointMm);
  const m::JigFit exact = m::fitJig(jig, measured);
  EXPECT_LT(exact.rmsMm, 1e-9);
  EXPECT_LT((exact.jigToDigitizer.matrix() - pose.matrix()).norm(), 1e-9);
  // A field that pushes points away from the transmitter by 1 % of their distance: a stretch no
  // rigid motion takes away, largest at the farthest point.
  std::vector<Eigen::Vector3d> bent;
  for (const Eigen::Vector3d& p : measured) bent.push_back(p * 1.01);
  const m::JigFit fit = m::fitJig(jig, bent);
  EXPECT_GT(fit.rmsMm, 1.0);
  EXPECT_LT(fit.rmsMm, 5.0);
  double largest = 0;
  std::string worst;
  for (std::size_t i = 0; i < fit.residualsMm.size(); ++i)
    if (fit.residualsMm[i].norm() > largest) {
      largest = fit.residualsMm[i].norm();
      worst = jig.points[i].id;
    }
  EXPECT_DOUBLE_EQ(fit.maxMm, largest);
  EXPECT_EQ(fit.worstId, worst);
  double sum = 0;
  for (const auto& r : fit.residualsMm) sum += r.squaredNorm();
  EXPECT_NEAR(fit.rmsMm, std::sqrt(sum / 8.0), 1e-12);
  // One point per divot, in its order.
  bent.pop_back();
  EXPECT_THROW((void)m::fitJig(jig, bent), m::InputError);
}
