#include "leafdig/acquisition/protocol/engine.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "leafdig/acquisition/protocol/point_rules.hpp"
#include "leafdig/acquisition/protocol/relocation.hpp"
#include "leafdig/model/leaf/markers.hpp"
#include "leafdig/names/name_table.hpp"
#include "rigid_map.hpp"
#include "words.hpp"

namespace leafdig::acquisition {

namespace {

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
  if (relocating_) {
    // The board points again, from the moved transmitter; then the fit (col 0).
    for (int c = 1; c <= 3; ++c)
      if (!find(What::BoardAgain, relocating_, c)) return {What::BoardAgain, relocating_, c};
    return {What::BoardAgain, relocating_, 0};
  }
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
  // A move of the transmitter in progress: its board points first, they are what is asked now.
  if (relocating_)
    for (int c = 1; c <= 3; ++c) add({What::BoardAgain, relocating_, c});
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
    case What::BoardAgain:
      if (s.col == 0)
        return "Transmitter moved · every board point is taken again: hold the button (or End) to fit its new "
               "position";
      return "Transmitter moved · board point " + std::to_string(s.col) + " of 3 again · " + boardName(s.col) +
             " of the board";
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

Vec3 Engine::toFirst(const Vec3& p) const {
  return detail::placed(toFirst_.back(), p);
}

Decision Engine::onStylus(const StylusInput& sample) {
  // After a move of the transmitter every sample is taken into the first position's frame
  // before anything sees it (not while the board points are taken again: those are fitted).
  StylusInput s = sample;
  if (!relocating_ && toFirst_.size() > 1) s.positionMm = toFirst(sample.positionMm);
  Decision d;
  if (const auto end = press_.take(s, settings_)) {
    if (end->cut) return reject(cutPressWords(end->heldNs));
    const std::int64_t held = end->heldNs;
    if (held >= settings_.undoPressNs) return undo();
    if (held >= settings_.longPressNs)
      d = decideEndRows();
    else
      d = decidePoint(s);
    if (d.kind == Decision::Kind::Accepted || d.kind == Decision::Kind::RowsEnded ||
        d.kind == Decision::Kind::RelocationFitted)
      apply(d);
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
  if (st.what == What::BoardAgain && st.col == 0)
    return reject("every board point is taken again: hold the button (or End) to fit the transmitter's new position");
  // The still samples just before the press (and while it was held).
  const std::vector<const StylusInput*> window = press_.window(release.tNs, settings_);
  const rules::Press press = rules::settle(window, settings_);
  if (press.refusal) return reject(*press.refusal);
  // In this order: the first rule that refuses names the problem; the later ones are not run.
  const bool again = st.what == What::BoardAgain;
  const rules::Candidate candidate{st, press.mean, items_, settings_};
  if (auto refusal = rules::doublePress(candidate, press_.pressedAt(), lastAcceptedReleaseNs_)) return reject(*refusal);
  using Rule = rules::Refusal (*)(const rules::Candidate&);
  if (!again)
    for (const Rule rule :
         {&rules::boardAxes, &rules::rowDirection, &rules::rowStart, &rules::evenSpacing, &rules::onMidrib})
      if (auto refusal = rule(candidate)) return reject(*refusal);
  Decision d;
  d.kind = Decision::Kind::Accepted;
  d.item.what = st.what;
  d.item.row = st.row;
  d.item.col = st.col;
  d.item.positionMm = {press.mean.x(), press.mean.y(), press.mean.z()};
  d.item.raw = window.back()->raw;
  d.item.frame = again ? st.row : static_cast<int>(toFirst_.size()) - 1 + plantPosition_;
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
  if (relocating_ && (actions_.empty() || actions_.back() == kMoveStarted)) {
    d.kind = Decision::Kind::RelocationCancelled;  // no board point taken again yet: the move is undone
    d.relocation = relocating_;
    apply(d);
    return d;
  }
  if (retake_) {
    d.kind = Decision::Kind::RetakeCancelled;
    d.item = retakeOld_;
    apply(d);
    return d;
  }
  if (actions_.empty()) return reject("nothing to undo");
  if (actions_.back() == kMoveFitted) {
    d.kind = Decision::Kind::RelocationReopened;
    d.relocation = static_cast<int>(toFirst_.size()) - 1;
  } else if (actions_.back() == kRowsEnded) {
    d.kind = Decision::Kind::RowsReopened;
  } else {
    d.kind = Decision::Kind::Undone;
    d.item = items_[static_cast<std::size_t>(actions_.back())];
  }
  apply(d);
  return d;
}

Decision Engine::retake(What what, int row, int col) {
  if (relocating_) return reject("finish moving the transmitter first: " + prompt());
  if (retake_) return reject("finish the retake in progress first (or undo it)");
  if (what == What::BoardAgain)
    return reject(
        "a board point taken again after a move placed every later point: it cannot be retaken alone "
        "(undo back to it, or move the transmitter again)");
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
  Decision d = decideEndRows();
  apply(d);
  return d;
}

Decision Engine::decideEndRows() const {
  const Step st = step();
  if (st.what == What::BoardAgain) return fitOf(st.row);
  if (retake_) return reject("finish the retake first: " + prompt());
  if (st.what != What::Marker) return reject("the rows are already ended");
  if (st.col != 1)
    return reject("finish row " + std::to_string(st.row) + " first (point " + std::to_string(st.col) + " of 7)");
  if (completeRows() < settings_.minRows)
    return reject("a leaf needs at least " + std::to_string(settings_.minRows) + " rows");
  Decision d;
  d.kind = Decision::Kind::RowsEnded;
  return d;
}

Decision Engine::moveTransmitter() {
  if (!settings_.boardFrame)
    return reject(
        "a leaf's transmitter can move only when the capture began with the board frame (--board, the "
        "station's Board box): its three points are the landmarks taken again after the move");
  if (relocating_) return reject("the transmitter is being moved already: " + prompt());
  if (retake_) return reject("finish the retake first: " + prompt());
  for (int c = 1; c <= 3; ++c)
    if (!find(What::Board, 0, c))
      return reject("take the board's three points first: they are what a move is fitted to");
  if (complete()) return reject("the leaf is complete: there is nothing left to take from another position");
  Decision d;
  d.kind = Decision::Kind::RelocationStarted;
  d.relocation = static_cast<int>(toFirst_.size());
  apply(d);
  return d;
}

namespace {

// Move r's fit: the board points as first taken against the same points taken again.
RelocationFit fitBoardPoints(const std::vector<Item>& items, int relocation, double toleranceMm) {
  std::vector<Eigen::Vector3d> before, after;
  for (int c = 1; c <= 3; ++c) {
    const Item* b = findItem(items, What::Board, 0, c);
    const Item* a = findItem(items, What::BoardAgain, relocation, c);
    if (!b || !a) {
      RelocationFit missing;
      missing.refusal = "take board point " + std::to_string(c) + " (" + boardName(c) + ") again first";
      return missing;
    }
    before.emplace_back(b->positionMm[0], b->positionMm[1], b->positionMm[2]);
    after.emplace_back(a->positionMm[0], a->positionMm[1], a->positionMm[2]);
  }
  RelocationSettings rs;
  rs.toleranceMm = toleranceMm;
  rs.noun = "board point";
  rs.lineRemedy = "undo and take the board's origin, +X and +Y points again";
  RelocationFit fit = fitRelocation(before, after, rs);
  if (fit.refusal && fit.rmsMm > toleranceMm) {
    // Three points share a bad one's error in the fit; a move keeps their distances, so the
    // one that moved is the one outside the pair whose distance still agrees.
    const auto error = [&](int i, int j) {
      const auto u = static_cast<std::size_t>(i), v = static_cast<std::size_t>(j);
      return std::abs((before[u] - before[v]).norm() - (after[u] - after[v]).norm());
    };
    const double without[3] = {error(1, 2), error(0, 2), error(0, 1)};
    const int moved = static_cast<int>(std::min_element(without, without + 3) - without);
    const double off = std::max(error(moved, (moved + 1) % 3), error(moved, (moved + 2) % 3));
    fit.worstLandmark = moved + 1;
    fit.refusal = "the board points do not agree after the move (RMS " + detail::mm(fit.rmsMm) + ", more than " +
                  detail::mm(toleranceMm) + "): board point " + std::to_string(moved + 1) + " (" +
                  boardName(moved + 1) + ") moved: its distances to the others changed by up to " + detail::mm(off) +
                  " — it slipped, or was pressed elsewhere; undo and take it again";
  }
  return fit;
}

}  // namespace

BoardMoveFit fitBoardMove(const std::vector<Item>& items, int relocation, double toleranceMm) {
  const RelocationFit fit = fitBoardPoints(items, relocation, toleranceMm);
  BoardMoveFit out;
  out.toFirst = detail::mapOf(fit.newToOld);
  out.refusal = fit.refusal;
  return out;
}

Decision Engine::fitOf(int relocation) const {
  const RelocationFit fit = fitBoardPoints(items_, relocation, settings_.relocationToleranceMm);
  if (fit.refusal) return reject(*fit.refusal);
  Decision d;
  d.kind = Decision::Kind::RelocationFitted;
  d.relocation = relocation;
  d.fitRmsMm = fit.rmsMm;
  d.fitWorstMm = fit.worstMm;
  d.fitWorstPoint = fit.worstLandmark;
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
      actions_.push_back(kRowsEnded);
      break;
    case Decision::Kind::RowsReopened:
      rowsEnded_ = false;
      if (!actions_.empty() && actions_.back() == kRowsEnded) actions_.pop_back();
      break;
    case Decision::Kind::RelocationStarted:
      if (!relocating_ && d.relocation == static_cast<int>(toFirst_.size())) {
        relocating_ = d.relocation;
        actions_.push_back(kMoveStarted);
      }
      break;
    case Decision::Kind::RelocationFitted:
      if (relocating_ == d.relocation) {
        // Recomputed from the items: replay gives the same.
        const RelocationFit fit = fitBoardPoints(items_, d.relocation, settings_.relocationToleranceMm);
        if (fit.refusal) break;
        toFirst_.push_back(detail::mapOf(fit.newToOld));
        relocating_ = 0;
        actions_.push_back(kMoveFitted);
      }
      break;
    case Decision::Kind::RelocationReopened:
      if (!relocating_ && !actions_.empty() && actions_.back() == kMoveFitted && toFirst_.size() > 1) {
        actions_.pop_back();
        toFirst_.pop_back();
        relocating_ = static_cast<int>(toFirst_.size());
      }
      break;
    case Decision::Kind::RelocationCancelled:
      if (relocating_ && !actions_.empty() && actions_.back() == kMoveStarted) {
        actions_.pop_back();
        relocating_ = 0;
      }
      break;
    case Decision::Kind::Undone:
      if (!actions_.empty() && actions_.back() >= 0) erase(static_cast<std::size_t>(actions_.back()));
      break;
    default: break;
  }
}

}  // namespace leafdig::acquisition
