// `leafdig.plant-markers/1`: the shipped sample read whole, units converted, written and read
// back the same, and every kind of bad input refused with the node, the key and what to do.
#include "leafdig/model/plant/plant_markers.hpp"

#include <gtest/gtest.h>

#include <string>

#include "leafdig/model/errors.hpp"
#include "leafdig/model/plant/plant_frame.hpp"

using namespace leafdig::model;

namespace {

std::string sample() {
  return std::string(LEAFDIG_SOURCE_DIR) + "/data/plants/sample.plant-markers.json";
}

const char* kSmall = R"({"format": "leafdig.plant-markers/1", "units": "cm", "plant": "p1", "extra": {"ignored": true},
  "landmarks": [[11, 0, 2.5], [-5.5, 9.5, 2.5], [-5.5, -9.5, 2.5]],
  "collar": {"point": [0, 0, 0], "diameter": 2.1},
  "nodes": [
    {"point": [0.1, 0, 7], "diameter": 1.9, "leaf": {"kind": "none", "state": "pruned"}},
    {"point": [0.2, 0, 15], "diameter": 1.7,
     "leaf": {"kind": "quick", "base": [0.6, 0, 15], "tip": [30, 0, 35], "side": [15, 8, 25], "type": "upper"}},
    {"point": [0.2, 0, 22], "diameter": 1.5}]})";

std::string refusal(const std::string& text) {
  try {
    (void)parsePlantMarkersJson(text, "p.json");
  } catch (const InputError& e) {
    return e.what();
  }
  return "accepted";
}

std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return text;
}

}  // namespace

TEST(PlantMarkers, TheShippedSampleReadsWholeAndMakesAPlantFrame) {
  const PlantMarkers p = readPlantMarkersFile(sample());
  EXPECT_EQ(p.plant, "tobacco-p12");
  ASSERT_EQ(p.landmarksMm.size(), 4u);
  ASSERT_EQ(p.nodes.size(), 5u);
  EXPECT_EQ(p.nodes[0].state, LeafState::Dead);
  EXPECT_TRUE(std::holds_alternative<std::monostate>(p.nodes[0].leaf));
  ASSERT_TRUE(std::holds_alternative<MarkerSet>(p.nodes[1].leaf));
  EXPECT_EQ(std::get<MarkerSet>(p.nodes[1].leaf).rows.size(), 10u);
  ASSERT_TRUE(std::holds_alternative<QuickLeaf>(p.nodes[2].leaf));
  EXPECT_EQ(std::get<QuickLeaf>(p.nodes[2].leaf).type, "lower");
  EXPECT_TRUE(std::holds_alternative<std::monostate>(p.nodes[4].leaf));
  const PlantFrame frame = plantFrameFromLandmarks(p.landmarksMm, p.collarMm, p.nodes[0].pointMm - p.collarMm);
  // The sample's quick leaf at node 3 was laid out at azimuth 275°, 62° from +Z, 380 × 190 mm.
  const QuickLeaf& q = std::get<QuickLeaf>(p.nodes[2].leaf);
  const LeafPose pose = leafPose(frame.point(q.baseMm), frame.point(q.tipMm), frame.point(q.sideMm));
  EXPECT_NEAR(pose.azimuthDeg, 275.0, 0.01);
  EXPECT_NEAR(pose.inclinationDeg, 62.0, 0.01);
  EXPECT_NEAR(pose.lengthMm, 380.0, 0.01);
  EXPECT_NEAR(*pose.widthMm, 190.0, 0.01);
  EXPECT_NEAR(*pose.rollDeg, 0.0, 0.01);
}

TEST(PlantMarkers, UnitsAreConvertedAndWhatIsWrittenReadsBackTheSame) {
  const PlantMarkers p = parsePlantMarkersJson(kSmall, "small.json");
  EXPECT_DOUBLE_EQ(p.landmarksMm[0].x(), 110.0);
  EXPECT_DOUBLE_EQ(p.collarDiameterMm, 21.0);
  EXPECT_DOUBLE_EQ(p.nodes[1].pointMm.z(), 150.0);
  EXPECT_DOUBLE_EQ(std::get<QuickLeaf>(p.nodes[1].leaf).tipMm.x(), 300.0);
  EXPECT_EQ(p.nodes[0].state, LeafState::Pruned);
  for (const PlantMarkers& original : {p, readPlantMarkersFile(sample())}) {
    const std::string text = plantMarkersToJson(original);
    const PlantMarkers back = parsePlantMarkersJson(text, "written");
    EXPECT_EQ(plantMarkersToJson(back), text);
    ASSERT_EQ(back.nodes.size(), original.nodes.size());
    for (std::size_t i = 0; i < back.nodes.size(); ++i) {
      EXPECT_EQ(back.nodes[i].pointMm, original.nodes[i].pointMm);
      EXPECT_EQ(back.nodes[i].leaf.index(), original.nodes[i].leaf.index());
      EXPECT_EQ(back.nodes[i].state, original.nodes[i].state);
    }
  }
}

TEST(PlantMarkers, BadInputIsRefusedNamingTheNodeTheKeyAndWhatToDo) {
  const std::string ok = kSmall;
  EXPECT_EQ(refusal(ok), "accepted");
  const auto has = [](const std::string& message, const std::string& words) {
    return message.find(words) != std::string::npos ? testing::AssertionSuccess()
                                                    : testing::AssertionFailure() << message;
  };
  EXPECT_TRUE(has(refusal(""), "the file is empty"));
  EXPECT_TRUE(has(refusal("[1, 2]"), "expected a JSON object"));
  EXPECT_TRUE(has(refusal(replaced(ok, "plant-markers/1", "markers/1")), "not a leafdig plant-markers file"));
  EXPECT_TRUE(has(refusal(replaced(ok, "\"cm\"", "\"m\"")), "unknown unit \"m\"; use \"mm\", \"cm\" or \"in\""));
  EXPECT_TRUE(has(refusal(replaced(ok, ", [-5.5, -9.5, 2.5]]", "]")), "landmarks: must list at least three points"));
  EXPECT_TRUE(has(refusal(replaced(ok, "{\"point\": [0.2, 0, 22], ", "{")),
                  "node 3: required key \"point\" is missing; add it (see the leafdig.plant-markers/1 schema"));
  EXPECT_TRUE(has(refusal(replaced(ok, "\"kind\": \"quick\"", "\"kind\": \"sketch\"")),
                  "node 2 leaf kind: unknown leaf kind \"sketch\": use full, quick or none"));
  EXPECT_TRUE(has(refusal(replaced(ok, "\"state\": \"pruned\"", "\"state\": \"eaten\"")),
                  "node 1 leaf state: unknown leaf state \"eaten\": use alive, dead, broken, yellow or pruned"));
  EXPECT_TRUE(
      has(refusal(replaced(ok, "\"diameter\": 1.7", "\"diameter\": 0")), "node 2: diameter must be more than 0"));
  EXPECT_TRUE(has(refusal(replaced(ok, "\"diameter\": 1.5", "\"diameter\": 1e300")), "node 3: diameter is"));
  EXPECT_TRUE(has(refusal(replaced(ok, "\"tip\": [30, 0, 35]", "\"tip\": [30, NaN, 35]")),
                  "node 2 leaf tip: coordinate y is NaN"));
  EXPECT_TRUE(has(refusal(replaced(ok, "\"side\": [15, 8, 25], ", "")), "node 2 leaf: required key \"side\""));
  // A full leaf's markers are read as a markers file, named by their node.
  EXPECT_TRUE(has(refusal(replaced(ok, "{\"kind\": \"none\", \"state\": \"pruned\"}",
                                   R"({"kind": "full", "markers": {"format": "leafdig.markers/1", "units": "mm",
                                       "tip": [0, 0, 0], "rows": [{"points": [[1, 1, 1]]}]}})")),
                  "p.json: node 1 leaf markers: row 1: has 1 points; every row needs exactly 7 markers"));
}

TEST(PlantMarkers, ASurveysDateIsADayOfTheCalendarReadAndWrittenAsIso) {
  EXPECT_EQ(parseSurveyDate("2026-11-26"), (SurveyDate{2026, 11, 26}));
  EXPECT_EQ(parseSurveyDate("2024-02-29"), (SurveyDate{2024, 2, 29}));  // a leap year
  EXPECT_EQ(parseSurveyDate("2000-02-29"), (SurveyDate{2000, 2, 29}));  // divisible by 400
  for (const char* notADay : {"2026-02-29", "1900-02-29", "2026-04-31", "2026-00-10", "2026-13-01", "2026-1-01",
                              "26/11/2026", "1899-12-31", "3000-01-01", "2026-11-26T10:00", "", "２026-11-26"})
    EXPECT_FALSE(parseSurveyDate(notADay).has_value()) << notADay;
  EXPECT_EQ(toIso({2026, 6, 2}), "2026-06-02");
  // The plant-markers file carries it and writes it back.
  PlantMarkers p = readPlantMarkersFile(sample());
  ASSERT_TRUE(p.date.has_value());
  EXPECT_EQ(*p.date, (SurveyDate{2026, 6, 12}));
  EXPECT_EQ(parsePlantMarkersJson(plantMarkersToJson(p), "again").date, p.date);
  p.date.reset();
  EXPECT_EQ(plantMarkersToJson(p).find("\"date\""), std::string::npos);
}
