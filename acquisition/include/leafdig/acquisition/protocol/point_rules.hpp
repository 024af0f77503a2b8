#pragma once
// The rules a stylus point must pass before the marker protocol accepts it (docs/method.md,
// "The marker protocol"). Engine::decidePoint applies them in the order below; each is a
// function of the candidate point and what is already accepted, testable alone. A rule
// returns the words the technician reads when it refuses the point, or nothing.
#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "leafdig/acquisition/protocol/items.hpp"

namespace leafdig::acquisition::rules {

using Point = Eigen::Vector3d;
using Refusal = std::optional<std::string>;  // why the point is refused, in words

[[nodiscard]] inline Point toPoint(const Vec3& v) {
  return {v[0], v[1], v[2]};
}

// A point the technician pressed for: the step it is for and where the stylus was.
struct Candidate {
  Step step;
  Point point;
  const std::vector<Item>& items;  // accepted so far, in order
  const Settings& settings;
};

// The press: the stylus samples from stillWindow before the press to the release. Fewer
// than three, a status other than "ok" or a spread above stillTolerance refuse it; else
// `mean` is the point.
struct Press {
  Point mean = Point::Zero();
  Refusal refusal;
};
[[nodiscard]] Press settle(const std::vector<const StylusInput*>& window, const Settings& settings);

// A second press close to the previous accepted point and right after it (distance alone
// would refuse the 2 mm rows near the tip of a small leaf). The previous point is the last one
// in the candidate's frame: a board point taken again after a move of the transmitter is
// judged against the board points taken again (they are in the moved transmitter's frame).
[[nodiscard]] Refusal doublePress(const Candidate& c, std::int64_t pressedAtNs, std::int64_t lastAcceptedReleaseNs);
// The same rule for any capture: `previous` is the last accepted stylus point, if any.
[[nodiscard]] Refusal doublePressNear(const Point& candidate, const std::optional<Point>& previous,
                                      std::int64_t pressedAtNs, std::int64_t lastAcceptedReleaseNs,
                                      const Settings& settings);
// The board's +X point away from the origin, its +Y point away from the X axis.
[[nodiscard]] Refusal boardAxes(const Candidate& c);
// Going back along a row: the path turns by more than 150° (a row bends at most at the
// midrib, where the lateral veins meet at 60–100°).
[[nodiscard]] Refusal rowDirection(const Candidate& c);
// A row starts on the right margin: nearer the previous row's first point than its last.
[[nodiscard]] Refusal rowStart(const Candidate& c);
// Points 3–7 of a row within spacingTolerance of the row's mean spacing so far.
[[nodiscard]] Refusal evenSpacing(const Candidate& c);
// Point 4 of rows 2… farther from the tip than the row before, on the midrib's line.
[[nodiscard]] Refusal onMidrib(const Candidate& c);

// Distance of p from the line through a and b (from a when a and b coincide).
[[nodiscard]] double lineDistance(const Point& p, const Point& a, const Point& b);

}  // namespace leafdig::acquisition::rules
