#include "leafdig/acquisition/engine.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "leafdig/acquisition/enum_names.hpp"
#include "leafdig/model/leaf/markers.hpp"

namespace leafdig::acquisition {

static_assert(kMarkersPerRow == model::kMarkersPerRow);

namespace {

// Distance of p from the line through a and b.
double lineDistance(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 ab{b[0] - a[0], b[1] - a[1], b[2] - a[2]};
  const Vec3 ap{p[0] - a[0], p[1] - a[1], p[2] - a[2]};
  const double len = std::sqrt(ab[0] * ab[0] + ab[1] * ab[1] + ab[2] * ab[2]);
  if (len < 1e-9) return distanceMm(p, a);
  const Vec3 c{ab[1] * ap[2] - ab[2] * ap[1], ab[2] * ap[0] - ab[0] * ap[2], ab[0] * ap[1] - ab[1] * ap[0]};
  return std::sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]) / len;
}

std::string mm(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.1f mm", v);
  return b;
}

const char* colName(int col) {
  switch (col) {
    case 1: return "right margin";
    case 2:
    case 3: return "right lateral vein";
    case 4: return "midrib";
    case 5:
    case 6: return "left lateral vein";
    case 7: return "left margin";
    default: return "";
  }
}

const char* boardName(int col) {
  return col == 1 ? "origin" : col == 2 ? "+X direction" : "+Y side";
}

}  // namespace

bool isStylusItem(What w) {
  return w == What::Board || w == What::Tip || w == What::Marker;
}

double distanceMm(const Vec3& a, const Vec3& b) {
  return std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]));
}

const Item* findItem(const std::vector<Item>& items, What w, int row, int col) {
  for (const Item& i : items)
    if (i.what == w && i.row == row && i.col == col) return &i;
  return nullptr;
}

int completeRows(const std::vector<Item>& items) {
  const auto markersIn = [&](int row) {
    int n = 0;
    for (const Item& i : items) n += i.what == What::Marker && i.row == row;
    return n;
  };
  int r = 0;
  while (markersIn(r + 1) == 7) ++r;
  return r;
}

namespace {

constexpr NameTable<Mode, 3> kModeNames{{{Mode::Standard, "standard"}, {Mode::Full, "full"}, {Mode::Small, "small"}}};
constexpr NameTable<Order, 2> kOrderNames{{{Order::Sequential, "sequential"}, {Order::Interleaved, "interleaved"}}};
constexpr NameTable<What, 8> kWhatNames{{{What::Board, "board"},
                                         {What::Tip, "tip"},
                                         {What::Marker, "marker"},
                                         {What::MidribThickness, "midrib_thickness"},
                                         {What::VeinOriginThickness, "vein_origin_thickness"},
                                         {What::EdgeThickness, "edge_thickness"},
                                         {What::PointThickness, "point_thickness"},
                                         {What::Done, "done"}}};

}  // namespace

const char* toString(Mode m) {
  return nameIn(kModeNames, m);
}
const char* toString(Order o) {
  return nameIn(kOrderNames, o);
}
Mode modeFromString(const std::string& s) {
  if (const auto m = valueIn(kModeNames, s)) return *m;
  throw std::invalid_argument("unknown capture mode '" + s + "': use standard, full or small");
}
Order orderFromString(const std::string& s) {
  if (const auto o = valueIn(kOrderNames, s)) return *o;
  throw std::invalid_argument("unknown capture order '" + s + "': use sequential or interleaved");
}

const char* toString(What w) {
  return nameIn(kWhatNames, w);
}

What whatFromString(const std::string& s) {
  // "done" names the end of the protocol, not an item.
  if (const auto w = valueIn(kWhatNames, s); w && *w != What::Done) return *w;
  throw std::invalid_argument("unknown item '" + s +
                              "': use board, tip, marker, midrib_thickness, vein_origin_thickness, edge_thickness or "
                              "point_thickness");
}

Engine::Engine(Settings s) : settings_(s) {}

const Item* Engine::find(What w, int row, int col) const {
  return findItem(items_, w, row, col);
}

int Engine::markersInRow(int row) const {
  int n = 0;
  for (const Item& i : items_) n += i.what == What::Marker && i.row == row;
  return n;
}

int Engine::completeRows() const {
  return acquisition::completeRows(items_);
}

std::vector<Step> Engine::thicknessSteps(int row) const {
  std::vector<Step> s;
  switch (settings_.mode) {
    case Mode::Standard:
      s.push_back({What::MidribThickness, row, 4});
      s.push_back({What::VeinOriginThickness, row, 4});
      break;
    case Mode::Small: s.push_back({What::MidribThickness, row, 4}); break;
    case Mode::Full:
      s.push_back({What::MidribThickness, row, 4});
      for (int c = 1; c <= 7; ++c) s.push_back({What::PointThickness, row, c});
      break;
  }
  return s;
}

Step Engine::step() const {
  if (retake_) return *retake_;
  if (settings_.boardFrame)
    for (int c = 1; c <= 3; ++c)
      if (!find(What::Board, 0, c)) return {What::Board, 0, c};
  if (!find(What::Tip, 0, 0)) return {What::Tip, 0, 0};
  const int rows = completeRows();
  const bool interleaved = settings_.order == Order::Interleaved;
  if (interleaved) {
    for (int r = 1; r <= rows; ++r)
      for (const Step& s : thicknessSteps(r))
        if (!find(s.what, s.row, s.col)) return s;
  }
  if (!rowsEnded_) return {What::Marker, rows + 1, markersInRow(rows + 1) + 1};
  if (!interleaved) {
    for (int r = 1; r <= rows; ++r)
      for (const Step& s : thicknessSteps(r))
        if (!find(s.what, s.row, s.col)) return s;
  }
  if (settings_.mode != Mode::Full && !find(What::EdgeThickness, 0, 0)) return {What::EdgeThickness, 0, 0};
  return {What::Done, 0, 0};
}

std::vector<PlannedStep> Engine::plan() const {
  std::vector<PlannedStep> out;
  const Step current = step();
  const auto add = [&](const Step& s) {
    PlannedStep p{s, PlannedStep::State::Pending};
    if (s == current)
      p.state = PlannedStep::State::Current;
    else if (find(s.what, s.row, s.col))
      p.state = PlannedStep::State::Done;
    out.push_back(p);
  };
  const auto addRow = [&](int row) {
    for (int c = 1; c <= kMarkersPerRow; ++c) add({What::Marker, row, c});
  };
  // A row is complete for the plan when only a retaken point is missing from it.
  const auto complete = [&](int row) {
    const bool retaken = retake_ && retake_->what == What::Marker && retake_->row == row;
    return markersInRow(row) + (retaken ? 1 : 0) == kMarkersPerRow;
  };
  if (settings_.boardFrame)
    for (int c = 1; c <= 3; ++c) add({What::Board, 0, c});
  add({What::Tip, 0, 0});
  int lastRow = 0;
  for (const Item& i : items_)
    if (i.what == What::Marker) lastRow = std::max(lastRow, i.row);
  if (retake_ && retake_->what == What::Marker) lastRow = std::max(lastRow, retake_->row);
  const bool interleaved = settings_.order == Order::Interleaved;
  for (int r = 1; r <= lastRow; ++r) {
    addRow(r);
    if (interleaved && complete(r))
      for (const Step& s : thicknessSteps(r)) add(s);
  }
  if (!rowsEnded_ && (lastRow == 0 || complete(lastRow))) addRow(lastRow + 1);
  if (rowsEnded_ && !interleaved)
    for (int r = 1; r <= lastRow; ++r)
      if (complete(r))
        for (const Step& s : thicknessSteps(r)) add(s);
  if (rowsEnded_ && settings_.mode != Mode::Full) add({What::EdgeThickness, 0, 0});
  return out;
}

std::string Engine::prompt() const {
  const Step s = step();
  const std::string row = "Row " + std::to_string(s.row) + " · ";
  const std::string again = retake_ ? "Retake · " : "";
  switch (s.what) {
    case What::Board:
      return again + "Board frame · point " + std::to_string(s.col) + " of 3 · " + boardName(s.col) + " of the board";
    case What::Tip: return again + "Tip: touch the leaf tip and press";
    case What::Marker: {
      std::string p = again + row + "point " + std::to_string(s.col) + " of 7 · " + colName(s.col);
      if (!retake_ && s.col == 1 && s.row > settings_.minRows)
        p += "  (or hold the button to end the rows; the last row is at the leaf base)";
      return p;
    }
    case What::MidribThickness: return again + row + "back side · midrib thickness (r¹) with the caliper";
    case What::VeinOriginThickness:
      return again + row + "back side · lateral vein origin thickness (r²) with the caliper";
    case What::PointThickness:
      return again + row + "back side · thickness at point " + std::to_string(s.col) + " (" + colName(s.col) + ")";
    case What::EdgeThickness: return again + "Margin thickness (d) with the caliper";
    case What::Done: return "Leaf complete";
  }
  return "";
}

Decision Engine::reject(std::string reason) const {
  Decision d;
  d.kind = Decision::Kind::Rejected;
  d.reason = std::move(reason);
  return d;
}

Decision Engine::onStylus(const StylusInput& s) {
  recent_.push_back(s);
  while (!recent_.empty() && s.tNs - recent_.front().tNs > 3 * settings_.stillWindowNs + settings_.longPressNs)
    recent_.pop_front();
  Decision d;
  if (s.button && !pressed_) {
    pressed_ = true;
    pressedAt_ = s.tNs;
  } else if (!s.button && pressed_) {
    pressed_ = false;
    const std::int64_t held = s.tNs - pressedAt_;
    if (held >= settings_.undoPressNs) return undo();
    if (held >= settings_.longPressNs)
      d = decideEndRows();
    else
      d = decidePoint(s);
    if (d.kind == Decision::Kind::Accepted || d.kind == Decision::Kind::RowsEnded) apply(d);
    if (d.kind == Decision::Kind::Accepted) lastAcceptedReleaseNs_ = s.tNs;
  }
  return d;
}

Decision Engine::decidePoint(const StylusInput& release) {
  const Step st = step();
  if (!isStylusItem(st.what)) {
    if (st.what == What::Done) return reject("the leaf is complete: nothing more to point at");
    return reject("now measure with the caliper: " + prompt());
  }
  // The still samples just before the press (and while it was held).
  std::vector<const StylusInput*> window;
  for (const StylusInput& s : recent_)
    if (s.tNs >= pressedAt_ - settings_.stillWindowNs && s.tNs <= release.tNs) window.push_back(&s);
  if (window.size() < 3)
    return reject("too few stylus samples around the press: is the digitizer streaming? Press again");
  Vec3 mean{};
  for (const auto* s : window)
    for (std::size_t k = 0; k < 3; ++k) mean[k] += s->positionMm[k] / static_cast<double>(window.size());
  double worst = 0;
  for (const auto* s : window) {
    worst = std::max(worst, distanceMm(s->positionMm, mean));
    if (s->status != "ok")
      return reject("the digitizer reported status '" + s->status + "' during the press: retake the point");
  }
  if (worst > settings_.stillToleranceMm)
    return reject("the stylus moved " + mm(worst) + " during the press: hold it still on the marker and press again");

  Item item;
  item.what = st.what;
  item.row = st.row;
  item.col = st.col;
  item.positionMm = mean;
  item.raw = window.back()->raw;
  // Double tap: close to the previous accepted point and pressed right after it. (Distance
  // alone would refuse the 2 mm rows near the tip of a small leaf.)
  for (auto it = items_.rbegin(); it != items_.rend(); ++it) {
    if (!isStylusItem(it->what)) continue;
    const double d = distanceMm(it->positionMm, mean);
    if (d < settings_.doubleTapMm && lastAcceptedReleaseNs_ >= 0 &&
        pressedAt_ - lastAcceptedReleaseNs_ < settings_.doubleTapNs)
      return reject("this point is " + mm(d) + " from the previous one: a double press? Move to the next marker");
    break;
  }
  if (st.what == What::Board && st.col >= 2) {
    const Item* origin = find(What::Board, 0, 1);
    const Item* xAxis = find(What::Board, 0, 2);
    if (st.col == 2 && origin && distanceMm(mean, origin->positionMm) < settings_.boardMinMm)
      return reject("the +X point is only " + mm(distanceMm(mean, origin->positionMm)) +
                    " from the origin: take it at least " + mm(settings_.boardMinMm) +
                    " away along the board's X edge");
    if (st.col == 3 && origin && xAxis &&
        lineDistance(mean, origin->positionMm, xAxis->positionMm) < settings_.boardMinMm)
      return reject("the +Y point is only " + mm(lineDistance(mean, origin->positionMm, xAxis->positionMm)) +
                    " off the X axis: take it at least " + mm(settings_.boardMinMm) + " to the side");
  }
  if (st.what == What::Marker) {
    const Item* prev = st.col > 1 ? find(What::Marker, st.row, st.col - 1) : nullptr;
    const Item* prev2 = st.col > 2 ? find(What::Marker, st.row, st.col - 2) : nullptr;
    if (prev && prev2) {
      // Going back along the row: the path turns by more than 150° (a row bends at most at
      // the midrib, where the lateral veins meet at 60-100°).
      const Vec3 a{prev->positionMm[0] - prev2->positionMm[0], prev->positionMm[1] - prev2->positionMm[1],
                   prev->positionMm[2] - prev2->positionMm[2]};
      const Vec3 b{mean[0] - prev->positionMm[0], mean[1] - prev->positionMm[1], mean[2] - prev->positionMm[2]};
      const double na = distanceMm(a, {0, 0, 0}), nb = distanceMm(b, {0, 0, 0});
      if (na > 0 && nb > 0 &&
          (a[0] * b[0] + a[1] * b[1] + a[2] * b[2]) / (na * nb) < std::cos(150.0 * 3.141592653589793 / 180.0))
        return reject("point " + std::to_string(st.col) + " goes back along row " + std::to_string(st.row) +
                      " (markers are taken right to left): take point " + std::to_string(st.col));
    }
    // A row starts on the right margin: its first point lies nearer the previous row's first
    // point than that row's last (left-margin) one. A second, slow press on the last point of
    // the row before (outside the double-tap window) would otherwise become this row's first
    // point and shift every point after it.
    if (st.col == 1 && st.row >= 2) {
      const Item* right = find(What::Marker, st.row - 1, 1);
      const Item* left = find(What::Marker, st.row - 1, 7);
      if (right && left && distanceMm(mean, left->positionMm) < distanceMm(mean, right->positionMm))
        return reject("row " + std::to_string(st.row) + " starts on the right margin, by row " +
                      std::to_string(st.row - 1) + "'s point 1; this is by its point 7 (the left margin)");
    }
    if (st.col >= 3 && prev) {
      double sum = 0;
      for (int c = 2; c < st.col; ++c)
        sum += distanceMm(find(What::Marker, st.row, c)->positionMm, find(What::Marker, st.row, c - 1)->positionMm);
      const double spacing = sum / (st.col - 2);
      const double here = distanceMm(mean, prev->positionMm);
      if (here < (1 - settings_.spacingTolerance) * spacing || here > (1 + settings_.spacingTolerance) * spacing)
        return reject("uneven spacing: " + mm(here) + " from point " + std::to_string(st.col - 1) +
                      ", the row so far is " + mm(spacing) + " apart; was a marker skipped?");
    }
    if (st.col == 4 && st.row >= 2) {
      const Item* tip = find(What::Tip, 0, 0);
      const Item* above = find(What::Marker, st.row - 1, 4);
      // The midrib's local direction: the two midrib points above (or the tip and row 1).
      const Item* above2 = st.row >= 3 ? find(What::Marker, st.row - 2, 4) : tip;
      if (tip && above && above2) {
        if (distanceMm(mean, tip->positionMm) <= distanceMm(above->positionMm, tip->positionMm))
          return reject("row " + std::to_string(st.row) + " must be farther from the tip than row " +
                        std::to_string(st.row - 1));
        const double off = lineDistance(mean, above2->positionMm, above->positionMm);
        if (off > settings_.midribToleranceMm)
          return reject("the 4th point should be on the midrib: it is " + mm(off) + " off the line through " +
                        (st.row >= 3 ? "the midrib points of rows " + std::to_string(st.row - 2) + " and " +
                                           std::to_string(st.row - 1)
                                     : std::string("the tip and row 1's midrib point")));
      }
    }
  }
  Decision d;
  d.kind = Decision::Kind::Accepted;
  d.item = item;
  return d;
}

Decision Engine::onCaliper(const CaliperInput& c) {
  const Step st = step();
  if (isStylusItem(st.what)) return reject("a caliper reading now? " + prompt() + " first");
  if (st.what == What::Done) return reject("the leaf is complete: the reading was not used");
  if (!(c.valueMm >= settings_.minThicknessMm && c.valueMm <= settings_.maxThicknessMm)) {
    char b[160];
    std::snprintf(b, sizeof b, "a thickness of %.3f mm is outside %g–%g mm: check the unit and the jaws, measure again",
                  c.valueMm, settings_.minThicknessMm, settings_.maxThicknessMm);
    return reject(b);
  }
  Decision d;
  d.kind = Decision::Kind::Accepted;
  d.item.what = st.what;
  d.item.row = st.row;
  d.item.col = st.col;
  d.item.valueMm = c.valueMm;
  d.item.raw = c.raw;
  if (lastReadingAt_ >= 0 && c.tNs - lastReadingAt_ <= settings_.repeatWindowNs && c.valueMm == lastReading_)
    d.item.flag = "repeated reading";  // kept, flagged for the curator
  lastReadingAt_ = c.tNs;
  lastReading_ = c.valueMm;
  apply(d);
  return d;
}

Decision Engine::undo() {
  Decision d;
  if (retake_) {
    d.kind = Decision::Kind::RetakeCancelled;
    d.item = retakeOld_;
    apply(d);
    return d;
  }
  if (actions_.empty()) return reject("nothing to undo");
  if (actions_.back() < 0) {
    d.kind = Decision::Kind::RowsReopened;
  } else {
    d.kind = Decision::Kind::Undone;
    d.item = items_[static_cast<std::size_t>(actions_.back())];
  }
  apply(d);
  return d;
}

Decision Engine::retake(What what, int row, int col) {
  if (retake_) return reject("finish the retake in progress first (or undo it)");
  const Item* old = find(what, row, col);
  if (!old) {
    std::string where = toString(what);
    if (row > 0) where += " row " + std::to_string(row);
    if (col > 0) where += " point " + std::to_string(col);
    return reject("nothing was captured as " + where + " yet: there is nothing to retake");
  }
  Decision d;
  d.kind = Decision::Kind::RetakeStarted;
  d.item = *old;
  apply(d);
  return d;
}

void Engine::erase(std::size_t index) {
  items_.erase(items_.begin() + static_cast<std::ptrdiff_t>(index));
  std::vector<int> kept;
  for (int a : actions_) {
    if (a == static_cast<int>(index)) continue;
    kept.push_back(a > static_cast<int>(index) ? a - 1 : a);
  }
  actions_ = std::move(kept);
}

Decision Engine::endRows() {
  const Decision d = decideEndRows();
  apply(d);
  return d;
}

Decision Engine::decideEndRows() const {
  if (retake_) return reject("finish the retake first: " + prompt());
  const Step st = step();
  if (st.what != What::Marker) return reject("the rows are already ended");
  if (st.col != 1)
    return reject("finish row " + std::to_string(st.row) + " first (point " + std::to_string(st.col) + " of 7)");
  if (completeRows() < settings_.minRows)
    return reject("a leaf needs at least " + std::to_string(settings_.minRows) + " rows");
  Decision d;
  d.kind = Decision::Kind::RowsEnded;
  return d;
}

void Engine::apply(const Decision& d) {
  switch (d.kind) {
    case Decision::Kind::Accepted:
      items_.push_back(d.item);
      actions_.push_back(static_cast<int>(items_.size()) - 1);
      if (retake_ && retake_->what == d.item.what && retake_->row == d.item.row && retake_->col == d.item.col)
        retake_.reset();
      break;
    case Decision::Kind::RetakeStarted:
      for (std::size_t i = 0; i < items_.size(); ++i)
        if (items_[i].what == d.item.what && items_[i].row == d.item.row && items_[i].col == d.item.col) {
          erase(i);
          retake_ = Step{d.item.what, d.item.row, d.item.col};
          retakeOld_ = d.item;
          break;
        }
      break;
    case Decision::Kind::RetakeCancelled:
      if (retake_) {
        items_.push_back(d.item);
        actions_.push_back(static_cast<int>(items_.size()) - 1);
        retake_.reset();
      }
      break;
    case Decision::Kind::RowsEnded:
      rowsEnded_ = true;
      actions_.push_back(-1);
      break;
    case Decision::Kind::RowsReopened:
      rowsEnded_ = false;
      if (!actions_.empty() && actions_.back() < 0) actions_.pop_back();
      break;
    case Decision::Kind::Undone:
      if (!actions_.empty() && actions_.back() >= 0) erase(static_cast<std::size_t>(actions_.back()));
      break;
    default: break;
  }
}

}  // namespace leafdig::acquisition
