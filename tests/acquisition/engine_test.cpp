// The protocol engine driven as a technician drives it: still stylus, press, release;
// caliper readings; undo; the end-of-rows long press. Then replay of what was decided.
#include "leafdig/acquisition/protocol/engine.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <random>

#include "leafdig/model/leaf/markers_json.hpp"
#include "leafdig/names/name_table.hpp"

namespace acq = leafdig::acquisition;
using Kind = acq::Decision::Kind;

namespace {

constexpr std::int64_t kMs = 1'000'000;

struct Operator {
  explicit Operator(acq::Engine& e) : engine(e) {}
  acq::Engine& engine;
  std::int64_t t = 0;
  std::mt19937 rng{7};
  std::vector<acq::Decision> log;  // what a front end would store

  // Holds the stylus on p for 0.4 s, presses for `pressMs`, releases. `shakeMm` moves it.
  acq::Decision press(const acq::Vec3& p, std::int64_t pressMs = 200, double shakeMm = 0.0, std::string status = "ok",
                      int stillSamples = 75) {
    std::normal_distribution<double> noise(0.0, 0.1);
    acq::Decision last;
    const auto sample = [&](bool button, double shake) {
      acq::StylusInput s;
      s.tNs = (t += 8 * kMs);
      s.positionMm = {p[0] + noise(rng) + shake, p[1] + noise(rng), p[2] + noise(rng)};
      s.button = button;
      s.status = status;
      s.raw = "01 …";
      const auto d = engine.onStylus(s);
      if (d.kind != Kind::Ignored) last = d;
    };
    for (int i = 0; i < stillSamples; ++i) sample(false, 0);
    for (std::int64_t i = 0; i < pressMs / 8; ++i) sample(true, shakeMm * std::sin(static_cast<double>(i)));
    sample(false, 0);
    if (last.kind != Kind::Rejected && last.kind != Kind::Ignored) log.push_back(last);
    return last;
  }
  acq::Decision read(double mm) {
    const auto d = engine.onCaliper({t += 500 * kMs, mm, "+" + std::to_string(mm) + "\r"});
    if (d.kind == Kind::Accepted) log.push_back(d);
    return d;
  }
};

acq::Vec3 v(const Eigen::Vector3d& e) {
  return {e.x(), e.y(), e.z()};
}

class EngineSample : public ::testing::TestWithParam<const char*> {};

TEST_P(EngineSample, CapturesAWholeLeafWithoutKeyboardAndReplaysItExactly) {
  const auto leaf = leafdig::model::readMarkersFile(std::string(LEAFDIG_SOURCE_DIR) + "/data/samples/" + GetParam() +
                                                    ".markers.json");
  const std::size_t n = leaf.rows.size();
  acq::Engine engine;
  Operator op{engine};
  EXPECT_EQ(engine.prompt(), "Tip: touch the leaf tip and press");
  EXPECT_EQ(op.press(v(leaf.tipMm)).kind, Kind::Accepted);
  for (std::size_t r = 0; r < leaf.rows.size(); ++r)
    for (int c = 0; c < 7; ++c) {
      const acq::Step s = engine.step();
      ASSERT_EQ(s.what, acq::What::Marker);
      ASSERT_EQ(s.row, static_cast<int>(r) + 1);
      ASSERT_EQ(s.col, c + 1);
      const auto d = op.press(v(leaf.rows[r].pointsMm[static_cast<std::size_t>(c)]));
      ASSERT_EQ(d.kind, Kind::Accepted) << d.reason << " at row " << r + 1 << " point " << c + 1;
    }
  EXPECT_NE(engine.prompt().find("hold the button to end the rows"), std::string::npos);
  EXPECT_NE(engine.prompt().find("the last row is at the leaf base"), std::string::npos);
  EXPECT_EQ(op.press({500, 500, 500}, 1500).kind, Kind::RowsEnded);  // long press, anywhere
  EXPECT_EQ(engine.completeRows(), static_cast<int>(n));
  for (std::size_t r = 0; r < leaf.rows.size(); ++r) {
    EXPECT_EQ(engine.step().what, acq::What::MidribThickness);
    EXPECT_EQ(op.read(*leaf.rows[r].midribThicknessMm).kind, Kind::Accepted);
    EXPECT_EQ(engine.step().what, acq::What::VeinOriginThickness);
    EXPECT_EQ(op.read(*leaf.rows[r].veinOriginThicknessMm).kind, Kind::Accepted);
  }
  EXPECT_EQ(engine.step().what, acq::What::EdgeThickness);
  EXPECT_EQ(op.read(*leaf.edgeThicknessMm).kind, Kind::Accepted);
  EXPECT_TRUE(engine.complete());
  // Positions are the means of the still samples: within the noise of the truth.
  const auto& items = engine.items();
  ASSERT_EQ(items.size(), 1 + 7 * n + 2 * n + 1);
  for (std::size_t r = 0; r < n; ++r)
    for (std::size_t c = 0; c < 7; ++c) {
      const auto& it = items[1 + 7 * r + c];
      EXPECT_NEAR(it.positionMm[0], leaf.rows[r].pointsMm[c].x(), 0.1);
    }
  // Replaying the stored decisions rebuilds the same state.
  acq::Engine replay;
  for (const auto& d : op.log) replay.apply(d);
  EXPECT_TRUE(replay.complete());
  ASSERT_EQ(replay.items().size(), items.size());
  for (std::size_t i = 0; i < items.size(); ++i) {
    EXPECT_EQ(replay.items()[i].positionMm, items[i].positionMm);
    EXPECT_EQ(replay.items()[i].valueMm, items[i].valueMm);
  }
}

INSTANTIATE_TEST_SUITE_P(Samples, EngineSample,
                         ::testing::Values("lower-leaf-n10", "upper-small-leaf-n17", "upper-curved-leaf-n14"),
                         [](const auto& info) {
                           std::string n = info.param;
                           std::replace(n.begin(), n.end(), '-', '_');
                           return n;
                         });

class EngineRow : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_EQ(op.press({0, 0, 0}).kind, Kind::Accepted);  // tip at the origin, rows below it
    for (int c = 1; c <= 7; ++c) ASSERT_EQ(op.press(pt(1, c)).kind, Kind::Accepted);
  }
  static acq::Vec3 pt(int row, int col) { return {40.0 - 12.0 * (col - 1), -30.0 * row, 0.0}; }
  acq::Engine engine;
  Operator op{engine};
};

TEST_F(EngineRow, RejectsADoubleTapAMovingStylusAndAStatusLetter) {
  ASSERT_EQ(op.press(pt(2, 1)).kind, Kind::Accepted);
  auto d = op.press({pt(2, 1)[0] + 0.5, pt(2, 1)[1], 0}, 200, 0.0, "ok", 20);  // pressed again at once
  EXPECT_EQ(d.kind, Kind::Rejected);
  EXPECT_NE(d.reason.find("double press"), std::string::npos) << d.reason;
  d = op.press(pt(2, 2), 200, 4.0);
  EXPECT_EQ(d.kind, Kind::Rejected);
  EXPECT_NE(d.reason.find("moved"), std::string::npos) << d.reason;
  d = op.press(pt(2, 2), 200, 0.0, "x");
  EXPECT_EQ(d.kind, Kind::Rejected);
  EXPECT_NE(d.reason.find("status 'x'"), std::string::npos) << d.reason;
  EXPECT_EQ(op.press(pt(2, 2)).kind, Kind::Accepted);  // the step was kept
}

// A digitizer that resets (or is unplugged) while the button is down: the driver connects again
// and its stream begins anew, button up. The press it cut is no press — not an undo, as its
// length across the outage would say, nor a point — and is refused in words; the next press
// is taken as usual.
TEST_F(EngineRow, APressCutByTheDigitizersReconnectIsRefusedNotTakenForAnUndo) {
  ASSERT_EQ(op.press(pt(2, 1)).kind, Kind::Accepted);
  const std::size_t before = engine.items().size();
  const auto sample = [&](const acq::Vec3& p, bool button, bool streamBegins) {
    acq::StylusInput s;
    s.tNs = (op.t += 8 * kMs);
    s.positionMm = p;
    s.button = button;
    s.raw = "01 …";
    s.streamBegins = streamBegins;
    return engine.onStylus(s);
  };
  for (int i = 0; i < 60; ++i) EXPECT_EQ(sample(pt(2, 2), false, false).kind, Kind::Ignored);
  for (int i = 0; i < 10; ++i) EXPECT_EQ(sample(pt(2, 2), true, false).kind, Kind::Ignored);
  op.t += 20'000 * kMs;  // the digitizer's outage: longer than the press that undoes
  const acq::Decision d = sample(pt(2, 2), false, true);
  EXPECT_EQ(d.kind, Kind::Rejected);
  EXPECT_NE(d.reason.find("press again"), std::string::npos) << d.reason;
  EXPECT_NE(d.reason.find("digitizer"), std::string::npos) << d.reason;
  EXPECT_EQ(engine.items().size(), before);  // nothing undone
  EXPECT_EQ(engine.step(), (acq::Step{acq::What::Marker, 2, 2}));
  EXPECT_EQ(op.press(pt(2, 2)).kind, Kind::Accepted);
  // A stream that begins again with the button up and no press under way changes nothing.
  for (int i = 0; i < 5; ++i) sample(pt(2, 3), false, false);
  op.t += 5'000 * kMs;
  EXPECT_EQ(sample(pt(2, 3), false, true).kind, Kind::Ignored);
  EXPECT_EQ(op.press(pt(2, 3)).kind, Kind::Accepted);
}

TEST_F(EngineRow, RejectsOrderSpacingAndMidribMistakes) {
  ASSERT_EQ(op.press(pt(2, 1)).kind, Kind::Accepted);
  ASSERT_EQ(op.press(pt(2, 2)).kind, Kind::Accepted);
  ASSERT_EQ(op.press(pt(2, 3)).kind, Kind::Accepted);
  auto d = op.press({pt(2, 2)[0] + 3, pt(2, 2)[1], 0});  // back towards point 2
  EXPECT_EQ(d.kind, Kind::Rejected);
  EXPECT_NE(d.reason.find("goes back"), std::string::npos) << d.reason;
  ASSERT_EQ(engine.undo().kind, Kind::Undone);
  d = op.press(pt(2, 5));  // skipped two markers
  EXPECT_EQ(d.kind, Kind::Rejected);
  EXPECT_NE(d.reason.find("uneven spacing"), std::string::npos) << d.reason;
  ASSERT_EQ(op.press(pt(2, 3)).kind, Kind::Accepted);
  d = op.press({pt(2, 4)[0], pt(2, 4)[1], 25.0});  // 25 mm above the midrib line, same spacing-ish
  EXPECT_EQ(d.kind, Kind::Rejected);
  EXPECT_EQ(op.press(pt(2, 4)).kind, Kind::Accepted);
}

TEST_F(EngineRow, ASlowSecondPressOnARowsLastPointIsNotTakenForTheNextRowsFirst) {
  // Row 1 ended at point 7 (the left margin). Pressed there again, slowly (outside the
  // double-tap window): it is not row 2's point 1, which starts on the right margin.
  const auto d = op.press(pt(1, 7));
  EXPECT_EQ(d.kind, Kind::Rejected);
  EXPECT_NE(d.reason.find("row 2 starts on the right margin"), std::string::npos) << d.reason;
  EXPECT_EQ(op.press(pt(2, 1)).kind, Kind::Accepted);
  for (int c = 2; c <= 7; ++c) EXPECT_EQ(op.press(pt(2, c)).kind, Kind::Accepted) << c;
}

TEST_F(EngineRow, UndoGoesBackOneStepAndEndingRowsNeedsEnoughRows) {
  auto d = engine.endRows();
  EXPECT_EQ(d.kind, Kind::Rejected);
  EXPECT_NE(d.reason.find("at least 2 rows"), std::string::npos);
  ASSERT_EQ(op.press(pt(2, 1)).kind, Kind::Accepted);
  EXPECT_EQ(engine.step(), (acq::Step{acq::What::Marker, 2, 2}));
  d = engine.undo();
  EXPECT_EQ(d.kind, Kind::Undone);
  EXPECT_EQ(d.item.row, 2);
  EXPECT_EQ(engine.step(), (acq::Step{acq::What::Marker, 2, 1}));
  for (int c = 1; c <= 7; ++c) ASSERT_EQ(op.press(pt(2, c)).kind, Kind::Accepted);
  EXPECT_EQ(engine.endRows().kind, Kind::RowsEnded);
  engine.apply(engine.endRows());  // a second end is rejected and changes nothing
  EXPECT_EQ(engine.step().what, acq::What::MidribThickness);
  EXPECT_EQ(engine.undo().kind, Kind::RowsReopened);
  EXPECT_EQ(engine.step(), (acq::Step{acq::What::Marker, 3, 1}));
}

TEST_F(EngineRow, CaliperReadingsAreCheckedAndRepeatsFlaggedNotDropped) {
  for (int c = 1; c <= 7; ++c) ASSERT_EQ(op.press(pt(2, c)).kind, Kind::Accepted);
  auto d = op.read(0.5);
  EXPECT_EQ(d.kind, Kind::Rejected);  // a stylus step: point first
  EXPECT_EQ(engine.endRows().kind, Kind::RowsEnded);
  d = op.read(25.4 * 10);  // an inch-mode gauge mistaken for mm
  EXPECT_EQ(d.kind, Kind::Rejected);
  EXPECT_NE(d.reason.find("check the unit"), std::string::npos);
  d = op.read(0.8);
  EXPECT_EQ(d.kind, Kind::Accepted);
  EXPECT_TRUE(d.item.flag.empty());
  d = op.read(0.8);
  EXPECT_EQ(d.kind, Kind::Accepted);
  EXPECT_EQ(d.item.flag, "repeated reading");
  EXPECT_EQ(d.item.what, acq::What::VeinOriginThickness);
}

TEST(EngineModes, StepsFollowModeAndOrder) {
  for (auto [mode, order] :
       {std::pair{acq::Mode::Small, acq::Order::Interleaved}, std::pair{acq::Mode::Full, acq::Order::Sequential}}) {
    acq::Settings s;
    s.mode = mode;
    s.order = order;
    acq::Engine engine(s);
    Operator op{engine};
    ASSERT_EQ(op.press({0, 0, 0}).kind, Kind::Accepted);
    for (int c = 1; c <= 7; ++c) ASSERT_EQ(op.press({40.0 - 12.0 * (c - 1), -30.0, 0}).kind, Kind::Accepted);
    if (order == acq::Order::Interleaved) {
      EXPECT_EQ(engine.step(), (acq::Step{acq::What::MidribThickness, 1, 4}));  // right after the row
      EXPECT_EQ(op.read(0.9).kind, Kind::Accepted);
      EXPECT_EQ(engine.step(), (acq::Step{acq::What::Marker, 2, 1}));  // small: r¹ only
    } else {
      for (int c = 1; c <= 7; ++c) ASSERT_EQ(op.press({40.0 - 12.0 * (c - 1), -60.0, 0}).kind, Kind::Accepted);
      EXPECT_EQ(engine.endRows().kind, Kind::RowsEnded);
      EXPECT_EQ(engine.step(), (acq::Step{acq::What::MidribThickness, 1, 4}));
      EXPECT_EQ(op.read(0.9).kind, Kind::Accepted);
      EXPECT_EQ(engine.step(), (acq::Step{acq::What::PointThickness, 1, 1}));  // full: every point
    }
  }
  EXPECT_THROW((void)leafdig::model::thicknessModeFromString("huge"), leafdig::UnknownName);
  EXPECT_EQ(acq::orderFromString("interleaved"), acq::Order::Interleaved);
}

}  // namespace

namespace {

TEST(EngineMidrib, AFourthPointOffTheMidribIsRejectedWithTheDistance) {
  acq::Settings s;
  s.spacingTolerance = 10.0;  // only the midrib rule is under test here
  acq::Engine engine(s);
  Operator op(engine);
  const auto pt = [](int row, int col) { return acq::Vec3{40.0 - 12.0 * (col - 1), -30.0 * row, 0.0}; };
  ASSERT_EQ(op.press({0, 0, 0}).kind, Kind::Accepted);
  for (int c = 1; c <= 7; ++c) ASSERT_EQ(op.press(pt(1, c)).kind, Kind::Accepted);
  for (int c = 1; c <= 3; ++c) ASSERT_EQ(op.press(pt(2, c)).kind, Kind::Accepted);
  const auto d = op.press({pt(2, 4)[0], pt(2, 4)[1], 20.0});
  EXPECT_EQ(d.kind, Kind::Rejected);
  EXPECT_NE(d.reason.find("should be on the midrib: it is 20."), std::string::npos) << d.reason;
  const auto closer = op.press({0.0, -20.0, 0.0});  // on the line but not below row 1
  EXPECT_EQ(closer.kind, Kind::Rejected);
  EXPECT_NE(closer.reason.find("farther from the tip"), std::string::npos) << closer.reason;
}

}  // namespace

namespace {

// The plan as a front end shows it: one letter a step (D done, C current, P pending).
std::string states(const std::vector<acq::PlannedStep>& plan, acq::What what, int row = -1) {
  std::string s;
  for (const auto& p : plan)
    if (p.step.what == what && (row < 0 || p.step.row == row))
      s += p.state == acq::PlannedStep::State::Done ? 'D' : p.state == acq::PlannedStep::State::Current ? 'C' : 'P';
  return s;
}

TEST_F(EngineRow, ThePlanListsTheOpenRowThenTheThicknessStepsOnceTheRowsAreEnded) {
  for (int c = 1; c <= 2; ++c) ASSERT_EQ(op.press(pt(2, c)).kind, Kind::Accepted);
  auto plan = engine.plan();
  EXPECT_EQ(states(plan, acq::What::Tip), "D");
  EXPECT_EQ(states(plan, acq::What::Marker, 1), "DDDDDDD");
  EXPECT_EQ(states(plan, acq::What::Marker, 2), "DDCPPPP");
  EXPECT_EQ(states(plan, acq::What::Marker, 3), "");        // not asked for yet
  EXPECT_EQ(states(plan, acq::What::MidribThickness), "");  // sequential: after the rows
  // A retaken point is the current step; the rows after it stay listed.
  engine.apply(engine.retake(acq::What::Marker, 1, 4));
  plan = engine.plan();
  EXPECT_EQ(states(plan, acq::What::Marker, 1), "DDDCDDD");
  EXPECT_EQ(states(plan, acq::What::Marker, 2), "DDPPPPP");
  ASSERT_EQ(op.press(pt(1, 4)).kind, Kind::Accepted);
  for (int c = 3; c <= 7; ++c) ASSERT_EQ(op.press(pt(2, c)).kind, Kind::Accepted);
  EXPECT_EQ(states(engine.plan(), acq::What::Marker, 3), "CPPPPPP");  // the open row
  engine.apply(engine.endRows());
  plan = engine.plan();
  EXPECT_EQ(states(plan, acq::What::Marker, 3), "");
  EXPECT_EQ(states(plan, acq::What::MidribThickness), "CP");
  EXPECT_EQ(states(plan, acq::What::VeinOriginThickness), "PP");
  EXPECT_EQ(states(plan, acq::What::EdgeThickness), "P");
  ASSERT_EQ(plan.back().step.what, acq::What::EdgeThickness);
  // Each step's place follows the order the engine asks for them.
  for (std::size_t i = 0; i + 1 < plan.size(); ++i) {
    if (plan[i + 1].state == acq::PlannedStep::State::Current) {
      EXPECT_NE(plan[i].state, acq::PlannedStep::State::Pending);
    }
  }
}

TEST(EnginePlan, InterleavedOrderPutsARowsThicknessRightAfterIt) {
  acq::Settings s;
  s.order = acq::Order::Interleaved;
  acq::Engine engine(s);
  Operator op{engine};
  ASSERT_EQ(op.press({0, 0, 0}).kind, Kind::Accepted);
  for (int c = 1; c <= 7; ++c) ASSERT_EQ(op.press({40.0 - 12.0 * (c - 1), -30.0, 0}).kind, Kind::Accepted);
  const auto plan = engine.plan();
  std::string order;
  for (const auto& p : plan)
    order += acq::toString(p.step.what) +
             std::string(p.step.what == acq::What::Marker ? std::to_string(p.step.row) : "") + " ";
  EXPECT_EQ(
      order,
      "tip marker1 marker1 marker1 marker1 marker1 marker1 marker1 midrib_thickness vein_origin_thickness marker2 "
      "marker2 marker2 marker2 marker2 marker2 marker2 ");
  EXPECT_EQ(states(plan, acq::What::MidribThickness), "C");
}

}  // namespace

// ---- moving the transmitter (issue 29): a leaf's board points are the landmarks -------------
namespace {

// The board (truth, first transmitter position) and a technician whose stylus is read from
// wherever the transmitter stands now: `from` maps the first position's frame to the current one.
class EngineMove : public ::testing::Test {
 protected:
  static acq::Settings boardSettings() {
    acq::Settings s;
    s.boardFrame = true;
    return s;
  }
  static acq::Vec3 board(int col) { return {col == 2 ? 150.0 : -150.0, col == 3 ? 150.0 : -150.0, -5.0}; }
  static acq::Vec3 pt(int row, int col) { return {40.0 - 12.0 * (col - 1), -30.0 * row, 0.0}; }
  acq::Decision press(const acq::Vec3& truth, std::int64_t ms = 200) {
    const Eigen::Vector3d p = from * Eigen::Vector3d(truth[0], truth[1], truth[2]);
    return op.press({p.x(), p.y(), p.z()}, ms);
  }
  acq::Decision move() {
    const acq::Decision d = engine.moveTransmitter();
    if (d.kind == Kind::RelocationStarted) op.log.push_back(d);
    return d;
  }
  acq::Decision undo() {
    const acq::Decision d = engine.undo();
    if (d.kind != Kind::Rejected) op.log.push_back(d);
    return d;
  }
  // Moves the transmitter to `pose` and takes the three board points again from there.
  void relocateTo(const Eigen::Isometry3d& pose) {
    ASSERT_EQ(move().kind, Kind::RelocationStarted);
    EXPECT_NE(op.read(1.2).reason.find("a caliper reading now?"), std::string::npos) << "the board points first";
    from = pose;
    for (int c = 1; c <= 3; ++c) {
      EXPECT_EQ(engine.step().what, acq::What::BoardAgain);
      EXPECT_EQ(engine.step().col, c);
      ASSERT_EQ(press(board(c)).kind, Kind::Accepted) << "board point " << c << " again";
    }
    EXPECT_EQ(engine.step().col, 0);
    EXPECT_NE(engine.prompt().find("hold the button (or End) to fit"), std::string::npos) << engine.prompt();
    EXPECT_NE(press(board(1)).reason.find("every board point is taken again"), std::string::npos);
    const acq::Decision fit = press(board(3), 1500);  // the long press fits
    ASSERT_EQ(fit.kind, Kind::RelocationFitted) << fit.reason;
    EXPECT_LT(fit.fitRmsMm, 0.3);
  }
  static Eigen::Isometry3d pose(double turnDeg, const Eigen::Vector3d& shift) {
    Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
    p.linear() =
        Eigen::AngleAxisd(turnDeg * 3.14159265358979323846 / 180.0, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    p.translation() = shift;
    return p;
  }
  void SetUp() override {
    for (int c = 1; c <= 3; ++c) ASSERT_EQ(press(board(c)).kind, Kind::Accepted);
    ASSERT_EQ(press({0, 0, 0}).kind, Kind::Accepted);  // the tip
  }
  acq::Engine engine{boardSettings()};
  Operator op{engine};
  Eigen::Isometry3d from = Eigen::Isometry3d::Identity();
};

}  // namespace

TEST_F(EngineMove, ALeafTakenFromThreeTransmitterPositionsLiesInTheFirstAndReplaysTheSame) {
  for (int c = 1; c <= 7; ++c) ASSERT_EQ(press(pt(1, c)).kind, Kind::Accepted);
  for (int c = 1; c <= 3; ++c) ASSERT_EQ(press(pt(2, c)).kind, Kind::Accepted);
  // Moved in the middle of row 2, then again after it: the third position is fitted to the
  // first directly (the board points as first taken), so the chain holds.
  relocateTo(pose(25, {120, -80, 30}));
  for (int c = 4; c <= 7; ++c) ASSERT_EQ(press(pt(2, c)).kind, Kind::Accepted) << "row 2 point " << c;
  relocateTo(pose(-35, {-60, 140, -20}));
  for (int c = 1; c <= 7; ++c) ASSERT_EQ(press(pt(3, c)).kind, Kind::Accepted) << "row 3 point " << c;
  EXPECT_EQ(engine.transmitterPositions(), 3);
  ASSERT_EQ(press({0, 0, 0}, 1500).kind, Kind::RowsEnded);
  for (int r = 1; r <= 3; ++r)
    for (int c = 1; c <= 7; ++c) {
      const acq::Item* i = acq::findItem(engine.items(), acq::What::Marker, r, c);
      ASSERT_NE(i, nullptr);
      EXPECT_LT(acq::distanceMm(i->positionMm, pt(r, c)), 0.3) << "row " << r << " point " << c;
      EXPECT_EQ(i->frame, r == 1 || (r == 2 && c <= 3) ? 0 : r == 2 ? 1 : 2) << "row " << r << " point " << c;
    }
  // The board points taken again are kept as pressed, in their position's frame.
  const acq::Item* again = acq::findItem(engine.items(), acq::What::BoardAgain, 2, 1);
  ASSERT_NE(again, nullptr);
  EXPECT_EQ(again->frame, 2);
  EXPECT_GT(acq::distanceMm(again->positionMm, board(1)), 50.0);
  acq::Engine replay{boardSettings()};
  for (const auto& d : op.log) replay.apply(d);
  EXPECT_EQ(replay.transmitterPositions(), 3);
  ASSERT_EQ(replay.items().size(), engine.items().size());
  for (std::size_t i = 0; i < engine.items().size(); ++i)
    EXPECT_EQ(replay.items()[i].positionMm, engine.items()[i].positionMm);
  for (int k = 0; k < 12; ++k)
    EXPECT_EQ(replay.positionToFirst(2)[static_cast<std::size_t>(k)],
              engine.positionToFirst(2)[static_cast<std::size_t>(k)]);
}

TEST_F(EngineMove, AMoveIsFittedAtEveryKindOfStepAndUndoneStepByStep) {
  // At the tip's row start, inside a row, after the rows (a thickness step): each move fits.
  relocateTo(pose(10, {30, 0, 0}));
  for (int r = 1; r <= 2; ++r)
    for (int c = 1; c <= 7; ++c) ASSERT_EQ(press(pt(r, c)).kind, Kind::Accepted);
  ASSERT_EQ(press({0, 0, 0}, 1500).kind, Kind::RowsEnded);
  ASSERT_EQ(engine.step().what, acq::What::MidribThickness);
  relocateTo(pose(-20, {0, 50, 10}));
  ASSERT_EQ(engine.step().what, acq::What::MidribThickness) << "the thickness step comes back after the fit";
  // Undone step by step: the fit, each board point again, the move itself.
  ASSERT_EQ(undo().kind, Kind::RelocationReopened);
  EXPECT_EQ(engine.step().what, acq::What::BoardAgain);
  EXPECT_EQ(engine.transmitterPositions(), 2);
  for (int c = 3; c >= 1; --c) {
    const acq::Decision d = undo();
    ASSERT_EQ(d.kind, Kind::Undone);
    EXPECT_EQ(d.item.what, acq::What::BoardAgain);
    EXPECT_EQ(d.item.col, c);
  }
  ASSERT_EQ(undo().kind, Kind::RelocationCancelled);
  EXPECT_EQ(engine.relocating(), 0);
  EXPECT_EQ(engine.step().what, acq::What::MidribThickness);
  acq::Engine replay{boardSettings()};
  for (const auto& d : op.log) replay.apply(d);
  EXPECT_EQ(replay.relocating(), 0);
  EXPECT_EQ(replay.transmitterPositions(), 2);
  EXPECT_EQ(replay.items().size(), engine.items().size());
}

TEST_F(EngineMove, AMovedBoardPointOrPointsOnOneLineAreRefusedByName) {
  // A board point that moved 5 mm while the transmitter was moved: the fit names it.
  ASSERT_EQ(move().kind, Kind::RelocationStarted);
  from = pose(15, {40, 20, 0});
  EXPECT_NE(engine.retake(acq::What::Tip, 0, 0).reason.find("finish moving the transmitter first"), std::string::npos);
  EXPECT_NE(engine.moveTransmitter().reason.find("being moved already"), std::string::npos);
  ASSERT_EQ(press(board(1)).kind, Kind::Accepted);
  acq::Vec3 slipped = board(2);
  slipped[1] += 5.0;
  ASSERT_EQ(press(slipped).kind, Kind::Accepted);
  ASSERT_EQ(press(board(3)).kind, Kind::Accepted);
  const acq::Decision refused = press(board(3), 1500);
  ASSERT_EQ(refused.kind, Kind::Rejected);
  EXPECT_NE(refused.reason.find("the board points do not agree after the move"), std::string::npos) << refused.reason;
  EXPECT_NE(
      refused.reason.find("board point 2 (+X direction) moved: its distances to the others changed by up to 3.5 mm"),
      std::string::npos)
      << refused.reason;
  EXPECT_EQ(engine.transmitterPositions(), 1);
  // Taken again where it is: fitted.
  ASSERT_EQ(undo().kind, Kind::Undone);
  ASSERT_EQ(undo().kind, Kind::Undone);
  ASSERT_EQ(press(board(2)).kind, Kind::Accepted);
  ASSERT_EQ(press(board(3)).kind, Kind::Accepted);
  ASSERT_EQ(engine.endRows().kind, Kind::RelocationFitted) << "End fits, as the long press does";
  // Three points on one line cannot fix the turn.
  ASSERT_EQ(move().kind, Kind::RelocationStarted);
  for (const acq::Vec3& p : {acq::Vec3{0, 0, 0}, acq::Vec3{100, 0, 0}, acq::Vec3{200, 0.5, 0}})
    ASSERT_EQ(op.press(p).kind, Kind::Accepted);
  EXPECT_NE(engine.endRows().reason.find("the board points are nearly on one line"), std::string::npos);
  // Without a board frame there is nothing to fit a move to.
  acq::Engine plain;
  EXPECT_NE(plain.moveTransmitter().reason.find("began with the board frame"), std::string::npos);
}
