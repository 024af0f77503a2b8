#include "leafdig/acquisition/review/correction.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iomanip>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "leafdig/acquisition/review/review.hpp"
#include "leafdig/acquisition/session/plant_session.hpp"
#include "leafdig/db/history.hpp"
#include "leafdig/model/errors.hpp"
#include "leafdig/model/io/survey_export.hpp"
#include "leafdig/model/limits.hpp"
#include "protocol/item_json.hpp"
#include "protocol/plant_item_json.hpp"
#include "protocol/rigid_map.hpp"
#include "review_checks.hpp"

namespace leafdig::acquisition {

namespace {

using detail::isBlank;
using detail::itemJson;
using detail::keyOf;
using detail::leafWhat;
using detail::plantItemJson;
using detail::projectionOf;
using detail::requireChain;
using nlohmann::json;
namespace m = leafdig::model;

// What a curator's correction of session `id` needs before anything is read (a leaf's and a
// plant's alike): a complete session (approved and rejected are final, open is still being
// captured), a reason, a name, and a chain that verifies. std::invalid_argument / SessionError.
void requireCorrectable(const db::EventStore& store, std::int64_t id, const std::string& status,
                        const std::string& reason, const std::string& who) {
  if (status != "complete")
    throw std::invalid_argument("session " + std::to_string(id) + " is " + status +
                                ": only a complete session (awaiting review) can be corrected");
  if (isBlank(reason)) throw std::invalid_argument("a correction needs a reason: say what was wrong");
  if (isBlank(who)) throw std::invalid_argument("a correction needs the curator's name");
  requireChain(store, id, "corrected");
}

// A corrected point that would move further than `limitMm` from where it was (both in the frame
// `sessions show` gives) is refused until the curator confirms the move (issue 49).
void requireConfirmedMove(const Vec3& from, const Vec3& to, double limitMm, const std::string& item) {
  const double d = distanceMm(from, to);
  if (d <= limitMm) return;
  std::ostringstream t;
  t << std::fixed << std::setprecision(1) << "the " << item << " would move " << d << " mm, more than the " << limitMm
    << " mm a correction moves unconfirmed: check the position (x, y, z in mm, as sessions show gives it), then "
       "confirm the move (--confirm); nothing was written";
  throw UnconfirmedMove(t.str(), d);
}

}  // namespace

void setCorrectionItem(Correction& c, const std::string& word, int node) {
  c.node = node;
  c.plantWhat.reset();
  try {
    c.what = whatFromString(word);
    return;
  } catch (const std::invalid_argument&) {
  }
  try {
    c.plantWhat = plantWhatFromString(word);
  } catch (const std::invalid_argument&) {
    throw std::invalid_argument(word +
                                " is not an item: a leaf's board, board_again, tip, marker, midrib_thickness, "
                                "vein_origin_thickness, point_thickness or edge_thickness; a plant's landmark, "
                                "landmark_again, collar, collar_diameter, point, reading or quick_point");
  }
  if (node > 0)
    throw std::invalid_argument("node " + std::to_string(node) +
                                " is a full leaf: its items are tip, marker and the thicknesses, not " + word);
}

namespace {

// A curator's correction of one item as stored: the old item, the event it replaces, the
// corrected one, why and who.
db::EventInput correctionEvent(const Item& old, const Item& fixed, std::int64_t seq, const std::string& reason,
                               const std::string& who) {
  json payload = detail::itemJson(old);
  payload["seq"] = seq;
  payload["corrected"] = detail::itemJson(fixed);
  payload["reason"] = reason;
  payload["who"] = who;
  db::EventInput ev;
  ev.kind = "corrected";
  ev.payloadJson = payload.dump();
  ev.raw = fixed.raw;
  ev.projection = detail::projectionOf(fixed);
  ev.retracts = seq;
  return ev;
}

// A position given in the plant frame, in the digitizer's first frame: through the plant frame the
// session's points make now (std::invalid_argument when they make none yet).
Vec3 fromPlantFrame(const PlantEngine& engine, const std::string& plant, const Vec3& p) {
  m::PlantFrame frame;
  try {
    frame = m::surveyPlant(engine.captured(plant)).frame;
  } catch (const m::InputError& e) {
    throw std::invalid_argument(std::string("a position in the plant frame needs the plant's frame, which this "
                                            "session's points do not make (") +
                                e.what() + "): give it in the digitizer's frame (--frame digitizer)");
  }
  const Eigen::Vector3d d = frame.fromDigitizer.inverse() * Eigen::Vector3d(p[0], p[1], p[2]);
  return Vec3{d.x(), d.y(), d.z()};
}

}  // namespace

const char* toString(PositionFrame f) {
  return f == PositionFrame::Plant ? "plant" : "digitizer";
}

PositionFrame positionFrameFromString(const std::string& s) {
  if (s == "plant") return PositionFrame::Plant;
  if (s == "digitizer") return PositionFrame::Digitizer;
  throw std::invalid_argument("unknown frame '" + s +
                              "': a position is in the plant frame or the digitizer's (plant, digitizer)");
}

namespace {

std::vector<db::EventInput> plantCorrectionEvents(const db::EventStore& store, const db::SessionInfo& info,
                                                  const std::vector<db::Event>& logged, Correction c);

// A correction as planned: the session's row and every event it held, read once, and the events
// the correction writes, worked out against those very events (every check made, nothing
// written): the corrected item's, then the points a refitted move places again. `who` is the
// signature they carry.
struct Plan {
  db::SessionInfo info;
  std::vector<db::Event> logged;
  std::vector<db::EventInput> events;
  std::string who;
};

std::vector<db::EventInput> leafCorrectionEvents(const db::EventStore& store, const Plan& p, const Correction& c);

Plan planCorrection(const db::EventStore& store, std::int64_t id, const Correction& given) {
  Plan plan;
  Correction c = given;
  c.who = plan.who = store.signature(given.who);  // through a login: the login that writes it
  plan.info = detail::infoOrThrow(store, id);
  plan.logged = store.events(id);
  const db::SessionInfo& info = plan.info;
  if (info.kind == "plant") {
    if (!c.plantWhat && c.node <= 0)
      throw std::invalid_argument("session " + std::to_string(id) +
                                  " is a plant: name the plant's item (landmark, collar, collar_diameter, point, "
                                  "reading, quick_point) or a full leaf's item with its node");
    plan.events = plantCorrectionEvents(store, info, plan.logged, c);
  } else {
    plan.events = leafCorrectionEvents(store, plan, c);
  }
  // Written only if nobody added to the session since it was read here, or since the curator saw
  // the effect (CorrectionEffect::head): else the store's conflict, and nothing written.
  if (!plan.events.empty()) {
    const std::int64_t head = plan.logged.empty() ? 0 : plan.logged.back().seq;
    plan.events.front().follows = given.seenHead.value_or(head);
  }
  return plan;
}

std::vector<db::EventInput> leafCorrectionEvents(const db::EventStore& store, const Plan& plan, const Correction& c) {
  const std::int64_t id = plan.info.id;
  if (c.frame == PositionFrame::Plant)
    throw std::invalid_argument("session " + std::to_string(id) +
                                " captured one leaf: its points are corrected in the digitizer's frame, as sessions "
                                "show gives them (--frame digitizer)");
  if (c.plantWhat || c.node > 0)
    throw std::invalid_argument("session " + std::to_string(id) +
                                " captured one leaf: a plant's item or a node does not apply (--what tip, marker, "
                                "or a thickness, with --row and --col)");
  requireCorrectable(store, id, plan.info.status, c.reason, c.who);
  const ReviewedSession r = reviewedFrom(plan.info, plan.logged);
  const Item* old = findItem(r.engine.items(), c.what, c.row, c.col);
  if (!old)
    throw std::invalid_argument(std::string("session ") + std::to_string(id) + " has no " + toString(c.what) +
                                (c.row ? " at row " + std::to_string(c.row) : "") +
                                (c.col ? " col " + std::to_string(c.col) : "") + " to correct");
  Item fixed = *old;
  fixed.flag.clear();
  if (isStylusItem(c.what)) {
    if (!c.positionMm || c.valueMm)
      throw std::invalid_argument("a marker is corrected with a position (x, y, z in mm)");
    for (double v : *c.positionMm)
      if (!std::isfinite(v) || std::abs(v) > model::kMaxCoordinateMm)
        throw std::invalid_argument("the corrected position must be finite numbers in mm within ±" +
                                    std::to_string(static_cast<int>(model::kMaxCoordinateMm)) +
                                    " mm of the transmitter");
    fixed.positionMm = *c.positionMm;
    // A corrected point is given in the first transmitter position's frame (as the review shows
    // it); a board point taken again stays in its own.
    if (c.what != What::BoardAgain) fixed.frame = 0;
    // An item is held where sessions show gives it (the engine places a point taken after a move
    // into the first frame as it takes it), so the move is between the two positions as they are.
    requireConfirmedMove(old->positionMm, fixed.positionMm, c.confirmAboveMm, toString(c.what));
  } else {
    if (!c.valueMm || c.positionMm) throw std::invalid_argument("a thickness is corrected with a value in mm");
    if (!(*c.valueMm >= r.settings.minThicknessMm && *c.valueMm <= r.settings.maxThicknessMm)) {
      std::ostringstream t;
      t << "a thickness of " << *c.valueMm << " mm is outside this session's range " << r.settings.minThicknessMm << "–"
        << r.settings.maxThicknessMm << " mm: give the value in millimetres";
      throw std::invalid_argument(t.str());
    }
    fixed.valueMm = *c.valueMm;
  }
  fixed.raw = "corrected by " + c.who;
  std::vector<db::EventInput> events{correctionEvent(*old, fixed, r.seqs.at(detail::keyOf(*old)), c.reason, c.who)};
  // A board point (as first taken, or taken again after a move) places every point taken after a
  // move: each move is fitted again and its points moved with the new fit, each by its own
  // correction, all written together or not at all.
  if ((c.what == What::Board || c.what == What::BoardAgain) && r.engine.transmitterPositions() > 1) {
    std::vector<Item> after = r.engine.items();
    for (Item& i : after)
      if (detail::keyOf(i) == detail::keyOf(fixed)) i = fixed;
    const std::string because =
        std::string("placed again by its move's new fit (") + toString(c.what) + " " + std::to_string(c.col) +
        (c.what == What::BoardAgain ? " of move " + std::to_string(c.row) : "") + " corrected): " + c.reason;
    for (int move = 1; move < r.engine.transmitterPositions(); ++move) {
      if (c.what == What::BoardAgain && c.row != move) continue;
      const BoardMoveFit was = fitBoardMove(r.engine.items(), move, r.settings.relocationToleranceMm);
      const BoardMoveFit now = fitBoardMove(after, move, r.settings.relocationToleranceMm);
      if (was.refusal || now.refusal)
        throw std::invalid_argument("with this correction the transmitter's move " + std::to_string(move) +
                                    " no longer fits (" + *(now.refusal ? now.refusal : was.refusal) +
                                    "): check the position, nothing was written");
      if (was.toFirst == now.toFirst) continue;  // a fit the correction leaves as it was: its points stay
      for (const Item& i : r.engine.items()) {
        if (!isStylusItem(i.what) || i.what == What::BoardAgain || i.frame != move) continue;
        Item moved = i;
        moved.flag.clear();
        moved.raw = fixed.raw;
        moved.positionMm =
            detail::replaced(detail::isometryOf(was.toFirst), detail::isometryOf(now.toFirst), i.positionMm);
        events.push_back(correctionEvent(i, moved, r.seqs.at(detail::keyOf(i)), because, c.who));
      }
    }
  }
  return events;
}

std::vector<db::EventInput> plantCorrectionEvents(const db::EventStore& store, const db::SessionInfo& info,
                                                  const std::vector<db::Event>& logged, Correction c) {
  const What leafItem = c.what;                                           // node > 0: a full leaf's item
  const PlantWhat plantItem = c.plantWhat.value_or(PlantWhat::Landmark);  // else the plant's own
  const std::int64_t id = info.id;  // a plant's session: planCorrection dispatched on its kind
  requireCorrectable(store, id, info.status, c.reason, c.who);
  const PlantSessionSetup setup = PlantCaptureSession::setupFromJson(info.settingsJson);
  std::map<std::string, std::int64_t> held;
  PlantEngine engine = PlantCaptureSession::replay(setup, logged, &held);
  if (c.positionMm && c.frame == PositionFrame::Plant) {
    for (double v : *c.positionMm)
      if (!std::isfinite(v) || std::abs(v) > m::kMaxCoordinateMm)
        throw std::invalid_argument("the corrected position must be finite numbers in mm within ±" +
                                    std::to_string(static_cast<int>(m::kMaxCoordinateMm)) + " mm");
    c.positionMm = fromPlantFrame(engine, info.plant, *c.positionMm);
    // A landmark taken again after a move is held in its own transmitter position's frame.
    if (c.node <= 0 && plantItem == PlantWhat::LandmarkAgain && c.col >= 1 &&
        c.col < static_cast<int>(engine.toFirst().size())) {
      const Eigen::Vector3d own = engine.toFirst()[static_cast<std::size_t>(c.col)].inverse() *
                                  Eigen::Vector3d((*c.positionMm)[0], (*c.positionMm)[1], (*c.positionMm)[2]);
      c.positionMm = Vec3{own.x(), own.y(), own.z()};
    }
  }

  const bool stylus = c.node > 0 ? acquisition::isStylusItem(leafItem) : isStylusItem(plantItem);
  if (stylus) {
    if (!c.positionMm || c.valueMm) throw std::invalid_argument("a point is corrected with a position (x, y, z in mm)");
    for (double v : *c.positionMm)
      if (!std::isfinite(v) || std::abs(v) > m::kMaxCoordinateMm)
        throw std::invalid_argument("the corrected position must be finite numbers in mm within ±" +
                                    std::to_string(static_cast<int>(m::kMaxCoordinateMm)) + " mm of the transmitter");
  } else if (!c.valueMm || c.positionMm) {
    throw std::invalid_argument(std::string("a ") + (c.node > 0 ? "thickness" : "diameter") +
                                " is corrected with a value in mm");
  }
  const double minMm = setup.settings.minThicknessMm;
  const double maxMm = c.node > 0 ? setup.settings.maxThicknessMm : m::kMaxThicknessMm;
  if (c.valueMm && !(*c.valueMm >= minMm && *c.valueMm <= maxMm)) {
    char b[200];
    std::snprintf(b, sizeof b, "a %s of %g mm is outside this session's range %g–%g mm: give the value in millimetres",
                  c.node > 0 ? "thickness" : "diameter", *c.valueMm, minMm, maxMm);
    throw std::invalid_argument(b);
  }

  // One correction as stored: the old item, the event it replaces, the corrected one, why, who.
  std::vector<db::EventInput> events;
  const auto correction = [&](json old, const json& fixed, const std::string& key, const std::string& why) {
    const std::int64_t seq = held.at(key);
    old["seq"] = seq;
    old["corrected"] = fixed;
    old["reason"] = why;
    old["who"] = c.who;
    db::EventInput ev;
    ev.kind = "corrected";
    ev.payloadJson = old.dump();
    ev.raw = "corrected by " + c.who;
    ev.projection = projectionOf(fixed.dump(), ev.raw);
    ev.retracts = seq;
    events.push_back(std::move(ev));
  };
  const PlantEngine before = engine;
  bool refit = false;
  int onlyMove = 0;  // a landmark taken again refits its own move; a landmark as first taken, every move
  if (c.node > 0) {
    const Engine* leaf = engine.leaf(c.node);
    const Item* found = nullptr;
    if (leaf)
      for (const Item& i : leaf->items())
        if (i.what == leafItem && i.row == c.row && i.col == c.col) found = &i;
    if (!found)
      throw std::invalid_argument("plant session " + std::to_string(id) + " has no " + toString(leafItem) +
                                  (c.row ? " at row " + std::to_string(c.row) : "") +
                                  (c.col ? " col " + std::to_string(c.col) : "") + " in node " +
                                  std::to_string(c.node) + "'s leaf" + (leaf ? "" : " (that node has no full leaf)") +
                                  " to correct");
    Item fixed = *found;
    fixed.flag.clear();
    if (c.positionMm) {
      fixed.positionMm = *c.positionMm;
      fixed.frame = 0;  // a corrected point is given in the first transmitter position's frame
      // Held in the first frame already (as sessions show gives it): the move is between the two.
      requireConfirmedMove(found->positionMm, fixed.positionMm, c.confirmAboveMm,
                           "node " + std::to_string(c.node) + " leaf's " + toString(leafItem));
    }
    if (c.valueMm) fixed.valueMm = *c.valueMm;
    fixed.raw = "corrected by " + c.who;
    json old = itemJson(*found);
    old["what"] = leafWhat(c.node, *found);
    json fixedJson = itemJson(fixed);
    fixedJson["what"] = leafWhat(c.node, fixed);
    correction(old, fixedJson, keyOf(c.node, *found), c.reason);
    fixed.flag = "corrected: " + c.reason;
    (void)engine.correctLeaf(c.node, fixed);
  } else {
    // A part left out (0) names the first where the item has parts (a node's point, reading).
    const PlantItem* found = nullptr;
    for (const PlantItem& i : engine.items())
      if (i.what == plantItem && i.index == c.row && (i.part == c.col || (c.col == 0 && i.part == 1))) found = &i;
    if (!found)
      throw std::invalid_argument("plant session " + std::to_string(id) + " has no " + toString(plantItem) +
                                  (c.row ? " " + std::to_string(c.row) : "") +
                                  (c.col ? " part " + std::to_string(c.col) : "") +
                                  " to correct (landmarks by number, a node's point and reading by node)");
    PlantItem fixed = *found;
    fixed.flag.clear();
    if (c.positionMm) {
      fixed.positionMm = *c.positionMm;
      // A corrected point is given in the first transmitter position's frame; a landmark taken
      // again stays in its own.
      if (fixed.what != PlantWhat::LandmarkAgain) fixed.frame = 0;
      requireConfirmedMove(found->positionMm, fixed.positionMm, c.confirmAboveMm, toString(plantItem));
    }
    if (c.valueMm) fixed.valueMm = *c.valueMm;
    fixed.raw = "corrected by " + c.who;
    correction(plantItemJson(*found), plantItemJson(fixed), keyOf(*found), c.reason);
    refit = fixed.what == PlantWhat::Landmark || fixed.what == PlantWhat::LandmarkAgain;
    if (fixed.what == PlantWhat::LandmarkAgain) onlyMove = fixed.part;
    fixed.flag = "corrected: " + c.reason;
    (void)engine.correct(fixed);
  }
  // A landmark places every point taken after a move: each move it takes part in is fitted
  // again and the points taken from that position moved with the new fit, each by its own
  // correction, all written together or not at all.
  const int moves = static_cast<int>(before.toFirst().size()) - 1;
  for (int move = 1; refit && move <= moves; ++move) {
    if (onlyMove && move != onlyMove) continue;
    const RelocationFit was = before.fitOf(move);
    const RelocationFit now = engine.fitOf(move);
    if (was.refusal || now.refusal)
      throw std::invalid_argument("with this correction the transmitter's move " + std::to_string(move) +
                                  " no longer fits (" + *(now.refusal ? now.refusal : was.refusal) +
                                  "): check the position, nothing was written");
    // A move that did not take the corrected landmark again fits as before: its points stay.
    if (was.newToOld.matrix() == now.newToOld.matrix()) continue;
    const std::string why = std::string("placed again by its move's new fit (") + toString(plantItem) + " " +
                            std::to_string(c.row) + (onlyMove ? " of move " + std::to_string(onlyMove) : "") +
                            " corrected): " + c.reason;
    for (const PlantItem& i : before.items()) {
      if (!isStylusItem(i.what) || i.what == PlantWhat::LandmarkAgain || i.frame != move) continue;
      PlantItem moved = i;
      moved.flag.clear();
      moved.raw = "corrected by " + c.who;
      moved.positionMm = detail::replaced(was.newToOld, now.newToOld, i.positionMm);
      correction(plantItemJson(i), plantItemJson(moved), keyOf(i), why);
      moved.flag = "corrected: " + why;
      (void)engine.correct(moved);
    }
    for (int node = 1; node <= before.nodes(); ++node) {
      const Engine* leaf = before.leaf(node);
      if (!leaf) continue;
      for (const Item& i : leaf->items()) {
        if (!acquisition::isStylusItem(i.what) || i.frame != move) continue;
        Item moved = i;
        moved.flag.clear();
        moved.raw = "corrected by " + c.who;
        moved.positionMm = detail::replaced(was.newToOld, now.newToOld, i.positionMm);
        json old = itemJson(i);
        old["what"] = leafWhat(node, i);
        json movedJson = itemJson(moved);
        movedJson["what"] = leafWhat(node, moved);
        correction(old, movedJson, keyOf(node, i), why);
        moved.flag = "corrected: " + why;
        (void)engine.correctLeaf(node, moved);
      }
    }
  }
  // The corrected plant must still stand: a landmark moved onto the others' line leaves no frame.
  try {
    (void)m::surveyPlant(engine.captured(info.plant));
  } catch (const m::InputError& e) {
    throw std::invalid_argument(std::string("the corrected plant would not hold together (") + e.what() +
                                "): check the position, nothing was written");
  }
  return events;
}

// The session's events with `planned` after them, as the store would hold them once written.
std::vector<db::Event> withPlanned(std::vector<db::Event> logged, const std::vector<db::EventInput>& planned) {
  std::int64_t seq = logged.empty() ? 0 : logged.back().seq;
  for (const db::EventInput& in : planned) {
    db::Event e;
    e.seq = ++seq;
    e.kind = in.kind;
    e.payloadJson = in.payloadJson;
    e.raw = in.raw;
    e.monoNs = in.monoNs;
    logged.push_back(std::move(e));
  }
  return logged;
}

void change(CorrectionEffect& effect, std::string what, double before, double after) {
  if (std::abs(after - before) > 1e-9 * std::max(1.0, std::abs(before)))
    effect.changes.push_back({std::move(what), before, after});
}

// A leaf's area (blade, projected) from its items; nothing when the items make no leaf.
std::optional<model::LeafMetrics> leafMetricsOf(const ReviewedSession& r) {
  try {
    return summarize(r).metrics;
  } catch (const model::InputError&) {
    return std::nullopt;
  }
}

// What the planned events change, worked out from the events the plan read.
CorrectionEffect effectOf(const Plan& plan) {
  CorrectionEffect effect;
  effect.events = static_cast<int>(plan.events.size());
  const std::vector<db::Event>& logged = plan.logged;
  const std::vector<db::Event> after = withPlanned(logged, plan.events);
  // The corrected item's own move: the first correction planned (the others are points a
  // refitted move places again).
  effect.head = logged.empty() ? 0 : logged.back().seq;
  for (const db::ReviewEntry& r : db::reviewHistory(after))
    if (r.seq > effect.head && r.action == "corrected") {
      effect.movedMm = r.movedMm();
      break;
    }
  const db::SessionInfo& info = plan.info;
  if (info.kind == "plant") {
    const PlantSessionSetup setup = PlantCaptureSession::setupFromJson(info.settingsJson);
    const auto surveyOf = [&](const std::vector<db::Event>& events) -> std::optional<m::PlantSurvey> {
      try {
        return m::surveyPlant(PlantCaptureSession::replay(setup, events).captured(info.plant));
      } catch (const m::InputError&) {
        return std::nullopt;
      }
    };
    const auto was = surveyOf(logged), now = surveyOf(after);
    if (!was || !now) return effect;
    for (std::size_t n = 0; n < was->nodes.size() && n < now->nodes.size(); ++n)
      change(effect, "node " + std::to_string(was->nodes[n].index) + " height_mm", was->nodes[n].heightMm,
             now->nodes[n].heightMm);
    double totalWas = 0, totalNow = 0;
    for (std::size_t l = 0; l < was->leaves.size() && l < now->leaves.size(); ++l) {
      const m::SurveyedLeaf &a = was->leaves[l], &b = now->leaves[l];
      const std::string leaf = "leaf " + std::to_string(a.node);
      if (a.pose && b.pose) change(effect, leaf + " length_mm", a.pose->lengthMm, b.pose->lengthMm);
      if (a.areaMm2 && b.areaMm2) change(effect, leaf + " area_mm2", *a.areaMm2, *b.areaMm2);
      totalWas += a.areaMm2.value_or(0);
      totalNow += b.areaMm2.value_or(0);
    }
    change(effect, "leaf area total_mm2", totalWas, totalNow);
    return effect;
  }
  ReviewedSession r = reviewedFrom(info, logged);
  const auto was = leafMetricsOf(r);
  r.engine = CaptureSession::replay(r.settings, after);
  const auto now = leafMetricsOf(r);
  if (was && now) {
    change(effect, "blade area_mm2", was->blade.areaMm2, now->blade.areaMm2);
    change(effect, "projected area_mm2", was->blade.projectedAreaMm2, now->blade.projectedAreaMm2);
  }
  return effect;
}

}  // namespace

std::int64_t correct(db::EventStore& store, std::int64_t id, const Correction& c, CorrectionEffect* effect) {
  const Plan plan = planCorrection(store, id, c);
  if (effect) *effect = effectOf(plan);
  (void)store.ensureOperator(plan.who, "curator");
  return store.appendAll(id, plan.events);
}

CorrectionEffect previewCorrection(const db::EventStore& store, std::int64_t id, const Correction& c) {
  return effectOf(planCorrection(store, id, c));
}

}  // namespace leafdig::acquisition
