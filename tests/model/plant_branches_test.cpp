// A plant with branches (axes of order 2 and 3) digitized in place: where each node hangs is
// read from `after` / `branches_from`, checked (a node listed later, both keys, an axis followed
// twice, an order above 3), measured in the survey per axis (internodes from the node a branch
// starts at, divergence between leaves of one axis), written as an MTG whose `+I` lines the
// strict reader hangs on the bearing internode, and built as a model with one tube per branch.
#include <gtest/gtest.h>

#include <map>
#include <string>

#include "../support/strict_formats.hpp"
#include "leafdig/model/errors.hpp"
#include "leafdig/model/io/survey_export.hpp"
#include "leafdig/model/mesh/mesh.hpp"
#include "leafdig/model/plant/plant_markers.hpp"
#include "leafdig/model/plant/plant_survey.hpp"
#include "leafdig/model/plant/surveyed_plant.hpp"
#include "leafdig/model/synth/synthetic_leaf.hpp"

using namespace leafdig::model;
using Eigen::Vector3d;

namespace {

// The shipped sample's digitizer frame is the plant frame moved by the collar: (300, 200, -400).
const Vector3d kCollar{300.0, 200.0, -400.0};

QuickLeaf quick(const Vector3d& base, const Vector3d& tip, const Vector3d& side) {
  return {kCollar + base, kCollar + tip, kCollar + side, ""};
}

// The sample's landmarks and collar; the main stem 1, 2, then a branch from node 2 (nodes 3
// and 4, node 4 bearing a branch of order 3: node 5), then the main stem again after node 2
// (nodes 6, 7). Points in the plant frame, moved to the digitizer's.
PlantMarkers branched() {
  PlantMarkers p = readPlantMarkersFile(std::string(LEAFDIG_SOURCE_DIR) + "/data/plants/sample.plant-markers.json");
  p.plant = "pepper-b1";
  const auto node = [](const Vector3d& at, double diameter) {
    PlantNode n;
    n.pointMm = kCollar + at;
    n.diameterMm = diameter;
    return n;
  };
  std::vector<PlantNode> nodes;
  nodes.push_back(node({1, 0, 70}, 19.8));                                   // 1
  nodes.push_back(node({2, -1, 160}, 18.6));                                 // 2
  nodes.back().leaf = quick({12, -1, 160}, {200, -1, 260}, {100, 60, 215});  // azimuth 0
  nodes.push_back(node({2, 60, 200}, 9.0));                                  // 3: branch from 2
  nodes.back().branchesFrom = 2;
  nodes.back().leaf = quick({2, 66, 200}, {2, 200, 280}, {-50, 130, 240});      // azimuth 90
  nodes.push_back(node({3, 120, 250}, 8.0));                                    // 4: after 3
  nodes.back().leaf = quick({-5, 120, 250}, {-150, 120, 330}, {-75, 40, 290});  // azimuth 180
  nodes.push_back(node({3, 150, 300}, 5.0));                                    // 5: branch from 4
  nodes.back().branchesFrom = 4;
  nodes.push_back(node({3, -2, 250}, 17.1));  // 6: after 2
  nodes.back().after = 2;
  nodes.back().leaf = quick({3, -12, 250}, {3, -200, 350}, {60, -100, 300});  // azimuth 270
  nodes.push_back(node({4, -3, 330}, 15.9));                                  // 7
  p.nodes = nodes;
  return p;
}

std::string refusal(PlantMarkers p) {
  try {
    (void)parsePlantMarkersJson(plantMarkersToJson(p), "b.json");
  } catch (const InputError& e) {
    return e.what();
  }
  return "accepted";
}

}  // namespace

TEST(PlantBranches, EachNodeHangsWhereItSaysAndTheFileReadsBackTheSame) {
  const PlantMarkers p = branched();
  const std::string text = plantMarkersToJson(p);
  EXPECT_NE(text.find("\"branches_from\": 2"), std::string::npos);
  EXPECT_NE(text.find("\"after\": 2"), std::string::npos);
  const PlantMarkers back = parsePlantMarkersJson(text, "b.json");
  EXPECT_EQ(plantMarkersToJson(back), text);
  const std::vector<NodeLink> links = plantTopology(back.nodes, "b.json");
  ASSERT_EQ(links.size(), 7u);
  const std::vector<std::tuple<int, char, int, int>> want{
      {0, '<', 1, 1}, {1, '<', 1, 1}, {2, '+', 2, 3}, {3, '<', 2, 3}, {4, '+', 3, 5}, {2, '<', 1, 1}, {6, '<', 1, 1}};
  for (std::size_t i = 0; i < want.size(); ++i) {
    SCOPED_TRACE("node " + std::to_string(i + 1));
    EXPECT_EQ(links[i].parent, std::get<0>(want[i]));
    EXPECT_EQ(links[i].relation, std::get<1>(want[i]));
    EXPECT_EQ(links[i].order, std::get<2>(want[i]));
    EXPECT_EQ(links[i].axis, std::get<3>(want[i]));
  }
  EXPECT_TRUE(hasBranches(links));
  // A plant without the keys is one axis, and its file has none of them.
  const PlantMarkers sample =
      readPlantMarkersFile(std::string(LEAFDIG_SOURCE_DIR) + "/data/plants/sample.plant-markers.json");
  EXPECT_FALSE(hasBranches(plantTopology(sample.nodes, "sample")));
  EXPECT_EQ(plantMarkersToJson(sample).find("branches_from"), std::string::npos);
}

TEST(PlantBranches, ANodeHangingOnNothingItCanIsRefusedByNumberWithWhatToDo) {
  PlantMarkers p = branched();
  p.nodes[2].branchesFrom = 3;  // itself
  EXPECT_NE(refusal(p).find("node 3 branches_from: must be the number of a node listed before it (1 to 2)"),
            std::string::npos)
      << refusal(p);
  p = branched();
  p.nodes[5].after = 9;
  EXPECT_NE(refusal(p).find("node 6 after: must be the number of a node listed before it (1 to 5)"), std::string::npos)
      << refusal(p);
  p = branched();
  p.nodes[5].branchesFrom = 2;  // with its "after": 2
  EXPECT_NE(refusal(p).find("node 6: says both \"after\" and \"branches_from\""), std::string::npos) << refusal(p);
  p = branched();
  p.nodes[5].after = 3;  // node 4 already follows node 3
  EXPECT_NE(refusal(p).find("node 6: follows node 3, which another node already follows on its axis"),
            std::string::npos)
      << refusal(p);
  p = branched();
  p.nodes[5].after.reset();  // node 6 would follow node 5 (order 3), and node 7 with it
  EXPECT_EQ(refusal(p), "accepted");
  p.nodes.push_back(p.nodes[4]);  // node 8: a branch from node 5, of order 4
  p.nodes.back().branchesFrom = 5;
  EXPECT_NE(refusal(p).find("node 8: would start an axis of order 4 (node 5 is on one of order 3): a plant takes "
                            "axes up to order 3"),
            std::string::npos)
      << refusal(p);
  // Wrong types, by key.
  const std::string text = plantMarkersToJson(branched());
  const auto at = text.find("\"branches_from\": 2");
  std::string bad = text;
  bad.replace(at, 18, "\"branches_from\": \"2\"");
  try {
    (void)parsePlantMarkersJson(bad, "b.json");
    ADD_FAILURE() << "accepted a node number in quotes";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("node 3 branches_from: must be the number of a node listed before it"),
              std::string::npos)
        << e.what();
  }
}

TEST(PlantBranches, TheSurveyMeasuresEachAxisOnItsOwn) {
  const PlantSurvey s = surveyPlant(branched());
  ASSERT_EQ(s.nodes.size(), 7u);
  // Internodes from the node each hangs on: a branch's first from the bearing node.
  EXPECT_NEAR(s.nodes[2].internodeMm, (Vector3d(2, 60, 200) - Vector3d(2, -1, 160)).norm(), 1e-6);
  EXPECT_NEAR(s.nodes[4].internodeMm, (Vector3d(3, 150, 300) - Vector3d(3, 120, 250)).norm(), 1e-6);
  EXPECT_NEAR(s.nodes[5].internodeMm, (Vector3d(3, -2, 250) - Vector3d(2, -1, 160)).norm(), 1e-6);
  EXPECT_EQ(s.nodes[5].link.parent, 2);
  EXPECT_EQ(s.nodes[4].link.order, 3);
  // Divergence between successive leaves of one axis: node 4's from node 3's (both on the
  // branch: 90° → 180°), node 6's from node 2's (main stem: 0° → 270°), none for node 3.
  std::map<int, const SurveyedLeaf*> leaf;
  for (const SurveyedLeaf& l : s.leaves) leaf[l.node] = &l;
  ASSERT_EQ(leaf.size(), 4u);
  EXPECT_NEAR(leaf[2]->pose->azimuthDeg, 0.0, 0.5);
  EXPECT_NEAR(leaf[3]->pose->azimuthDeg, 90.0, 0.5);
  EXPECT_FALSE(leaf[2]->divergenceDeg);
  EXPECT_FALSE(leaf[3]->divergenceDeg);
  ASSERT_TRUE(leaf[4]->divergenceDeg);
  EXPECT_NEAR(*leaf[4]->divergenceDeg, 90.0, 1.0);
  ASSERT_TRUE(leaf[6]->divergenceDeg);
  EXPECT_NEAR(*leaf[6]->divergenceDeg, 270.0, 1.0);
  const std::string json = plantSurveyToJson(s);
  EXPECT_NE(json.find("\"relation\": \"+\""), std::string::npos);
  EXPECT_NE(json.find("\"order\": 3"), std::string::npos);
}

TEST(PlantBranches, TheMtgHangsEachBranchOnItsBearingInternodeForTheStrictReader) {
  const PlantSurvey s = surveyPlant(branched());
  const std::string text = encodeSurveyMtg(s, SurveyDate{2026, 11, 27});
  const leafdig::test::MtgFile mtg = leafdig::test::readMtgStrictly(text);
  EXPECT_TRUE(mtg.relations.count({'I', 'I', '+'}));
  // Entities by label: their parent's label and their relation.
  std::map<std::string, std::pair<std::string, char>> hang;
  const auto label = [&](int k) {
    const auto& e = mtg.entities[static_cast<std::size_t>(k)];
    return std::string(1, e.symbol) + std::to_string(e.index);
  };
  for (std::size_t k = 0; k < mtg.entities.size(); ++k) {
    const auto& e = mtg.entities[k];
    if (e.symbol == 'P') continue;
    hang[label(static_cast<int>(k))] = {e.parent >= 0 ? label(e.parent) : "", e.relation};
  }
  const std::map<std::string, std::pair<std::string, char>> want{
      {"I1", {"I0", '<'}}, {"I2", {"I1", '<'}}, {"L2", {"I2", '+'}}, {"I3", {"I2", '+'}},
      {"L3", {"I3", '+'}}, {"I4", {"I3", '<'}}, {"L4", {"I4", '+'}}, {"I5", {"I4", '+'}},
      {"I6", {"I2", '<'}}, {"L6", {"I6", '+'}}, {"I7", {"I6", '<'}}};
  for (const auto& [name, where] : want) {
    SCOPED_TRACE(name);
    ASSERT_TRUE(hang.count(name));
    EXPECT_EQ(hang[name], where);
  }
  EXPECT_EQ(hang.size(), want.size() + 1);  // and I0
  // Three TOPO columns: node 5 (order 3) stands two deep.
  EXPECT_NE(text.find("TOPO\t\t\tDate"), std::string::npos);
  EXPECT_NE(text.find("\n\t\t+I5\t"), std::string::npos) << text;
  // The CSV in the same order, each row naming its parent and relation.
  const std::string csv = encodeSurveyCsv(s, SurveyDate{2026, 11, 27});
  EXPECT_LT(csv.find("\nI3,I,3,I2,+,"), csv.find("\nI6,I,6,I2,<,"));
  EXPECT_LT(csv.find("\nI5,I,5,I4,+,"), csv.find("\nI6,"));
  // An unbranched plant's MTG says nothing of branches.
  const std::string plain = encodeSurveyMtg(
      surveyPlant(readPlantMarkersFile(std::string(LEAFDIG_SOURCE_DIR) + "/data/plants/sample.plant-markers.json")),
      SurveyDate{2026, 11, 27});
  EXPECT_EQ(plain.find("I\tI\t+"), std::string::npos);
  EXPECT_NE(plain.find("TOPO\t\tDate"), std::string::npos);
}

TEST(PlantBranches, TheModelHasATubePerBranchFromItsBearingNode) {
  const PlantSurvey s = surveyPlant(branched());
  const Plant plant = surveyedPlant(s, {}, LibraryLeaf{kSampleShapeSource, sampleLeafShape()});
  ASSERT_TRUE(plant.stem);
  ASSERT_EQ(plant.branches.size(), 2u);
  EXPECT_EQ(plant.branches[0].name, "branch-3");
  EXPECT_EQ(plant.branches[1].name, "branch-5");
  // The stem runs through the collar and the main nodes only; a branch from its bearer.
  EXPECT_EQ(plant.stem->curve.dataBalls().size(), 5u);  // collar, 1, 2, 6, 7
  EXPECT_NEAR(plant.stemHeightMm, 330.0, 1.0);
  const auto& b = plant.branches[0].curve.dataBalls();
  ASSERT_EQ(b.size(), 3u);
  EXPECT_NEAR((b[0].center - Vector3d(2, -1, 160)).norm(), 0.0, 1e-6);
  EXPECT_NEAR(b[0].radius, 4.5, 1e-9);
  EXPECT_EQ(plant.leaves.size(), 4u);
  const LeafMesh mesh = meshPlant(plant, MeshResolution::preset("preview"));
  std::vector<std::string> axes;
  for (const Organ& o : mesh.organs)
    if (o.leafRank == 0) axes.push_back(o.name);
  EXPECT_EQ(axes, (std::vector<std::string>{"plant/stem", "plant/branch-3", "plant/branch-5"}));
  // The GLB's entities: a branch's pieces under its own internodes.
  const std::string glb = encodeSurveyGlb(s, SurveyDate{2026, 11, 27}, mesh, "test");
  for (const char* piece : {"plant/branch-3/I3", "plant/branch-3/I4", "plant/branch-5/I5", "plant/stem/I6"})
    EXPECT_NE(glb.find(piece), std::string::npos) << piece;
}
