#include "leafdig/acquisition/protocol/point_rules.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

#include "words.hpp"

namespace leafdig::acquisition::rules {

namespace {

using detail::mm;

// The accepted stylus point (what, row, col), if there is one.
std::optional<Point> at(const Candidate& c, What w, int row, int col) {
  const Item* i = findItem(c.items, w, row, col);
  if (!i) return std::nullopt;
  return toPoint(i->positionMm);
}

std::string num(int v) {
  return std::to_string(v);
}

}  // namespace

double lineDistance(const Point& p, const Point& a, const Point& b) {
  const Point ab = b - a;
  const double len = ab.norm();
  if (len < 1e-9) return (p - a).norm();
  return ab.cross(p - a).norm() / len;
}

Press settle(const std::vector<const StylusInput*>& window, const Settings& settings) {
  Press out;
  if (window.size() < 3) {
    out.refusal = "too few stylus samples around the press: is the digitizer streaming? Press again";
    return out;
  }
  const double n = static_cast<double>(window.size());
  for (const auto* s : window) out.mean += toPoint(s->positionMm) / n;
  double worst = 0;
  for (const auto* s : window) {
    worst = std::max(worst, (toPoint(s->positionMm) - out.mean).norm());
    if (s->status != "ok") {
      out.refusal = "the digitizer reported status '" + s->status + "' during the press: retake the point";
      return out;
    }
  }
  if (worst > settings.stillToleranceMm)
    out.refusal = "the stylus moved " + mm(worst) + " during the press: hold it still on the marker and press again";
  return out;
}

Refusal doublePressNear(const Point& candidate, const std::optional<Point>& previous, std::int64_t pressedAtNs,
                        std::int64_t lastAcceptedReleaseNs, const Settings& settings) {
  if (!previous) return std::nullopt;
  const double d = (*previous - candidate).norm();
  if (d < settings.doubleTapMm && lastAcceptedReleaseNs >= 0 &&
      pressedAtNs - lastAcceptedReleaseNs < settings.doubleTapNs)
    return "this point is " + mm(d) + " from the previous one: a double press? Move to the next marker";
  return std::nullopt;
}

Refusal doublePress(const Candidate& c, std::int64_t pressedAtNs, std::int64_t lastAcceptedReleaseNs) {
  const bool again = c.step.what == What::BoardAgain;
  const auto last = std::find_if(c.items.rbegin(), c.items.rend(), [&](const Item& i) {
    return isStylusItem(i.what) && (i.what == What::BoardAgain) == again;
  });
  if (last == c.items.rend()) return std::nullopt;
  return doublePressNear(c.point, toPoint(last->positionMm), pressedAtNs, lastAcceptedReleaseNs, c.settings);
}

Refusal boardAxes(const Candidate& c) {
  if (c.step.what != What::Board || c.step.col < 2) return std::nullopt;
  const std::optional<Point> origin = at(c, What::Board, 0, 1);
  const std::optional<Point> xAxis = at(c, What::Board, 0, 2);
  const double minMm = c.settings.boardMinMm;
  if (c.step.col == 2 && origin && (c.point - *origin).norm() < minMm)
    return "the +X point is only " + mm((c.point - *origin).norm()) + " from the origin: take it at least " +
           mm(minMm) + " away along the board's X edge";
  if (c.step.col == 3 && origin && xAxis && lineDistance(c.point, *origin, *xAxis) < minMm)
    return "the +Y point is only " + mm(lineDistance(c.point, *origin, *xAxis)) + " off the X axis: take it at least " +
           mm(minMm) + " to the side";
  return std::nullopt;
}

Refusal rowDirection(const Candidate& c) {
  const Step& st = c.step;
  if (st.what != What::Marker || st.col <= 2) return std::nullopt;
  const std::optional<Point> prev = at(c, What::Marker, st.row, st.col - 1);
  const std::optional<Point> prev2 = at(c, What::Marker, st.row, st.col - 2);
  if (!prev || !prev2) return std::nullopt;
  const Point a = *prev - *prev2;
  const Point b = c.point - *prev;
  const double na = a.norm(), nb = b.norm();
  if (na > 0 && nb > 0 && a.dot(b) / (na * nb) < std::cos(150.0 * std::numbers::pi / 180.0))
    return "point " + num(st.col) + " goes back along row " + num(st.row) +
           " (markers are taken right to left): take point " + num(st.col);
  return std::nullopt;
}

Refusal rowStart(const Candidate& c) {
  const Step& st = c.step;
  if (st.what != What::Marker || st.col != 1 || st.row < 2) return std::nullopt;
  const std::optional<Point> right = at(c, What::Marker, st.row - 1, 1);
  const std::optional<Point> left = at(c, What::Marker, st.row - 1, kMarkersPerRow);
  if (right && left && (c.point - *left).norm() < (c.point - *right).norm())
    return "row " + num(st.row) + " starts on the right margin, by row " + num(st.row - 1) +
           "'s point 1; this is by its point 7 (the left margin)";
  return std::nullopt;
}

Refusal evenSpacing(const Candidate& c) {
  const Step& st = c.step;
  if (st.what != What::Marker || st.col < 3) return std::nullopt;
  const std::optional<Point> prev = at(c, What::Marker, st.row, st.col - 1);
  if (!prev) return std::nullopt;
  double sum = 0;
  for (int col = 2; col < st.col; ++col) {
    const std::optional<Point> here = at(c, What::Marker, st.row, col);
    const std::optional<Point> before = at(c, What::Marker, st.row, col - 1);
    if (!here || !before) return std::nullopt;  // the engine fills a row in order: not reached
    sum += (*here - *before).norm();
  }
  const double spacing = sum / (st.col - 2);
  const double gap = (c.point - *prev).norm();
  const double tol = c.settings.spacingTolerance;
  if (gap < (1 - tol) * spacing || gap > (1 + tol) * spacing)
    return "uneven spacing: " + mm(gap) + " from point " + num(st.col - 1) + ", the row so far is " + mm(spacing) +
           " apart; was a marker skipped?";
  return std::nullopt;
}

Refusal onMidrib(const Candidate& c) {
  const Step& st = c.step;
  if (st.what != What::Marker || st.col != 4 || st.row < 2) return std::nullopt;
  const std::optional<Point> tip = at(c, What::Tip, 0, 0);
  const std::optional<Point> above = at(c, What::Marker, st.row - 1, 4);
  // The midrib's local direction: the two midrib points above (or the tip and row 1).
  const std::optional<Point> above2 = st.row >= 3 ? at(c, What::Marker, st.row - 2, 4) : tip;
  if (!tip || !above || !above2) return std::nullopt;
  if ((c.point - *tip).norm() <= (*above - *tip).norm())
    return "row " + num(st.row) + " must be farther from the tip than row " + num(st.row - 1);
  const double off = lineDistance(c.point, *above2, *above);
  if (off > c.settings.midribToleranceMm)
    return "the 4th point should be on the midrib: it is " + mm(off) + " off the line through " +
           (st.row >= 3 ? "the midrib points of rows " + num(st.row - 2) + " and " + num(st.row - 1)
                        : std::string("the tip and row 1's midrib point"));
  return std::nullopt;
}

}  // namespace leafdig::acquisition::rules
