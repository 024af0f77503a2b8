// leafdig.plant-protocol/1: the built-in tobacco protocol, the shipped ones, and every refusal
// naming the entity and the key.
#include "leafdig/model/plant/plant_protocol.hpp"

#include <gtest/gtest.h>

#include <string>

#include "leafdig/model/errors.hpp"

namespace {

using namespace leafdig::model;

std::string shipped(const std::string& name) {
  return std::string(LEAFDIG_SOURCE_DIR) + "/data/protocols/" + name + ".plant-protocol.json";
}

// The message a bad protocol gets, or "" when it is read.
std::string refusal(const std::string& text) {
  try {
    (void)parsePlantProtocolJson(text, "p.json");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

std::string withEntities(const std::string& entities) {
  return R"({"format": "leafdig.plant-protocol/1", "species": "tobacco", "entities": [)" + entities + "]}";
}

TEST(PlantProtocol, TheBuiltInTobaccoProtocolIsTheShippedFileAndReadsItselfBack) {
  const PlantProtocol& p = defaultPlantProtocol();
  EXPECT_EQ(p.species, "tobacco");
  ASSERT_EQ(p.entities.size(), 2u);
  EXPECT_EQ(p.entities[0].name, "internode");
  EXPECT_EQ(p.entities[0].mtgClass, 'I');
  EXPECT_TRUE(p.entities[0].repeat);
  EXPECT_EQ(p.entities[0].points, std::vector<std::string>{"node"});
  EXPECT_EQ(p.entities[0].readings, std::vector<std::string>{"diameter"});
  EXPECT_EQ(p.entities[1].parent, "internode");
  EXPECT_EQ(p.entities[1].relation, '+');
  ASSERT_TRUE(p.entities[1].leaf.has_value());
  EXPECT_EQ(p.entities[1].leaf->fullEvery, 3);
  // The shipped tobacco file is the built-in protocol, key for key.
  EXPECT_EQ(plantProtocolToJson(readPlantProtocolFile(shipped("tobacco"))), plantProtocolToJson(p));
  EXPECT_EQ(plantProtocolToJson(parsePlantProtocolJson(plantProtocolToJson(p), "again")), plantProtocolToJson(p));
  const auto steps = describeSteps(p);
  ASSERT_EQ(steps.size(), 6u);
  EXPECT_EQ(steps[0], "landmarks · 3 to 64 points on the pot rim (or a board) · stylus");
  EXPECT_EQ(steps[3], "internode (I, one after another) · node · stylus");
  EXPECT_EQ(steps[5],
            "leaf (L, branching from internode) · full: the leaf protocol | quick: base, tip, side | none: a state "
            "(default: every 3rd in full, and the largest)");
}

TEST(PlantProtocol, OtherSpeciesAndBranchedPlantsAreProtocolsToo) {
  const PlantProtocol maize = readPlantProtocolFile(shipped("maize"));
  EXPECT_EQ(maize.entities[0].points, (std::vector<std::string>{"node", "ligule"}));
  EXPECT_EQ(maize.entities[1].leaf->kinds, (std::vector<LeafKind>{LeafKind::Quick, LeafKind::None}));
  EXPECT_EQ(maize.entities[1].leaf->quickPoints, (std::vector<std::string>{"ligule", "tip", "widest"}));
  const PlantProtocol branched = readPlantProtocolFile(shipped("branched"));
  const ProtocolEntity* branch = branched.find("branch");
  ASSERT_NE(branch, nullptr);
  EXPECT_EQ(branch->order, 2);
  EXPECT_EQ(branch->relation, '+');
  EXPECT_EQ(branched.find("branch_leaf")->order, 2);  // a leaf is on its axis' order
  EXPECT_EQ(branched.find("leaf")->leaf->fullEvery, 4);
  // A leaf that cannot be digitized in full has no default for it.
  EXPECT_EQ(describeSteps(branched).back(),
            "branch_leaf (F, branching from branch, axis of order 2) · quick: base, tip, side | none: a state");
}

TEST(PlantProtocol, ABadProtocolIsRefusedNamingTheEntityTheKeyAndWhatToDo) {
  const std::string internode = R"({"name": "internode", "class": "I", "repeat": true, "points": ["node"]})";
  EXPECT_EQ(refusal(withEntities(internode)), "");
  const auto has = [](const std::string& message, const std::string& part) {
    return message.find(part) != std::string::npos;
  };
  // An entity named twice.
  EXPECT_TRUE(has(refusal(withEntities(internode + R"(, {"name": "internode", "class": "J", "parent": "internode"})")),
                  "p.json: entity 2 (internode): the name \"internode\" is already an entity's"));
  // One class per entity; P is the plant's.
  EXPECT_TRUE(has(refusal(withEntities(internode + R"(, {"name": "leaf", "class": "I", "parent": "internode",
                                                          "leaf": {}})")),
                  "entity 2 (leaf) class: \"I\" is internode's already"));
  EXPECT_TRUE(has(refusal(withEntities(R"({"name": "stem", "class": "P", "points": ["node"]})")),
                  "entity 1 (stem) class: must be one capital letter, not P"));
  // Where things hang.
  EXPECT_TRUE(has(refusal(withEntities(internode + R"(, {"name": "leaf", "class": "L", "parent": "petiole",
                                                          "leaf": {}})")),
                  "\"petiole\" is not an entity listed before this one"));
  EXPECT_TRUE(has(refusal(withEntities(internode + R"(, {"name": "leaf", "class": "L", "leaf": {}})")),
                  "entity 2 (leaf): only the first entity starts the plant: give \"parent\""));
  EXPECT_TRUE(has(refusal(withEntities(internode + R"(, {"name": "leaf", "class": "L", "parent": "internode",
                                                          "relation": "<", "leaf": {}})")),
                  "a leaf branches from its node"));
  EXPECT_TRUE(has(refusal(withEntities(internode + R"(, {"name": "leaf", "class": "L", "parent": "internode",
                     "leaf": {}}, {"name": "hair", "class": "H", "parent": "leaf", "points": ["tip"]})")),
                  "nothing hangs on a leaf"));
  EXPECT_TRUE(has(refusal(withEntities(internode + R"(, {"name": "branch", "class": "B", "parent": "internode",
                                                          "relation": "+", "order": 1, "points": ["node"]})")),
                  "entity 2 (branch) order: is 2 by where it hangs"));
  // Points, readings and leaves.
  EXPECT_TRUE(has(refusal(withEntities(R"({"name": "internode", "class": "I", "points": ["node"],
                                           "readings": ["node"]})")),
                  "\"node\" is named twice in this entity"));
  EXPECT_TRUE(has(refusal(withEntities(R"({"name": "internode", "class": "I"})")), "asks for nothing"));
  EXPECT_TRUE(has(refusal(withEntities(R"({"name": "Internode", "class": "I", "points": ["node"]})")),
                  "entity 1 name: must be a word of 1 to 32 lower-case letters"));
  EXPECT_TRUE(has(refusal(withEntities(internode + R"(, {"name": "leaf", "class": "L", "parent": "internode",
                                                          "leaf": {"quick_points": ["base", "tip"]}})")),
                  "a quick leaf takes exactly three points"));
  EXPECT_TRUE(has(refusal(withEntities(internode + R"(, {"name": "leaf", "class": "L", "parent": "internode",
                                                          "leaf": {"kinds": ["full", "sketch"]}})")),
                  "unknown leaf kind \"sketch\": use full, quick or none"));
  EXPECT_TRUE(has(refusal(withEntities(internode + R"(, {"name": "leaf", "class": "L", "parent": "internode",
                                                          "leaf": {"full_every": 0}})")),
                  "full_every: must be a whole number from 1"));
  // The document itself.
  EXPECT_TRUE(has(refusal(R"({"format": "leafdig.markers/1"})"), "this is not a leafdig plant protocol"));
  EXPECT_TRUE(has(refusal(R"({"format": "leafdig.plant-protocol/1", "species": "tobacco"})"),
                  "required key \"entities\" is missing"));
  EXPECT_TRUE(has(refusal(withEntities("")), "entities: must list what is digitized after the collar"));
  EXPECT_TRUE(has(refusal(""), "the file is empty"));
}

}  // namespace
