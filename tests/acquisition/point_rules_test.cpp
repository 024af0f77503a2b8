// Each rule a stylus point must pass, alone: what it refuses, in which words, and what it lets
// through. (engine_test.cpp drives them together through Engine::onStylus.)
#include "leafdig/acquisition/protocol/point_rules.hpp"

#include <gtest/gtest.h>

namespace acq = leafdig::acquisition;
namespace rules = leafdig::acquisition::rules;
using rules::Point;

namespace {

acq::Item stylus(acq::What w, int row, int col, const Point& p) {
  acq::Item i;
  i.what = w;
  i.row = row;
  i.col = col;
  i.positionMm = {p.x(), p.y(), p.z()};
  return i;
}

acq::Item marker(int row, int col, const Point& p) {
  return stylus(acq::What::Marker, row, col, p);
}

acq::StylusInput sample(const Point& p, std::string status = "ok") {
  acq::StylusInput s;
  s.positionMm = {p.x(), p.y(), p.z()};
  s.status = std::move(status);
  return s;
}

testing::AssertionResult refusedWith(const rules::Refusal& r, const std::string& words) {
  if (!r) return testing::AssertionFailure() << "accepted; expected a refusal with \"" << words << "\"";
  if (r->find(words) == std::string::npos) return testing::AssertionFailure() << "refused with \"" << *r << "\"";
  return testing::AssertionSuccess();
}

}  // namespace

TEST(PointRules, SettleTakesTheMeanOfAStillPressAndRefusesTooFewMovingOrFaultySamples) {
  const acq::Settings settings;
  std::vector<acq::StylusInput> samples{sample({0, 0, 0}), sample({1, 0, 0}), sample({2, 0, 0})};
  std::vector<const acq::StylusInput*> window;
  for (const auto& s : samples) window.push_back(&s);
  const rules::Press still = rules::settle(window, settings);
  EXPECT_FALSE(still.refusal);
  EXPECT_DOUBLE_EQ(still.mean.x(), 1.0);  // spread 1 mm ≤ 1.5 mm

  samples[2] = sample({4, 0, 0});  // mean 5/3: 2.33 mm from the last sample
  EXPECT_TRUE(refusedWith(rules::settle(window, settings).refusal, "the stylus moved 2.3 mm during the press"));

  samples[2] = sample({2, 0, 0}, "E");
  EXPECT_TRUE(refusedWith(rules::settle(window, settings).refusal, "reported status 'E'"));

  window.pop_back();
  EXPECT_TRUE(refusedWith(rules::settle(window, settings).refusal, "too few stylus samples"));
}

TEST(PointRules, ADoublePressIsNearAndSoonAfterThePreviousPoint) {
  const acq::Settings settings;  // 2 mm, 0.5 s
  const std::vector<acq::Item> items{stylus(acq::What::Tip, 0, 0, {0, 0, 0}), marker(1, 1, {10, 0, 0})};
  const rules::Candidate near{{acq::What::Marker, 1, 2}, {11, 0, 0}, items, settings};
  EXPECT_TRUE(refusedWith(rules::doublePress(near, 1'200'000'000, 1'000'000'000), "1.0 mm from the previous one"));
  EXPECT_FALSE(rules::doublePress(near, 1'600'000'000, 1'000'000'000)) << "pressed 0.6 s later: a small leaf's row";
  EXPECT_FALSE(rules::doublePress(near, 1'200'000'000, -1)) << "nothing accepted by a press yet";
  const rules::Candidate far{{acq::What::Marker, 1, 2}, {14, 0, 0}, items, settings};
  EXPECT_FALSE(rules::doublePress(far, 1'200'000'000, 1'000'000'000));
  // After a move of the transmitter: a board point taken again is judged against the board
  // points taken again (the moved frame), a marker against the markers (the first frame).
  std::vector<acq::Item> moved = items;
  moved.push_back(stylus(acq::What::BoardAgain, 1, 1, {50, 50, 0}));
  const rules::Candidate again{{acq::What::BoardAgain, 1, 2}, {10.5, 0, 0}, moved, settings};
  EXPECT_FALSE(rules::doublePress(again, 1'200'000'000, 1'000'000'000)) << "the marker is in another frame";
  const rules::Candidate sameAgain{{acq::What::BoardAgain, 1, 2}, {50.5, 50, 0}, moved, settings};
  EXPECT_TRUE(refusedWith(rules::doublePress(sameAgain, 1'200'000'000, 1'000'000'000), "from the previous one"));
  const rules::Candidate nextMarker{{acq::What::Marker, 1, 2}, {50.5, 50, 0}, moved, settings};
  EXPECT_FALSE(rules::doublePress(nextMarker, 1'200'000'000, 1'000'000'000)) << "the board point is in another frame";
}

TEST(PointRules, TheBoardsAxesAreFarEnoughApart) {
  const acq::Settings settings;  // 20 mm
  std::vector<acq::Item> items{stylus(acq::What::Board, 0, 1, {0, 0, 0})};
  EXPECT_TRUE(refusedWith(rules::boardAxes({{acq::What::Board, 0, 2}, {12, 0, 0}, items, settings}),
                          "the +X point is only 12.0 mm from the origin"));
  EXPECT_FALSE(rules::boardAxes({{acq::What::Board, 0, 2}, {100, 0, 0}, items, settings}));
  items.push_back(stylus(acq::What::Board, 0, 2, {100, 0, 0}));
  EXPECT_TRUE(refusedWith(rules::boardAxes({{acq::What::Board, 0, 3}, {300, 5, 0}, items, settings}),
                          "the +Y point is only 5.0 mm off the X axis"));
  EXPECT_FALSE(rules::boardAxes({{acq::What::Board, 0, 3}, {30, 50, 0}, items, settings}));
}

TEST(PointRules, ARowGoesOneWayAndStartsOnTheRightMargin) {
  const acq::Settings settings;
  std::vector<acq::Item> items{marker(1, 1, {-30, 0, 0}), marker(1, 2, {-20, 0, 0})};
  // A turn of 180° (back along the row) is refused; the midrib's bend of 90° is not.
  EXPECT_TRUE(refusedWith(rules::rowDirection({{acq::What::Marker, 1, 3}, {-25, 0.5, 0}, items, settings}),
                          "point 3 goes back along row 1"));
  EXPECT_FALSE(rules::rowDirection({{acq::What::Marker, 1, 3}, {-20, 10, 0}, items, settings}));
  for (int c = 3; c <= 7; ++c) items.push_back(marker(1, c, {-30 + 10.0 * (c - 1), 0, 0}));
  // Row 2's first point: by row 1's point 1 (right margin), not by its point 7 (left).
  EXPECT_FALSE(rules::rowStart({{acq::What::Marker, 2, 1}, {-30, -10, 0}, items, settings}));
  EXPECT_TRUE(refusedWith(rules::rowStart({{acq::What::Marker, 2, 1}, {30, -10, 0}, items, settings}),
                          "this is by its point 7 (the left margin)"));
}

TEST(PointRules, ARowsSpacingStaysEven) {
  const acq::Settings settings;  // ±60 %
  const std::vector<acq::Item> items{marker(1, 1, {0, 0, 0}), marker(1, 2, {10, 0, 0}), marker(1, 3, {20, 0, 0})};
  EXPECT_FALSE(rules::evenSpacing({{acq::What::Marker, 1, 4}, {35, 0, 0}, items, settings}));  // 15 mm: +50 %
  EXPECT_TRUE(refusedWith(rules::evenSpacing({{acq::What::Marker, 1, 4}, {37, 0, 0}, items, settings}),
                          "uneven spacing: 17.0 mm from point 3, the row so far is 10.0 mm apart"));
  EXPECT_TRUE(refusedWith(rules::evenSpacing({{acq::What::Marker, 1, 4}, {23, 0, 0}, items, settings}),
                          "uneven spacing: 3.0 mm"));
}

TEST(PointRules, TheFourthPointIsOnTheMidribBelowTheRowBefore) {
  const acq::Settings settings;  // 15 mm
  std::vector<acq::Item> items{stylus(acq::What::Tip, 0, 0, {0, 0, 0}), marker(1, 4, {0, -20, 0})};
  EXPECT_FALSE(rules::onMidrib({{acq::What::Marker, 2, 4}, {3, -40, 0}, items, settings}));
  EXPECT_TRUE(refusedWith(rules::onMidrib({{acq::What::Marker, 2, 4}, {0, -10, 0}, items, settings}),
                          "row 2 must be farther from the tip than row 1"));
  EXPECT_TRUE(refusedWith(rules::onMidrib({{acq::What::Marker, 2, 4}, {20, -40, 0}, items, settings}),
                          "it is 20.0 mm off the line through the tip and row 1's midrib point"));
  items.push_back(marker(2, 4, {0, -40, 0}));
  EXPECT_TRUE(refusedWith(rules::onMidrib({{acq::What::Marker, 3, 4}, {-16, -60, 0}, items, settings}),
                          "off the line through the midrib points of rows 1 and 2"));
  // Rows other than point 4, and row 1, are not this rule's.
  EXPECT_FALSE(rules::onMidrib({{acq::What::Marker, 3, 3}, {-16, -60, 0}, items, settings}));
  EXPECT_FALSE(rules::onMidrib({{acq::What::Marker, 1, 4}, {100, 100, 0}, items, settings}));
}

TEST(PointRules, LineDistanceIsFromTheLineOrFromItsOnlyPoint) {
  EXPECT_DOUBLE_EQ(rules::lineDistance({0, 3, 4}, {-1, 0, 0}, {5, 0, 0}), 5.0);
  EXPECT_DOUBLE_EQ(rules::lineDistance({0, 3, 4}, {1, 0, 0}, {1, 0, 0}), std::sqrt(26.0));
}
