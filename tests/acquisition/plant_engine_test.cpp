// The plant protocol's engine driven as a technician drives it: landmarks, collar, node by node
// with the stem diameter and each node's leaf (full through the leaf protocol, quick, none),
// the long presses that end the landmarks and the plant, undo across the plant and its leaves,
// refusals in words; then replay of what was decided.
#include "leafdig/acquisition/protocol/plant_engine.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <random>
#include <set>
#include <stdexcept>
#include <string>
#include <variant>

#include "leafdig/acquisition/session/plant_preview.hpp"
#include "leafdig/acquisition/sim/truth.hpp"
#include "leafdig/model/plant/plant_markers.hpp"
#include "leafdig/model/plant/plant_protocol.hpp"
#include "leafdig/model/plant/plant_survey.hpp"
#include "leafdig/model/plant/surveyed_plant.hpp"
#include "leafdig/model/study/synthetic_plant.hpp"
#include "leafdig/model/synth/synthetic_leaf.hpp"

namespace acq = leafdig::acquisition;
namespace m = leafdig::model;
using Kind = acq::PlantDecision::Kind;
using acq::PlantWhat;

namespace {

constexpr std::int64_t kMs = 1'000'000;

m::PlantMarkers samplePlant() {
  return m::readPlantMarkersFile(std::string(LEAFDIG_SOURCE_DIR) + "/data/plants/sample.plant-markers.json");
}

struct Technician {
  explicit Technician(acq::PlantEngine& e, double noiseMm = 0.0) : engine(e), noise(0.0, noiseMm) {}
  acq::PlantEngine& engine;
  std::int64_t t = 0;
  std::mt19937 rng{11};
  std::normal_distribution<double> noise;
  std::vector<acq::PlantDecision> log;  // what a front end would store
  // Where the transmitter is: the digitizer reports a point p of the first position as this * p.
  Eigen::Isometry3d fromFirst = Eigen::Isometry3d::Identity();

  void keep(const acq::PlantDecision& d) {
    if (d.kind != Kind::Rejected && d.kind != Kind::Ignored) log.push_back(d);
  }
  acq::PlantDecision press(const acq::Vec3& p, std::int64_t pressMs = 200) {
    acq::PlantDecision last;
    const auto sample = [&](bool button) {
      acq::StylusInput s;
      s.tNs = (t += 8 * kMs);
      const double e = noise.stddev() > 0 ? 1.0 : 0.0;
      const Eigen::Vector3d q = fromFirst * Eigen::Vector3d(p[0], p[1], p[2]);
      s.positionMm = {q.x() + e * noise(rng), q.y() + e * noise(rng), q.z() + e * noise(rng)};
      s.button = button;
      s.raw = "01 …";
      const auto d = engine.onStylus(s);
      if (d.kind != Kind::Ignored) last = d;
    };
    for (int i = 0; i < 60; ++i) sample(false);
    for (std::int64_t i = 0; i < pressMs / 8; ++i) sample(true);
    sample(false);
    keep(last);
    return last;
  }
  // The button goes down on p; the digitizer resets for `outageMs`; its stream begins again,
  // button up (the driver has seen no press since it connected).
  acq::PlantDecision pressCutByAReconnect(const acq::Vec3& p, std::int64_t outageMs) {
    acq::PlantDecision last;
    const auto sample = [&](bool button, bool streamBegins) {
      acq::StylusInput s;
      s.tNs = (t += 8 * kMs);
      s.positionMm = p;
      s.button = button;
      s.raw = "01 …";
      s.streamBegins = streamBegins;
      const auto d = engine.onStylus(s);
      if (d.kind != Kind::Ignored) last = d;
    };
    for (int i = 0; i < 60; ++i) sample(false, false);
    for (int i = 0; i < 10; ++i) sample(true, false);
    t += outageMs * kMs;
    sample(false, true);
    keep(last);
    return last;
  }
  acq::PlantDecision read(double mm) {
    const auto d = engine.onCaliper({t += 500 * kMs, mm, "+" + std::to_string(mm) + "\r"});
    keep(d);
    return d;
  }
  acq::PlantDecision end() {
    const auto d = engine.end();
    keep(d);
    return d;
  }
  acq::PlantDecision undo() {
    const auto d = engine.undo();
    keep(d);
    return d;
  }
  acq::PlantDecision choose(int node, acq::LeafChoice c) {
    const auto d = engine.chooseLeaf(node, c);
    keep(d);
    return d;
  }
  acq::PlantDecision branch(int from) {
    const auto d = engine.branch(from);
    keep(d);
    return d;
  }

  // One step as the plant-markers document says; false when a press or reading was refused.
  bool act(const m::PlantMarkers& plant, std::string* why = nullptr) {
    const acq::PlantStep s = engine.step();
    acq::PlantDecision d;
    if (s.what == PlantWhat::Point && s.part == 1 && s.index <= static_cast<int>(plant.nodes.size())) {
      // Where the node hangs first: a branch begins (from a node of the stem), or ends.
      if (const auto place = acq::plantPlacementTruth(plant, s.index, engine.link(s.index))) {
        d = place->relation == '+' ? branch(place->parent) : end();
        if (d.kind == Kind::Rejected) return why && (*why = d.reason, false);
      }
      const acq::LeafChoice wanted = acq::plantChoiceTruth(plant, s.index);
      if (!(engine.choiceFor(s.index) == wanted)) {
        d = choose(s.index, wanted);
        if (d.kind == Kind::Rejected) return why && (*why = d.reason, false);
      }
    }
    const bool reading = s.what == PlantWhat::CollarDiameter || s.what == PlantWhat::Reading ||
                         (s.what == PlantWhat::Leaf && !acq::isStylusItem(s.leaf.what));
    if (reading) {
      d = read(acq::plantReadingTruth(plant, s));
    } else if (s.what == PlantWhat::Leaf && s.leaf.what == acq::What::Marker && s.leaf.col == 1 &&
               s.leaf.row > static_cast<int>(acq::plantLeafTruth(plant, s.index)->rows.size())) {
      d = press({0, 0, 0}, 1500);  // the long press that ends the rows
    } else if (const auto p = acq::plantPointTruth(plant, s)) {
      d = press(*p);
    } else {
      d = press({0, 0, 0}, 1500);  // the long press that ends the landmarks or the plant
    }
    if (d.kind == Kind::Rejected && why) *why = d.reason;
    return d.kind != Kind::Rejected;
  }
  void captureAll(const m::PlantMarkers& plant) {
    for (int guard = 0; guard < 2000 && !engine.complete(); ++guard) {
      std::string why;
      ASSERT_TRUE(act(plant, &why)) << why << " at " << engine.prompt();
    }
    ASSERT_TRUE(engine.complete());
  }
};

void expectSamePoints(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double tol, const std::string& what) {
  EXPECT_LT((a - b).norm(), tol) << what;
}

}  // namespace

TEST(PlantEngine, TakesASampledPlantNodeByNodeAndGivesBackWhatWasDigitized) {
  const m::PlantMarkers truth = samplePlant();
  acq::PlantEngine engine(m::defaultPlantProtocol());
  Technician tech{engine};
  EXPECT_EQ(engine.prompt(), "Landmark 1 · a mark on the pot rim (or the board)");
  tech.captureAll(truth);
  EXPECT_EQ(engine.prompt(), "Plant complete");
  EXPECT_EQ(engine.nodes(), static_cast<int>(truth.nodes.size()));

  const m::PlantMarkers got = engine.captured(truth.plant);
  ASSERT_EQ(got.landmarksMm.size(), truth.landmarksMm.size());
  for (std::size_t i = 0; i < got.landmarksMm.size(); ++i)
    expectSamePoints(got.landmarksMm[i], truth.landmarksMm[i], 1e-9, "landmark " + std::to_string(i + 1));
  expectSamePoints(got.collarMm, truth.collarMm, 1e-9, "collar");
  EXPECT_DOUBLE_EQ(got.collarDiameterMm, truth.collarDiameterMm);
  ASSERT_EQ(got.nodes.size(), truth.nodes.size());
  for (std::size_t i = 0; i < got.nodes.size(); ++i) {
    const std::string node = "node " + std::to_string(i + 1);
    expectSamePoints(got.nodes[i].pointMm, truth.nodes[i].pointMm, 1e-9, node);
    EXPECT_DOUBLE_EQ(got.nodes[i].diameterMm, truth.nodes[i].diameterMm) << node;
    EXPECT_EQ(got.nodes[i].state, truth.nodes[i].state) << node;
    EXPECT_EQ(got.nodes[i].leaf.index(), truth.nodes[i].leaf.index()) << node;
    // The leaf's type, as the technician chose it (the sample's quick leaves are "lower").
    if (const auto* quick = std::get_if<m::QuickLeaf>(&truth.nodes[i].leaf)) {
      ASSERT_TRUE(std::holds_alternative<m::QuickLeaf>(got.nodes[i].leaf)) << node;
      EXPECT_EQ(std::get<m::QuickLeaf>(got.nodes[i].leaf).type, quick->type) << node;
      EXPECT_FALSE(quick->type.empty()) << node;
    }
  }
  // The survey of what the engine took is the survey of the file: same frame, same angles.
  const m::PlantSurvey a = m::surveyPlant(got), b = m::surveyPlant(truth);
  ASSERT_EQ(a.leaves.size(), b.leaves.size());
  for (std::size_t i = 0; i < a.leaves.size(); ++i) {
    EXPECT_EQ(a.leaves[i].kind, b.leaves[i].kind);
    ASSERT_EQ(a.leaves[i].pose.has_value(), b.leaves[i].pose.has_value());
    if (a.leaves[i].pose) {
      EXPECT_NEAR(a.leaves[i].pose->azimuthDeg, b.leaves[i].pose->azimuthDeg, 1e-6);
      EXPECT_NEAR(a.leaves[i].pose->inclinationDeg, b.leaves[i].pose->inclinationDeg, 1e-6);
    }
    if (a.leaves[i].areaMm2) {
      ASSERT_TRUE(b.leaves[i].areaMm2.has_value());
      EXPECT_NEAR(*a.leaves[i].areaMm2, *b.leaves[i].areaMm2, 1e-6 * *b.leaves[i].areaMm2);
    }
  }

  // Replay: the stored decisions rebuild the same plant.
  acq::PlantEngine again(m::defaultPlantProtocol());
  for (const auto& d : tech.log) again.apply(d);
  EXPECT_TRUE(again.complete());
  EXPECT_EQ(m::plantMarkersToJson(again.captured(truth.plant)), m::plantMarkersToJson(got));
}

TEST(PlantEngine, ASyntheticPlantAtARandomTransmitterPoseIsTakenWholeAndSurveysAsItsFileDoes) {
  for (const std::uint64_t seed : {3U, 8U}) {
    m::SyntheticPlantSpec spec;
    spec.nodes = 12;
    spec.seed = seed;
    const m::SyntheticPlant plant = m::synthesizePlant(spec);
    acq::PlantEngine engine(m::defaultPlantProtocol());
    Technician tech{engine};
    tech.captureAll(plant.markers);
    const m::PlantSurvey a = m::surveyPlant(engine.captured(plant.markers.plant));
    const m::PlantSurvey b = m::surveyPlant(plant.markers);
    ASSERT_EQ(a.nodes.size(), b.nodes.size());
    for (std::size_t i = 0; i < a.nodes.size(); ++i)
      expectSamePoints(a.nodes[i].pointMm, b.nodes[i].pointMm, 1e-6, "node " + std::to_string(i + 1));
    ASSERT_EQ(a.leaves.size(), b.leaves.size());
    int full = 0;
    for (std::size_t i = 0; i < a.leaves.size(); ++i) {
      EXPECT_EQ(a.leaves[i].kind, b.leaves[i].kind);
      EXPECT_EQ(a.leaves[i].state, b.leaves[i].state);
      if (a.leaves[i].areaMm2) {
        ++full;
        EXPECT_NEAR(*a.leaves[i].areaMm2, *b.leaves[i].areaMm2, 1e-6 * *b.leaves[i].areaMm2);
      }
    }
    int inFile = 0;
    for (const m::PlantNode& n : plant.markers.nodes) inFile += std::holds_alternative<m::MarkerSet>(n.leaf);
    EXPECT_EQ(full, inFile) << "seed " << seed;
    EXPECT_GE(full, 3) << "seed " << seed;
  }
}

TEST(PlantEngine, ANoisyStylusStillGivesEveryPointWithinItsNoise) {
  const m::PlantMarkers truth = samplePlant();
  acq::PlantEngine engine(m::defaultPlantProtocol());
  Technician tech{engine, 0.1};
  tech.captureAll(truth);
  const m::PlantMarkers got = engine.captured(truth.plant);
  ASSERT_EQ(got.nodes.size(), truth.nodes.size());
  // The mean of ~85 samples of σ 0.1 mm per axis: well within 0.1 mm.
  for (std::size_t i = 0; i < got.nodes.size(); ++i)
    expectSamePoints(got.nodes[i].pointMm, truth.nodes[i].pointMm, 0.1, "node " + std::to_string(i + 1));
}

TEST(PlantEngine, PromptsSayWhereOnThePlantAndWithWhichTool) {
  const m::PlantMarkers truth = samplePlant();
  acq::PlantEngine engine(m::defaultPlantProtocol());
  Technician tech{engine};
  std::vector<std::string> prompts;
  for (int guard = 0; guard < 400 && !engine.complete(); ++guard) {
    prompts.push_back(engine.prompt());
    ASSERT_TRUE(tech.act(truth));
  }
  const auto seen = [&](const std::string& p) { return std::find(prompts.begin(), prompts.end(), p) != prompts.end(); };
  EXPECT_TRUE(seen("Collar · the stem at soil level"));
  EXPECT_TRUE(seen("Collar · stem diameter with the caliper"));
  EXPECT_TRUE(seen("Node 1 · node on the stem"));
  EXPECT_TRUE(seen("Node 5 · stem diameter with the caliper"));
  EXPECT_TRUE(seen("Node 3 · quick leaf · base (where the blade joins the petiole)"));
  EXPECT_TRUE(seen("Node 3 · quick leaf · side (the widest point of one margin)"));
  EXPECT_TRUE(seen("Node 2 · leaf · Tip: touch the leaf tip and press"));
  EXPECT_TRUE(seen("Landmark 4 · a mark on the pot rim (or the board)  (or hold the button to end the landmarks)"));
  EXPECT_TRUE(seen("Node 2 · node on the stem  (or hold the button to end the plant)"));
}

TEST(PlantEngine, RefusesWhatWouldSpoilThePlantFrameOrALeafsPoseInWords) {
  acq::PlantEngine engine(m::defaultPlantProtocol());
  Technician tech{engine};
  // Three landmarks on one line: ending them is refused, naming the farthest.
  EXPECT_EQ(tech.press({0, 0, 0}).kind, Kind::Accepted);
  EXPECT_EQ(tech.press({50, 0, 0}).kind, Kind::Accepted);
  EXPECT_EQ(tech.press({100, 1, 0}).kind, Kind::Accepted);
  const auto line = tech.press({0, 0, 0}, 1500);
  ASSERT_EQ(line.kind, Kind::Rejected);
  EXPECT_NE(line.reason.find("nearly on one line"), std::string::npos) << line.reason;
  EXPECT_NE(line.reason.find("undo to take a landmark again"), std::string::npos) << line.reason;
  // Two landmarks: too few to end.
  EXPECT_EQ(tech.undo().kind, Kind::Undone);
  EXPECT_EQ(tech.undo().kind, Kind::Undone);
  const auto few = tech.end();
  EXPECT_EQ(few.kind, Kind::Rejected);
  EXPECT_NE(few.reason.find("at least 3 landmarks (1 taken)"), std::string::npos) << few.reason;
  EXPECT_EQ(tech.press({100, 0, 0}).kind, Kind::Accepted);
  EXPECT_EQ(tech.press({0, 100, 0}).kind, Kind::Accepted);
  EXPECT_EQ(tech.press({0, 0, 0}, 1500).kind, Kind::LandmarksEnded);
  // A caliper reading when the stylus is asked for; the collar; a diameter of 0.
  const auto early = tech.read(9.0);
  EXPECT_EQ(early.kind, Kind::Rejected);
  EXPECT_NE(early.reason.find("a caliper reading now? Collar · the stem at soil level first"), std::string::npos);
  EXPECT_EQ(tech.press({30, 30, 0}).kind, Kind::Accepted);
  const auto zero = tech.read(0.0);
  EXPECT_EQ(zero.kind, Kind::Rejected);
  EXPECT_NE(zero.reason.find("stem diameter of 0.000 mm is outside"), std::string::npos) << zero.reason;
  EXPECT_EQ(tech.read(12.0).kind, Kind::Accepted);
  // The plant cannot end before its first node; node 1 in the rim's plane is refused.
  EXPECT_EQ(tech.end().kind, Kind::Rejected);
  const auto flat = tech.press({40, 30, 0});
  EXPECT_EQ(flat.kind, Kind::Rejected);
  EXPECT_NE(flat.reason.find("lies in the landmarks' plane"), std::string::npos) << flat.reason;
  EXPECT_EQ(tech.press({30, 30, 60}).kind, Kind::Accepted);
  EXPECT_EQ(tech.read(10.0).kind, Kind::Accepted);
  // Node 1's leaf is quick by default (full every 3rd): a tip on the base is refused.
  ASSERT_EQ(engine.step().what, PlantWhat::QuickPoint);
  EXPECT_EQ(tech.press({35, 30, 62}).kind, Kind::Accepted);
  tech.t += 2000 * kMs;  // not a double press: a tip pressed on purpose next to the base
  const auto onBase = tech.press({35.8, 30, 62});
  ASSERT_EQ(onBase.kind, Kind::Rejected);
  EXPECT_NE(onBase.reason.find("base and tip"), std::string::npos) << onBase.reason;
  // A leaf with points taken keeps its kind until they are undone.
  const auto change = tech.choose(1, {m::LeafKind::Full, m::LeafState::Alive, {}});
  EXPECT_EQ(change.kind, Kind::Rejected);
  EXPECT_EQ(change.reason, "node 1's leaf has points taken as a quick leaf: undo them first");
  const auto later = tech.choose(3, {m::LeafKind::None, m::LeafState::Alive, {}});
  EXPECT_EQ(later.kind, Kind::Rejected);
  EXPECT_EQ(later.reason, "node 3 is not taken yet: choose for node 2 or one before");
}

TEST(PlantEngine, UndoGoesBackThroughTheLeafAndThePlantInTheOrderTheyWereTaken) {
  acq::PlantEngine engine(m::defaultPlantProtocol());
  Technician tech{engine};
  for (const acq::Vec3& p : {acq::Vec3{100, 0, 0}, acq::Vec3{0, 100, 0}, acq::Vec3{-100, 0, 0}})
    ASSERT_EQ(tech.press(p).kind, Kind::Accepted);
  ASSERT_EQ(tech.end().kind, Kind::LandmarksEnded);
  ASSERT_EQ(tech.press({0, 0, 0}).kind, Kind::Accepted);
  ASSERT_EQ(tech.read(12).kind, Kind::Accepted);
  ASSERT_EQ(tech.press({0, 0, 40}).kind, Kind::Accepted);
  // Node 1 in full, chosen now; then its diameter; the leaf has the stylus.
  const auto chosen = tech.choose(1, {m::LeafKind::Full, m::LeafState::Yellow, {}});
  ASSERT_EQ(chosen.kind, Kind::LeafChosen);
  EXPECT_EQ(chosen.previous.kind, m::LeafKind::Quick);
  ASSERT_EQ(tech.read(10).kind, Kind::Accepted);
  ASSERT_EQ(engine.step().what, PlantWhat::Leaf);
  EXPECT_EQ(engine.prompt(), "Node 1 · leaf · Tip: touch the leaf tip and press");
  const auto tip = tech.press({150, 0, 50});
  ASSERT_EQ(tip.kind, Kind::Leaf);
  EXPECT_EQ(tip.node, 1);
  EXPECT_EQ(tip.leaf.kind, acq::Decision::Kind::Accepted);
  ASSERT_NE(engine.leaf(1), nullptr);
  EXPECT_EQ(engine.leaf(1)->items().size(), 1U);
  // A very long press undoes the leaf's tip (the leaf's own undo)…
  const auto undoTip = tech.press({150, 0, 50}, 3500);
  EXPECT_EQ(undoTip.kind, Kind::Leaf);
  EXPECT_EQ(undoTip.leaf.kind, acq::Decision::Kind::Undone);
  EXPECT_TRUE(engine.leaf(1)->items().empty());
  // …and again, with nothing of the leaf left, the plant's last action: the diameter.
  const auto undoDiameter = tech.press({150, 0, 50}, 3500);
  EXPECT_EQ(undoDiameter.kind, Kind::Undone);
  EXPECT_EQ(undoDiameter.item.what, PlantWhat::Reading);
  EXPECT_EQ(engine.step().what, PlantWhat::Reading);
  // Then the choice, then node 1's point.
  const auto undoChoice = tech.undo();
  EXPECT_EQ(undoChoice.kind, Kind::ChoiceUndone);
  EXPECT_EQ(engine.choiceFor(1).kind, m::LeafKind::Quick);
  const auto undoNode = tech.undo();
  EXPECT_EQ(undoNode.item.what, PlantWhat::Point);
  EXPECT_EQ(engine.nodes(), 0);

  // Everything the technician did, replayed, is where the engine is now.
  acq::PlantEngine replayed(m::defaultPlantProtocol());
  for (const auto& d : tech.log) replayed.apply(d);
  EXPECT_EQ(replayed.step(), engine.step());
  EXPECT_EQ(replayed.items().size(), engine.items().size());
}

// A press the digitizer's reconnect cut is refused in words — on the plant and inside a full
// leaf — and not taken for the very long press that undoes, as its length would say.
TEST(PlantEngine, APressCutByTheDigitizersReconnectIsRefusedNotTakenForAnUndo) {
  acq::PlantEngine engine(m::defaultPlantProtocol());
  Technician tech{engine};
  ASSERT_EQ(tech.press({100, 0, 0}).kind, Kind::Accepted);
  const auto cut = tech.pressCutByAReconnect({0, 100, 0}, 20'000);
  EXPECT_EQ(cut.kind, Kind::Rejected);
  EXPECT_NE(cut.reason.find("press again"), std::string::npos) << cut.reason;
  EXPECT_EQ(engine.items().size(), 1U);  // the first landmark is still there
  ASSERT_EQ(tech.press({0, 100, 0}).kind, Kind::Accepted);
  ASSERT_EQ(tech.press({-100, 0, 0}).kind, Kind::Accepted);
  ASSERT_EQ(tech.end().kind, Kind::LandmarksEnded);
  ASSERT_EQ(tech.press({0, 0, 0}).kind, Kind::Accepted);
  ASSERT_EQ(tech.read(12).kind, Kind::Accepted);
  ASSERT_EQ(tech.press({0, 0, 40}).kind, Kind::Accepted);
  ASSERT_EQ(tech.choose(1, {m::LeafKind::Full, m::LeafState::Alive, {}}).kind, Kind::LeafChosen);
  ASSERT_EQ(tech.read(10).kind, Kind::Accepted);
  ASSERT_EQ(tech.press({150, 0, 50}).kind, Kind::Leaf);  // the leaf's tip
  const std::size_t plantItems = engine.items().size();
  const auto inLeaf = tech.pressCutByAReconnect({150, 0, 30}, 20'000);
  EXPECT_EQ(inLeaf.kind, Kind::Rejected);
  EXPECT_EQ(inLeaf.leaf.kind, acq::Decision::Kind::Rejected);
  EXPECT_NE(inLeaf.reason.find("node 1 leaf: the digitizer connected again"), std::string::npos) << inLeaf.reason;
  ASSERT_NE(engine.leaf(1), nullptr);
  EXPECT_EQ(engine.leaf(1)->items().size(), 1U);  // the tip is kept
  EXPECT_EQ(engine.items().size(), plantItems);
}

TEST(PlantEngine, AnyPointOrReadingIsRetakenWhereItStandsAndReplaysToTheSamePlant) {
  const m::PlantMarkers plant = samplePlant();
  acq::PlantEngine engine(m::defaultPlantProtocol());
  Technician tech{engine};
  tech.captureAll(plant);
  const m::PlantMarkers before = engine.captured(plant.plant);
  const auto retake = [&](PlantWhat w, int index, int part) {
    const auto d = engine.retake(w, index, part);
    tech.keep(d);
    return d;
  };
  const auto asAt = [](const Eigen::Vector3d& p) { return acq::Vec3{p.x(), p.y(), p.z()}; };

  // Nothing there, or not an item: refused in words, nothing changes.
  EXPECT_NE(retake(PlantWhat::Landmark, 9, 0).reason.find("nothing was captured as landmark 9"), std::string::npos);
  EXPECT_NE(retake(PlantWhat::Reading, 7, 1).reason.find("nothing was captured as node 7 reading 1"),
            std::string::npos);
  EXPECT_EQ(retake(PlantWhat::Leaf, 2, 0).kind, Kind::Rejected);
  EXPECT_TRUE(engine.complete());

  // A landmark: out, asked for again in words, replaced at its number (landmark 1 stays first).
  const auto out = retake(PlantWhat::Landmark, 2, 0);
  ASSERT_EQ(out.kind, Kind::RetakeStarted);
  EXPECT_EQ(out.item.index, 2);
  EXPECT_FALSE(engine.complete());
  EXPECT_EQ(engine.step(), (acq::PlantStep{PlantWhat::Landmark, 2, 0, {}}));
  EXPECT_EQ(engine.prompt(), "Retake · Landmark 2 · a mark on the pot rim (or the board)");
  EXPECT_EQ(retake(PlantWhat::Collar, 0, 0).reason, "finish the retake in progress first (or undo it)");
  EXPECT_NE(tech.end().reason.find("finish the retake first"), std::string::npos);
  const Eigen::Vector3d moved = plant.landmarksMm[1] + Eigen::Vector3d(1.5, -0.5, 0.0);
  ASSERT_EQ(tech.press(asAt(moved)).kind, Kind::Accepted);
  EXPECT_TRUE(engine.complete());
  m::PlantMarkers now = engine.captured(plant.plant);
  ASSERT_EQ(now.landmarksMm.size(), before.landmarksMm.size());
  EXPECT_LT((now.landmarksMm[1] - moved).norm(), 1e-9);
  EXPECT_EQ(now.landmarksMm[0], before.landmarksMm[0]);
  EXPECT_EQ(now.landmarksMm[3], before.landmarksMm[3]);

  // A landmark that would spoil the plant frame (on top of landmark 1) is refused in words;
  // undo puts the old one back.
  ASSERT_EQ(retake(PlantWhat::Landmark, 3, 0).kind, Kind::RetakeStarted);
  const auto close = tech.press(asAt(now.landmarksMm[0] + Eigen::Vector3d(0.5, 0, 0)));
  ASSERT_EQ(close.kind, Kind::Rejected);
  EXPECT_NE(close.reason.find("landmark 1"), std::string::npos) << close.reason;
  EXPECT_NE(close.reason.find("undo to put the old one back"), std::string::npos) << close.reason;
  EXPECT_TRUE(engine.retaking());
  EXPECT_EQ(tech.undo().kind, Kind::RetakeCancelled);
  EXPECT_TRUE(engine.complete());

  // A node's stem diameter, a node's point, a quick leaf's tip, a full leaf's marker.
  ASSERT_EQ(retake(PlantWhat::Reading, 3, 1).kind, Kind::RetakeStarted);
  EXPECT_EQ(engine.prompt().rfind("Retake · Node 3 · stem", 0), 0U) << engine.prompt();
  EXPECT_EQ(tech.press(asAt(plant.nodes[2].pointMm)).kind, Kind::Rejected);  // a press is not a reading
  ASSERT_EQ(tech.read(16.4).kind, Kind::Accepted);
  ASSERT_EQ(retake(PlantWhat::Point, 4, 1).kind, Kind::RetakeStarted);
  const Eigen::Vector3d node4 = plant.nodes[3].pointMm + Eigen::Vector3d(0, 0, 2);
  ASSERT_EQ(tech.press(asAt(node4)).kind, Kind::Accepted);
  ASSERT_EQ(retake(PlantWhat::QuickPoint, 3, 2).kind, Kind::RetakeStarted);
  const auto& quick = std::get<m::QuickLeaf>(plant.nodes[2].leaf);
  const Eigen::Vector3d tip3 = quick.tipMm + Eigen::Vector3d(3, 0, 0);
  ASSERT_EQ(tech.press(asAt(tip3)).kind, Kind::Accepted);
  const auto leafOut = engine.retakeLeaf(2, acq::What::Marker, 1, 3);
  tech.keep(leafOut);
  ASSERT_EQ(leafOut.kind, Kind::Leaf);
  EXPECT_EQ(leafOut.leaf.kind, acq::Decision::Kind::RetakeStarted);
  EXPECT_EQ(engine.step().what, PlantWhat::Leaf);
  EXPECT_EQ(engine.step().leaf, (acq::Step{acq::What::Marker, 1, 3}));
  EXPECT_EQ(engine.prompt().rfind("Node 2 · leaf · Retake · Row 1 · point 3", 0), 0U) << engine.prompt();
  const Eigen::Vector3d marker =
      std::get<m::MarkerSet>(plant.nodes[1].leaf).rows[0].pointsMm[2] + Eigen::Vector3d(0, 1, 0);
  ASSERT_EQ(tech.press(asAt(marker)).kind, Kind::Leaf);
  EXPECT_NE(engine.retakeLeaf(4, acq::What::Tip, 0, 0).reason.find("node 4 has no full leaf"), std::string::npos);
  EXPECT_TRUE(engine.complete());

  now = engine.captured(plant.plant);
  EXPECT_DOUBLE_EQ(now.nodes[2].diameterMm, 16.4);
  EXPECT_LT((now.nodes[3].pointMm - node4).norm(), 1e-9);
  EXPECT_LT((std::get<m::QuickLeaf>(now.nodes[2].leaf).tipMm - tip3).norm(), 1e-9);
  EXPECT_LT((std::get<m::MarkerSet>(now.nodes[1].leaf).rows[0].pointsMm[2] - marker).norm(), 1e-9);
  EXPECT_EQ(now.landmarksMm[2], before.landmarksMm[2]);  // put back as it was

  // Undo after a retake takes the new item out, and the step asks for it again at its number.
  ASSERT_EQ(retake(PlantWhat::Landmark, 1, 0).kind, Kind::RetakeStarted);
  ASSERT_EQ(tech.press(asAt(plant.landmarksMm[0])).kind, Kind::Accepted);
  const auto undone = tech.undo();
  ASSERT_EQ(undone.kind, Kind::Undone);
  EXPECT_EQ(undone.item.index, 1);
  EXPECT_EQ(engine.step(), (acq::PlantStep{PlantWhat::Landmark, 1, 0, {}}));
  EXPECT_NE(tech.end().reason.find("landmark 1 was taken out"), std::string::npos);
  ASSERT_EQ(tech.press(asAt(plant.landmarksMm[0])).kind, Kind::Accepted);
  EXPECT_TRUE(engine.complete());
  EXPECT_LT((engine.captured(plant.plant).landmarksMm[0] - plant.landmarksMm[0]).norm(), 1e-9);

  // Replayed from what was decided, the engine is where this one is, item for item.
  acq::PlantEngine replayed(m::defaultPlantProtocol());
  for (const auto& d : tech.log) replayed.apply(d);
  EXPECT_EQ(replayed.step(), engine.step());
  ASSERT_EQ(replayed.items().size(), engine.items().size());
  const m::PlantMarkers a = engine.captured(plant.plant), b = replayed.captured(plant.plant);
  EXPECT_EQ(a.landmarksMm, b.landmarksMm);
  for (std::size_t k = 0; k < a.nodes.size(); ++k) {
    EXPECT_EQ(a.nodes[k].pointMm, b.nodes[k].pointMm) << k;
    EXPECT_EQ(a.nodes[k].diameterMm, b.nodes[k].diameterMm) << k;
  }
  const auto& ra = std::get<m::MarkerSet>(a.nodes[1].leaf).rows;
  const auto& rb = std::get<m::MarkerSet>(b.nodes[1].leaf).rows;
  ASSERT_EQ(ra.size(), rb.size());
  for (std::size_t k = 0; k < ra.size(); ++k) EXPECT_EQ(ra[k].pointsMm, rb[k].pointsMm) << k;
}

TEST(PlantEngine, EveryThirdLeafIsFullByDefaultAndTheTechnicianDecidesPerNode) {
  acq::PlantEngine engine(m::defaultPlantProtocol());
  EXPECT_EQ(engine.choiceFor(1).kind, m::LeafKind::Quick);
  EXPECT_EQ(engine.choiceFor(3).kind, m::LeafKind::Full);
  EXPECT_EQ(engine.choiceFor(6).kind, m::LeafKind::Full);
  m::PlantProtocol maize =
      m::readPlantProtocolFile(std::string(LEAFDIG_SOURCE_DIR) + "/data/protocols/maize.plant-protocol.json");
  acq::PlantEngine maizeEngine(maize);
  EXPECT_EQ(maizeEngine.choiceFor(3).kind, m::LeafKind::Quick);  // maize takes no full leaves
  const auto full = maizeEngine.chooseLeaf(1, {m::LeafKind::Full, m::LeafState::Alive, {}});
  EXPECT_EQ(full.kind, Kind::Rejected);
  EXPECT_EQ(full.reason, "the protocol does not take full leaves");
  // A leaf's type (for its shape from the organ library) is part of the choice, a short word.
  const auto typed = engine.chooseLeaf(1, {m::LeafKind::Quick, m::LeafState::Alive, "upper"});
  EXPECT_EQ(typed.kind, Kind::LeafChosen);
  EXPECT_EQ(engine.choiceFor(1).type, "upper");
  const auto tooLong = engine.chooseLeaf(1, {m::LeafKind::Quick, m::LeafState::Alive, std::string(65, 'x')});
  EXPECT_EQ(tooLong.kind, Kind::Rejected);
  EXPECT_NE(tooLong.reason.find("a leaf type is a short word"), std::string::npos) << tooLong.reason;
  EXPECT_EQ(engine.choiceFor(1).type, "upper");
}

TEST(PlantEngine, AMaizeProtocolAsksForTheLiguleAfterTheNodeAndKeepsTheNodeAsTheStemsPoint) {
  const m::PlantProtocol maize =
      m::readPlantProtocolFile(std::string(LEAFDIG_SOURCE_DIR) + "/data/protocols/maize.plant-protocol.json");
  acq::PlantEngine engine(maize);
  Technician tech{engine};
  for (const acq::Vec3& p : {acq::Vec3{100, 0, 0}, acq::Vec3{0, 100, 0}, acq::Vec3{-100, 0, 0}})
    ASSERT_EQ(tech.press(p).kind, Kind::Accepted);
  ASSERT_EQ(engine.end().kind, Kind::LandmarksEnded);
  ASSERT_EQ(tech.press({0, 0, 0}).kind, Kind::Accepted);
  ASSERT_EQ(tech.read(20).kind, Kind::Accepted);
  ASSERT_EQ(tech.press({0, 0, 50}).kind, Kind::Accepted);
  EXPECT_EQ(engine.prompt(), "Node 1 · ligule on the stem");
  ASSERT_EQ(tech.press({2, 0, 120}).kind, Kind::Accepted);
  EXPECT_EQ(engine.prompt(), "Node 1 · stem diameter with the caliper");
  ASSERT_EQ(tech.read(18).kind, Kind::Accepted);
  EXPECT_EQ(engine.prompt(), "Node 1 · quick leaf · ligule (where the blade joins the petiole)");
  const m::PlantMarkers got = engine.captured("m1");
  ASSERT_EQ(got.nodes.size(), 1U);
  expectSamePoints(got.nodes[0].pointMm, {0, 0, 50}, 1e-9, "node 1");
}

TEST(PlantEngine, AProtocolOfDeeperBranchesOrTwoStemsIsRefusedInWords) {
  const auto refusal = [](const std::string& entities) {
    try {
      acq::PlantEngine engine(m::parsePlantProtocolJson(
          R"({"format": "leafdig.plant-protocol/1", "species": "x", "entities": [)" + entities + "]}", "p.json"));
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("taken");
  };
  const std::string stem = R"({"name": "internode", "class": "I", "repeat": true, "points": ["node"]})";
  const std::string branch =
      R"({"name": "branch", "class": "B", "parent": "internode", "relation": "+", "repeat": true, "points": ["node"]})";
  EXPECT_NE(
      refusal(
          stem + "," + branch +
          R"(, {"name": "twig", "class": "T", "parent": "branch", "relation": "+", "repeat": true, "points": ["node"]})")
          .find("\"twig\" is an axis of order 3: plant capture takes the main stem and branches from it"),
      std::string::npos);
  EXPECT_NE(
      refusal(stem + R"(, {"name": "shoot", "class": "S", "parent": "internode", "repeat": true, "points": ["node"]})")
          .find("two stem entities (\"internode\" and \"shoot\")"),
      std::string::npos);
  EXPECT_NE(refusal(stem + "," + branch + R"(, {"name": "leaf", "class": "L", "parent": "branch", "leaf": {}})" +
                    R"(, {"name": "leaflet", "class": "F", "parent": "branch", "leaf": {}})")
                .find("two leaf entities (\"leaf\" and \"leaflet\") on its branch nodes"),
            std::string::npos);
  EXPECT_EQ(refusal(stem + "," + branch), "taken");
}

// A branched plant (a sucker at node 2: nodes 3 and 4 on it, then the stem again after node 2)
// taken with the branched protocol: the technician starts the branch from node 2, ends it with
// the long press, and the plant comes back exactly as its file says, branch leaves as the
// branch's leaf entity takes them; the prompts say where on the plant; replay gives the same.
TEST(PlantEngine, ABranchIsStartedFromAStemNodeEndedByTheLongPressAndGivenBackWhereItHangs) {
  const m::PlantMarkers truth =
      m::readPlantMarkersFile(std::string(LEAFDIG_SOURCE_DIR) + "/data/plants/branched.plant-markers.json");
  const m::PlantProtocol protocol =
      m::readPlantProtocolFile(std::string(LEAFDIG_SOURCE_DIR) + "/data/protocols/branched.plant-protocol.json");
  acq::PlantEngine engine(protocol);
  Technician tech{engine};
  std::set<std::string> prompts;  // as the technician saw them between actions
  for (int guard = 0; guard < 3000 && !engine.complete(); ++guard) {
    std::string why;
    ASSERT_TRUE(tech.act(truth, &why)) << why << " at " << engine.prompt();
    prompts.insert(engine.prompt());
  }
  ASSERT_TRUE(engine.complete());
  for (const char* said :
       {"Node 3 · branch diameter with the caliper",
        "Node 4 · node on the branch  (or hold the button to end the branch)",
        "Node 5 · stem diameter with the caliper", "Node 6 · node on the stem  (or hold the button to end the plant)"})
    EXPECT_TRUE(prompts.count(said)) << said;
  const m::PlantMarkers got = engine.captured(truth.plant);
  ASSERT_EQ(got.nodes.size(), truth.nodes.size());
  for (std::size_t i = 0; i < got.nodes.size(); ++i) {
    SCOPED_TRACE("node " + std::to_string(i + 1));
    EXPECT_EQ(got.nodes[i].after, truth.nodes[i].after);
    EXPECT_EQ(got.nodes[i].branchesFrom, truth.nodes[i].branchesFrom);
    expectSamePoints(got.nodes[i].pointMm, truth.nodes[i].pointMm, 1e-9, "point");
    EXPECT_EQ(got.nodes[i].leaf.index(), truth.nodes[i].leaf.index());
  }
  // The branch's nodes took the branch entity's reading; the stem's its own.
  EXPECT_DOUBLE_EQ(got.nodes[2].diameterMm, 9.0);
  const std::vector<acq::PlantDecision> placed = [&] {
    std::vector<acq::PlantDecision> out;
    for (const acq::PlantDecision& d : tech.log)
      if (d.kind == Kind::NodePlaced) out.push_back(d);
    return out;
  }();
  ASSERT_EQ(placed.size(), 2U);
  EXPECT_EQ(placed[0].node, 3);
  EXPECT_EQ(placed[0].place, (acq::NodePlace{2, '+'}));
  EXPECT_EQ(placed[1].node, 5);
  EXPECT_EQ(placed[1].place, (acq::NodePlace{2, '<'}));  // the long press ended the branch
  // Replaying the decisions rebuilds the same plant.
  acq::PlantEngine replayed(protocol);
  for (const acq::PlantDecision& d : tech.log) replayed.apply(d);
  EXPECT_EQ(m::plantMarkersToJson(replayed.captured(truth.plant)), m::plantMarkersToJson(got));
  // Its survey hangs the branch where the file does.
  const m::PlantSurvey survey = m::surveyPlant(got);
  EXPECT_EQ(survey.nodes[2].link.relation, '+');
  EXPECT_EQ(survey.nodes[4].link.parent, 2);
}

TEST(PlantEngine, ABranchIsPlacedOnlyWhereItCanHangAndUndoneLikeAnyDecision) {
  const m::PlantMarkers truth =
      m::readPlantMarkersFile(std::string(LEAFDIG_SOURCE_DIR) + "/data/plants/branched.plant-markers.json");
  {  // A protocol without branches says so.
    acq::PlantEngine plain(m::defaultPlantProtocol());
    const acq::PlantDecision d = plain.branch(1);
    ASSERT_EQ(d.kind, Kind::Rejected);
    EXPECT_NE(d.reason.find("this protocol has no branches"), std::string::npos) << d.reason;
  }
  acq::PlantEngine engine(
      m::readPlantProtocolFile(std::string(LEAFDIG_SOURCE_DIR) + "/data/protocols/branched.plant-protocol.json"));
  Technician tech{engine};
  EXPECT_NE(engine.branch().reason.find("take node 1 on the stem first"), std::string::npos);
  // Up to node 3's first point (nodes 1 and 2 on the stem, as the file has them).
  while (!(engine.step().what == PlantWhat::Point && engine.step().index == 3)) {
    const acq::PlantStep s = engine.step();
    if (s.what == PlantWhat::Point && s.index == 2 && s.part == 1) {
      // Not before node 2's point: node 2 would hang on node 1 by branching from it — taken;
      // then undone, so that the rest follows the file.
      ASSERT_EQ(tech.branch(1).kind, Kind::NodePlaced);
      EXPECT_EQ(engine.prompt(), "Node 2 · node on the branch from node 1");
      const acq::PlantDecision back = tech.undo();
      ASSERT_EQ(back.kind, Kind::PlacementUndone);
      EXPECT_EQ(back.place, (acq::NodePlace{1, '+'}));
      EXPECT_EQ(engine.link(2).relation, '<');
    }
    std::string why;
    ASSERT_TRUE(tech.act(truth, &why)) << why;
  }
  EXPECT_NE(engine.branch(7).reason.find("node 7 is not taken"), std::string::npos);
  // A full leaf chosen ahead for node 3 is not one a branch's leaf takes (quick or none).
  ASSERT_EQ(tech.choose(3, {m::LeafKind::Full, m::LeafState::Alive, {}}).kind, Kind::LeafChosen);
  EXPECT_NE(engine.branch().reason.find("node 3's leaf is chosen full, which \"branch_leaf\" does not take"),
            std::string::npos)
      << engine.branch().reason;
  ASSERT_EQ(tech.undo().kind, Kind::ChoiceUndone);
  ASSERT_EQ(tech.branch(0).kind, Kind::NodePlaced);  // from the stem's last node: 2
  EXPECT_EQ(engine.link(3).parent, 2);
  EXPECT_EQ(engine.link(3).order, 2);
  // Node 3's point and reading, then at node 4: a branch from node 3 (on the branch) is refused,
  // and so is placing anything while inside a node.
  ASSERT_TRUE(tech.act(truth));
  EXPECT_NE(engine.branch(2).reason.find("before its first point"), std::string::npos);
  while (!(engine.step().what == PlantWhat::Point && engine.step().index == 4)) ASSERT_TRUE(tech.act(truth));
  EXPECT_NE(engine.branch(3).reason.find("node 3 is on a branch: branches start from the main stem"),
            std::string::npos);
  // The long press at node 4's first point ends the branch: node 4 follows node 2 on the stem;
  // undo puts it back on the branch.
  ASSERT_EQ(tech.end().kind, Kind::NodePlaced);
  EXPECT_EQ(engine.link(4).order, 1);
  EXPECT_EQ(engine.link(4).parent, 2);
  ASSERT_EQ(tech.undo().kind, Kind::PlacementUndone);
  EXPECT_EQ(engine.link(4).order, 2);
  EXPECT_EQ(engine.link(4).parent, 3);
}

// Moving the transmitter (issue 29): after node 2's point the technician moves it (turned 30°
// about the vertical, shifted 120 mm) and takes the landmarks again. A landmark pressed 5 mm off
// is named by the refused fit; taken again right, the fit holds, every later point — the plant's
// and a full leaf's — lands where it would have without the move, undo goes back through the
// fit and the start, and replay gives the same plant.
TEST(PlantEngine, AMovedTransmitterIsFittedFromTheLandmarksTakenAgainAndEveryLaterPointFollows) {
  const m::PlantMarkers truth = samplePlant();
  acq::PlantEngine engine(m::defaultPlantProtocol());
  Technician tech{engine};
  EXPECT_NE(engine.moveTransmitter().reason.find("end the landmarks first"), std::string::npos);
  while (!(engine.step().what == PlantWhat::Reading && engine.step().index == 2)) ASSERT_TRUE(tech.act(truth));
  const auto keep = [&](acq::PlantDecision d) {
    tech.keep(d);
    return d;
  };
  ASSERT_EQ(keep(engine.moveTransmitter()).kind, Kind::RelocationStarted);
  EXPECT_EQ(engine.prompt(), "Transmitter moved · landmark 1 again");
  EXPECT_NE(engine.chooseLeaf(3, {}).reason.find("finish moving the transmitter first"), std::string::npos);
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = Eigen::AngleAxisd(30.0 * std::acos(-1.0) / 180.0, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  pose.translation() = Eigen::Vector3d(120.0, -40.0, 15.0);
  tech.fromFirst = pose;
  const auto landmark = [&](int k, const Eigen::Vector3d& off = Eigen::Vector3d::Zero()) {
    const Eigen::Vector3d p = truth.landmarksMm[static_cast<std::size_t>(k - 1)] + off;
    return tech.press({p.x(), p.y(), p.z()});
  };
  ASSERT_EQ(landmark(1).kind, Kind::Accepted);
  ASSERT_EQ(landmark(2).kind, Kind::Accepted);
  EXPECT_NE(tech.end().reason.find("take at least three of the landmarks again"), std::string::npos);
  ASSERT_EQ(landmark(3, {5.0, 0.0, 0.0}).kind, Kind::Accepted);  // pressed 5 mm off: it moved
  ASSERT_EQ(landmark(4).kind, Kind::Accepted);
  EXPECT_EQ(engine.prompt(), "Transmitter moved · every landmark taken again: hold the button (or End) to fit");
  const acq::PlantDecision refused = tech.end();
  ASSERT_EQ(refused.kind, Kind::Rejected);
  EXPECT_NE(refused.reason.find("landmark 3 is"), std::string::npos) << refused.reason;
  ASSERT_EQ(tech.undo().kind, Kind::Undone);  // landmark 4 again
  ASSERT_EQ(tech.undo().kind, Kind::Undone);  // landmark 3 again
  EXPECT_EQ(engine.prompt(), "Transmitter moved · landmark 3 again");
  ASSERT_EQ(landmark(3).kind, Kind::Accepted);
  EXPECT_EQ(engine.prompt(), "Transmitter moved · landmark 4 again  (or hold the button to fit)");
  ASSERT_EQ(landmark(4).kind, Kind::Accepted);
  const acq::PlantDecision fitted = tech.end();
  ASSERT_EQ(fitted.kind, Kind::RelocationFitted) << fitted.reason;
  EXPECT_LT(fitted.fit.rmsMm, 1e-6);
  // Undo takes the fit back (the landmarks again), and the end fits again.
  ASSERT_EQ(tech.undo().kind, Kind::RelocationReopened);
  EXPECT_EQ(engine.relocating(), 1);
  ASSERT_EQ(tech.end().kind, Kind::RelocationFitted);
  ASSERT_EQ(engine.toFirst().size(), 2U);
  EXPECT_TRUE(engine.toFirst()[1].isApprox(pose.inverse(), 1e-9));
  EXPECT_EQ(engine.step().what, PlantWhat::Reading);  // back where the capture was
  tech.captureAll(truth);
  const m::PlantMarkers got = engine.captured(truth.plant);
  ASSERT_EQ(got.nodes.size(), truth.nodes.size());
  for (std::size_t i = 0; i < got.nodes.size(); ++i)
    expectSamePoints(got.nodes[i].pointMm, truth.nodes[i].pointMm, 1e-6, "node " + std::to_string(i + 1));
  const m::MarkerSet& leaf = std::get<m::MarkerSet>(got.nodes[1].leaf);  // node 2's full leaf, after the move
  expectSamePoints(leaf.tipMm, std::get<m::MarkerSet>(truth.nodes[1].leaf).tipMm, 1e-6, "node 2's tip");
  acq::PlantEngine replayed(m::defaultPlantProtocol());
  for (const acq::PlantDecision& d : tech.log) replayed.apply(d);
  EXPECT_EQ(m::plantMarkersToJson(replayed.captured(truth.plant)), m::plantMarkersToJson(got));
  // A start undone with nothing taken again is cancelled.
  acq::PlantEngine other(m::defaultPlantProtocol());
  Technician again{other};
  while (other.step().what != PlantWhat::Collar) ASSERT_TRUE(again.act(truth));
  ASSERT_EQ(other.moveTransmitter().kind, Kind::RelocationStarted);
  EXPECT_NE(other.moveTransmitter().reason.find("being moved already"), std::string::npos);
  ASSERT_EQ(other.undo().kind, Kind::RelocationCancelled);
  EXPECT_EQ(other.step().what, PlantWhat::Collar);
}

// The tolerance is the session's (Settings::relocationToleranceMm: the station's settings,
// `--relocation-tolerance`): a landmark 5 mm off is refused at 1.5 mm and fitted at 10 mm.
TEST(PlantEngine, TheSessionsRelocationToleranceDecidesWhetherAMoveFits) {
  const m::PlantMarkers truth = samplePlant();
  for (const double tolerance : {1.5, 10.0}) {
    acq::Settings settings;
    settings.relocationToleranceMm = tolerance;
    acq::PlantEngine engine(m::defaultPlantProtocol(), settings);
    EXPECT_EQ(engine.relocationSettings().toleranceMm, tolerance);
    Technician tech{engine};
    while (engine.step().what != PlantWhat::Collar) ASSERT_TRUE(tech.act(truth));
    tech.keep(engine.moveTransmitter());
    for (int k = 1; k <= 4; ++k) {
      const Eigen::Vector3d p =
          truth.landmarksMm[static_cast<std::size_t>(k - 1)] + Eigen::Vector3d(k == 3 ? 5.0 : 0.0, 0.0, 0.0);
      ASSERT_EQ(tech.press({p.x(), p.y(), p.z()}).kind, Kind::Accepted);
    }
    const acq::PlantDecision fit = tech.end();
    if (tolerance < 2) {
      EXPECT_EQ(fit.kind, Kind::Rejected);
      EXPECT_NE(fit.reason.find("more than 1.5 mm"), std::string::npos) << fit.reason;
    } else {
      EXPECT_EQ(fit.kind, Kind::RelocationFitted) << fit.reason;
      EXPECT_GT(fit.fit.rmsMm, 1.5);
    }
  }
}

// A move of the transmitter at every kind of step a plant capture asks for — the collar, its
// diameter, a node's point and reading, a quick leaf's point, a full leaf's marker and its
// thickness reading — and in one case a second move later (a chain of three positions, the
// third fitted to the first directly): the landmarks taken again fit, the capture goes on at the
// step it left, and the plant comes out as the file says, replayed to the same file.
TEST(PlantEngine, AMoveAtEveryKindOfStepAndAChainOfThreePositionsGiveTheFilesPlant) {
  const m::PlantMarkers truth = samplePlant();
  struct Case {
    const char* name;
    std::function<bool(const acq::PlantStep&)> at;
  };
  const std::vector<Case> cases{
      {"the collar", [](const acq::PlantStep& s) { return s.what == PlantWhat::Collar; }},
      {"the collar's diameter", [](const acq::PlantStep& s) { return s.what == PlantWhat::CollarDiameter; }},
      {"node 3's point", [](const acq::PlantStep& s) { return s.what == PlantWhat::Point && s.index == 3; }},
      {"node 3's reading", [](const acq::PlantStep& s) { return s.what == PlantWhat::Reading && s.index == 3; }},
      {"node 3's quick leaf", [](const acq::PlantStep& s) { return s.what == PlantWhat::QuickPoint && s.index == 3; }},
      {"node 2's full leaf, a marker",
       [](const acq::PlantStep& s) {
         return s.what == PlantWhat::Leaf && s.leaf.what == acq::What::Marker && s.leaf.row == 3;
       }},
      {"node 2's full leaf, a thickness",
       [](const acq::PlantStep& s) { return s.what == PlantWhat::Leaf && !acq::isStylusItem(s.leaf.what); }},
  };
  const auto pose = [](double turnDeg, const Eigen::Vector3d& shift) {
    Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
    p.linear() = (Eigen::AngleAxisd(turnDeg * std::acos(-1.0) / 180.0, Eigen::Vector3d::UnitZ()) *
                  Eigen::AngleAxisd(0.05, Eigen::Vector3d::UnitX()))
                     .toRotationMatrix();
    p.translation() = shift;
    return p;
  };
  for (std::size_t c = 0; c < cases.size(); ++c) {
    SCOPED_TRACE(cases[c].name);
    acq::PlantEngine engine(m::defaultPlantProtocol());
    Technician tech{engine};
    // Moves the transmitter at the current step, takes the four landmarks again, fits.
    const auto move = [&](const Eigen::Isometry3d& to) {
      const acq::PlantStep before = engine.step();
      const acq::PlantDecision started = engine.moveTransmitter();
      tech.keep(started);
      ASSERT_EQ(started.kind, Kind::RelocationStarted) << started.reason;
      tech.fromFirst = to;
      for (const Eigen::Vector3d& l : truth.landmarksMm)
        ASSERT_EQ(tech.press({l.x(), l.y(), l.z()}).kind, Kind::Accepted);
      const acq::PlantDecision fitted = tech.end();
      ASSERT_EQ(fitted.kind, Kind::RelocationFitted) << fitted.reason;
      EXPECT_LT(fitted.fit.rmsMm, 1e-6);
      EXPECT_EQ(engine.step(), before) << "the capture goes on where it was";
    };
    for (int guard = 0; guard < 2000 && !cases[c].at(engine.step()); ++guard) ASSERT_TRUE(tech.act(truth));
    ASSERT_TRUE(cases[c].at(engine.step())) << engine.prompt();
    move(pose(25.0 + 10.0 * static_cast<double>(c), {80.0, -60.0, 10.0}));
    if (c == 0) {  // a third position, later: fitted to the first, not through the second
      for (int guard = 0; guard < 2000 && !(engine.step().what == PlantWhat::Point && engine.step().index == 4);
           ++guard)
        ASSERT_TRUE(tech.act(truth));
      const Eigen::Isometry3d third = pose(-70.0, {-150.0, 90.0, -20.0});
      move(third);
      ASSERT_EQ(engine.toFirst().size(), 3U);
      EXPECT_TRUE(engine.toFirst()[2].isApprox(third.inverse(), 1e-9));
    }
    tech.captureAll(truth);
    const m::PlantMarkers got = engine.captured(truth.plant);
    ASSERT_EQ(got.nodes.size(), truth.nodes.size());
    for (std::size_t i = 0; i < got.nodes.size(); ++i)
      expectSamePoints(got.nodes[i].pointMm, truth.nodes[i].pointMm, 1e-6, "node " + std::to_string(i + 1));
    const m::MarkerSet& leaf = std::get<m::MarkerSet>(got.nodes[1].leaf);
    const m::MarkerSet& want = std::get<m::MarkerSet>(truth.nodes[1].leaf);
    ASSERT_EQ(leaf.rows.size(), want.rows.size());
    for (std::size_t r = 0; r < leaf.rows.size(); ++r)
      for (std::size_t k = 0; k < m::kMarkersPerRow; ++k)
        expectSamePoints(leaf.rows[r].pointsMm[k], want.rows[r].pointsMm[k], 1e-6, "node 2's marker");
    acq::PlantEngine replayed(m::defaultPlantProtocol());
    for (const acq::PlantDecision& d : tech.log) replayed.apply(d);
    EXPECT_EQ(m::plantMarkersToJson(replayed.captured(truth.plant)), m::plantMarkersToJson(got));
  }
}

// The station's live plant preview at the moments a technician sees it change: the points alone
// before the plant frame, the stem from the first node (its diameter not read yet said so), the
// full leaf under capture drawn in the plant from its own live preview, and at the end exactly
// the captured plant's model at the preview's resolution.
TEST(PlantPreview, GrowsWithThePlantFromItsPointsToTheCapturedModel) {
  const m::PlantMarkers truth = samplePlant();
  acq::PlantEngine engine(m::defaultPlantProtocol());
  Technician tech{engine};
  const auto until = [&](const std::function<bool()>& done) {
    for (int guard = 0; guard < 2000 && !done() && !engine.complete(); ++guard) {
      std::string why;
      ASSERT_TRUE(tech.act(truth, &why)) << why << " at " << engine.prompt();
    }
  };
  const std::vector<m::LibraryLeaf> noLibrary;

  until([&] { return engine.items().size() == 2; });
  acq::PlantPreview p = acq::buildPlantPreview(engine, noLibrary);
  EXPECT_FALSE(p.inPlantFrame);
  EXPECT_TRUE(p.mesh.organs.empty());
  ASSERT_EQ(p.points.size(), 2u);
  for (std::size_t i = 0; i < 2; ++i) EXPECT_EQ(p.points[i].positionMm, engine.items()[i].positionMm);

  // Node 1's point taken, its diameter not yet: the stem is drawn, in the plant frame.
  until([&] { return engine.step().what == PlantWhat::Reading && engine.step().index == 1; });
  p = acq::buildPlantPreview(engine, noLibrary);
  ASSERT_TRUE(p.inPlantFrame) << (p.notes.empty() ? "" : p.notes.front());
  ASSERT_FALSE(p.mesh.organs.empty());
  EXPECT_EQ(p.mesh.organs.front().name, "plant/stem");
  const auto note = std::find_if(p.notes.begin(), p.notes.end(),
                                 [](const std::string& n) { return n.find("not read yet") != std::string::npos; });
  EXPECT_NE(note, p.notes.end());
  const auto collar = std::find_if(p.points.begin(), p.points.end(), [](const acq::Item& i) {
    return i.row == 0 && i.col == 0 && std::abs(i.positionMm[2]) < 1e-6 && std::abs(i.positionMm[0]) < 1e-6;
  });
  EXPECT_NE(collar, p.points.end()) << "the collar is the plant frame's origin";

  // Two rows into node 2's full leaf: the leaf view has it, and the plant draws it in place.
  until([&] {
    const acq::PlantStep s = engine.step();
    return s.what == PlantWhat::Leaf && s.index == 2 && engine.leaf(2) &&
           acq::completeRows(engine.leaf(2)->items()) >= 2;
  });
  p = acq::buildPlantPreview(engine, noLibrary);
  EXPECT_EQ(p.leafNode, 2);
  ASSERT_TRUE(p.leaf);
  ASSERT_FALSE(p.leaf->mesh.organs.empty());
  EXPECT_EQ(p.leafItems.size(), engine.leaf(2)->items().size());
  const m::PlantSurvey frame = m::surveyPlant([&] {
    m::PlantMarkers c = engine.captured("plant");
    for (auto& n : c.nodes) n.leaf = std::monostate{};
    return c;
  }());
  const m::Organ& blade = p.leaf->mesh.organs.back();
  const auto placed = std::find_if(p.mesh.organs.begin(), p.mesh.organs.end(),
                                   [&](const m::Organ& o) { return o.name == "plant/leaf-2/" + blade.name; });
  ASSERT_NE(placed, p.mesh.organs.end());
  EXPECT_EQ(placed->leafRank, 2);
  ASSERT_EQ(placed->mesh.positions.size(), blade.mesh.positions.size());
  EXPECT_LT((placed->mesh.positions.front() - frame.frame.point(blade.mesh.positions.front())).norm(), 1e-9);

  // The whole plant, built as the station builds it (one previewer along the capture, reusing
  // the leaves that did not change): the captured model itself, at the preview's resolution.
  acq::PlantPreviewer previewer;
  while (!engine.complete()) {
    until([&, n = engine.items().size()] { return engine.items().size() > n + 20; });
    (void)previewer.build(engine);
  }
  ASSERT_TRUE(engine.complete());
  p = previewer.build(engine);
  EXPECT_GT(previewer.reused(), 0) << "a finished leaf is not meshed again";
  const acq::PlantPreview once = acq::buildPlantPreview(engine, noLibrary);
  ASSERT_EQ(once.mesh.organs.size(), p.mesh.organs.size());
  for (std::size_t i = 0; i < once.mesh.organs.size(); ++i)
    EXPECT_EQ(once.mesh.organs[i].mesh.positions, p.mesh.organs[i].mesh.positions);
  EXPECT_EQ(p.leafNode, 0);
  EXPECT_FALSE(p.leaf);
  const m::Plant model = m::surveyedPlant(m::surveyPlant(engine.captured("plant")), noLibrary,
                                          m::LibraryLeaf{m::kSampleShapeSource, m::sampleLeafShape()});
  const m::LeafMesh expected = m::meshPlant(model, m::MeshResolution::preset("preview"));
  EXPECT_EQ(p.leaves, static_cast<int>(model.leaves.size()));
  EXPECT_EQ(p.leaves, 3);  // the sample: one full leaf, two quick ones
  ASSERT_EQ(p.mesh.organs.size(), expected.organs.size());
  for (std::size_t i = 0; i < expected.organs.size(); ++i) {
    EXPECT_EQ(p.mesh.organs[i].name, expected.organs[i].name);
    EXPECT_EQ(p.mesh.organs[i].mesh.positions, expected.organs[i].mesh.positions) << expected.organs[i].name;
  }
  // Every stylus point of the plant, then the full leaf's tip and markers (the view frames on them).
  const auto plantPoints = static_cast<std::size_t>(std::count_if(
      engine.items().begin(), engine.items().end(), [](const acq::PlantItem& i) { return acq::isStylusItem(i.what); }));
  const auto& leafItems = engine.leaf(2)->items();
  const auto leafPoints =
      static_cast<std::size_t>(std::count_if(leafItems.begin(), leafItems.end(), [](const acq::Item& i) {
        return i.what == acq::What::Tip || i.what == acq::What::Marker;
      }));
  ASSERT_EQ(p.points.size(), plantPoints + leafPoints);
  EXPECT_EQ(p.points.back().row, 2);
  EXPECT_GE(p.points.back().col, 100);
}
