// A distorted field for the simulated digitizers (issue 50): the leafdig.field-distortion/1
// reader refuses by name what it cannot take, the grid is trilinear inside and the nearest cell's
// outside, the steel-bench model pushes a sensor outwards most near the plate and far from the
// source, the preset shipped is the model's output, and a sensor moved through the field reports
// its position moved and its orientation turned while its truth stays.
#include "leafdig/devices/sim/field_distortion.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <string>

#include "leafdig/devices/pose.hpp"

namespace sim = leafdig::devices::sim;
using leafdig::devices::Vec3;
using nlohmann::json;

namespace {

// A 3×2×2 grid whose displacement is the linear field (0.01·x + 1, −0.02·y, 0.005·z − 2).
json linearField() {
  json d = json::array();
  for (int z = 0; z < 2; ++z)
    for (int y = 0; y < 2; ++y)
      for (int x = 0; x < 3; ++x) {
        const double px = -100 + 100.0 * x, py = 50 + 100.0 * y, pz = 100.0 * z;
        d.push_back({0.01 * px + 1, -0.02 * py, 0.005 * pz - 2});
      }
  return json{{"format", "leafdig.field-distortion/1"},
              {"units", "mm"},
              {"frame", "transmitter"},
              {"origin", {-100, 50, 0}},
              {"spacing_mm", 100},
              {"shape", {3, 2, 2}},
              {"displacement_mm", d}};
}

std::string refusal(const json& doc) {
  try {
    (void)sim::parseFieldDistortion(doc.dump(), "f.json");
  } catch (const sim::FieldDistortionError& e) {
    return e.what();
  }
  return {};
}

}  // namespace

TEST(FieldDistortion, TheGridIsTrilinearInsideAndTheNearestCellsOutside) {
  const sim::FieldDistortion f = sim::parseFieldDistortion(linearField().dump(), "f.json");
  // Inside the grid a linear field is reproduced exactly (the grid's x spans -100..100, y 50..150,
  // z 0..100).
  for (const Vec3 p : {Vec3{0, 100, 50}, Vec3{-37.5, 61, 13}, Vec3{99, 149, 99}, Vec3{-100, 50, 0}}) {
    const Vec3 d = f.displacementAt(p);
    EXPECT_NEAR(d[0], 0.01 * p[0] + 1, 1e-12);
    EXPECT_NEAR(d[1], -0.02 * p[1], 1e-12);
    EXPECT_NEAR(d[2], 0.005 * p[2] - 2, 1e-12);
  }
  // Outside, the position is clamped to the grid's box.
  const Vec3 far = f.displacementAt({1000, -1000, 100});
  EXPECT_NEAR(far[0], 0.01 * 100 + 1, 1e-12);
  EXPECT_NEAR(far[1], -0.02 * 50, 1e-12);
  EXPECT_NEAR(far[2], 0.005 * 100 - 2, 1e-12);
  EXPECT_EQ(f.rotationAt({0, 100, 100}), (Vec3{0, 0, 0}));
  const Vec3 r = f.reportedPosition({0, 100, 100});
  EXPECT_NEAR(r[0], 1, 1e-12);
  EXPECT_NEAR(r[1], 98, 1e-12);
  EXPECT_NEAR(r[2], 98.5, 1e-12);
}

TEST(FieldDistortion, AFileThatIsNotOneIsRefusedByName) {
  EXPECT_EQ(refusal(linearField()), "");
  const auto with = [](const char* key, const json& value) {
    json d = linearField();
    d[key] = value;
    return refusal(d);
  };
  EXPECT_NE(with("format", "leafdig.jig/1").find("its format is \"leafdig.jig/1\""), std::string::npos);
  EXPECT_NE(with("units", "cm").find("only \"mm\""), std::string::npos);
  EXPECT_NE(with("frame", "world").find("only \"transmitter\""), std::string::npos);
  EXPECT_NE(with("shape", json{3, 2, 3}).find("holds 12 values but the shape makes 18 cells"), std::string::npos);
  EXPECT_NE(with("shape", json{1, 2, 2}).find("shape[0] is 1"), std::string::npos);
  EXPECT_NE(with("shape", json{400, 400, 400}).find("at most 2000000"), std::string::npos);
  EXPECT_NE(with("spacing_mm", 0.5).find("at least 1 mm"), std::string::npos);
  EXPECT_NE(with("spacing_mm", "10").find("spacing_mm is not a number"), std::string::npos);
  EXPECT_NE(with("origin", json{0, 0}).find("origin is not three numbers"), std::string::npos);
  EXPECT_NE(with("extra", 1).find("a key leafdig does not read ('extra')"), std::string::npos);
  json big = linearField();
  big["displacement_mm"][4] = {0, 5000, 0};
  EXPECT_NE(refusal(big).find("displacement_mm[4][1] is 5000, not a number within ±1000"), std::string::npos)
      << refusal(big);
  json turned = linearField();
  turned["rotation_deg"] = json::array();
  for (int i = 0; i < 12; ++i) turned["rotation_deg"].push_back({0, 0, i == 7 ? 90 : 1});
  EXPECT_NE(refusal(turned).find("rotation_deg[7][2] is 90"), std::string::npos) << refusal(turned);
  json missing = linearField();
  missing.erase("origin");
  EXPECT_NE(refusal(missing).find("lacks \"origin\""), std::string::npos);
  for (const std::string bad : {"", "{", "[1,2]", "{\"format\": 1e400}"}) {
    try {
      (void)sim::parseFieldDistortion(bad, "f.json");
      ADD_FAILURE() << bad;
    } catch (const sim::FieldDistortionError& e) {
      EXPECT_EQ(std::string(e.what()).rfind("f.json: ", 0), 0u) << e.what();
    }
  }
  EXPECT_THROW((void)sim::readFieldDistortion("/nonexistent/field.json"), sim::FieldDistortionError);
}

TEST(FieldDistortion, TheSteelBenchPushesASensorOutwardsMostNearThePlateAndFarFromTheSource) {
  const sim::FieldDistortion f = sim::steelBench();
  const auto size = [](const Vec3& v) { return std::hypot(v[0], v[1], v[2]); };
  // Radial and outwards; growing with the distance and towards the plate (250 mm below).
  const Vec3 near = f.displacementAt({200, 0, 0}), mid = f.displacementAt({400, 0, 0}),
             low = f.displacementAt({400, 0, -150});
  EXPECT_GT(near[0], 0);
  EXPECT_NEAR(near[1], 0, 1e-9);
  EXPECT_LT(size(near), size(mid));
  EXPECT_LT(size(mid), size(low));
  // A leaf's distance from the transmitter: about a millimetre to a few (docs/devices.md, "The field").
  EXPECT_GT(size(mid), 1.0);
  EXPECT_LT(size(mid), 5.0);
  // Directly above the source the sensor's direction does not tilt.
  EXPECT_NEAR(size(f.rotationAt({0, 0, 500})), 0, 1e-9);
  EXPECT_GT(size(f.rotationAt({400, 0, -150})), 0.3);
  // What it writes it reads back, within the file's 0.001 mm.
  const sim::FieldDistortion back = sim::parseFieldDistortion(sim::encodeFieldDistortion(f), "x");
  ASSERT_EQ(back.displacementMm.size(), f.displacementMm.size());
  for (std::size_t i = 0; i < f.displacementMm.size(); ++i)
    for (std::size_t a = 0; a < 3; ++a) {
      EXPECT_NEAR(back.displacementMm[i][a], f.displacementMm[i][a], 5e-4);
      EXPECT_NEAR(back.rotationDeg[i][a], f.rotationDeg[i][a], 5e-5);
    }
  // The preset shipped is this model's output, byte for byte.
  std::ifstream in(std::string(LEAFDIG_SOURCE_DIR) + "/data/fields/steel-bench.field.json", std::ios::binary);
  ASSERT_TRUE(in) << "data/fields/steel-bench.field.json";
  const std::string shipped((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(shipped, sim::encodeFieldDistortion(f)) << "regenerate: leafdig field model steel-bench -o FILE";
}

namespace {
class Still final : public sim::StylusMotion {
 public:
  explicit Still(Vec3 at) : at_(at) {}
  [[nodiscard]] State at(double, std::uint64_t) const override {
    State s;
    s.positionMm = s.truthMm = at_;
    s.orientationDeg = {30, -20, 10};
    return s;
  }

 private:
  Vec3 at_;
};
}  // namespace

TEST(FieldDistortion, ASensorInTheFieldReportsItsPositionMovedAndItsOrientationTurned) {
  json doc = linearField();
  doc["rotation_deg"] = json::array();
  for (int i = 0; i < 12; ++i) doc["rotation_deg"].push_back({0, 0, 2});  // 2° about the vertical everywhere
  const auto field = std::make_shared<const sim::FieldDistortion>(sim::parseFieldDistortion(doc.dump(), "f"));
  const sim::DistortedMotion moved(std::make_shared<Still>(Vec3{0, 100, 100}), field);
  const auto s = moved.at(1.0, 3);
  EXPECT_EQ(s.truthMm, (Vec3{0, 100, 100}));
  EXPECT_NEAR(s.positionMm[0], 1, 1e-12);
  EXPECT_NEAR(s.positionMm[1], 98, 1e-12);
  EXPECT_NEAR(s.positionMm[2], 98.5, 1e-12);
  // Turned 2° about the transmitter's z: the azimuth by 2°, the rest as it was.
  EXPECT_NEAR(leafdig::devices::rotationBetweenDeg(leafdig::devices::rotationFromEulerDeg(s.orientationDeg),
                                                   leafdig::devices::rotationFromEulerDeg({30, -20, 10})),
              2.0, 1e-9);
  EXPECT_NEAR(s.orientationDeg[0], 32, 1e-9);
  EXPECT_NEAR(s.orientationDeg[1], -20, 1e-9);
  EXPECT_NEAR(s.orientationDeg[2], 10, 1e-9);
}
