#include "leafdig/acquisition/session/plant_session.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <utility>

#include "leafdig/acquisition/session/session.hpp"
#include "leafdig/db/event_rules.hpp"
#include "leafdig/model/errors.hpp"
#include "leafdig/model/files.hpp"
#include "leafdig/model/io/survey_export.hpp"
#include "leafdig/model/limits.hpp"
#include "leafdig/names/name_table.hpp"
#include "protocol/item_json.hpp"
#include "protocol/plant_item_json.hpp"
#include "protocol/rigid_map.hpp"

namespace leafdig::acquisition {

namespace {

using detail::itemFrom;
using detail::itemJson;
using detail::keyOf;
using detail::leafWhat;
using detail::nullable;
using detail::plantItemFrom;
using detail::plantItemJson;
using detail::projectionOf;
using nlohmann::json;
namespace m = leafdig::model;

// "node3.marker" → 3 and "marker"; nothing for a plant item's word.
std::optional<std::pair<int, std::string>> splitLeafWhat(const std::string& what) {
  if (what.rfind("node", 0) != 0) return std::nullopt;
  const auto dot = what.find('.');
  if (dot == std::string::npos || dot == 4 || dot > 8) return std::nullopt;
  int node = 0;
  for (std::size_t k = 4; k < dot; ++k) {
    if (what[k] < '0' || what[k] > '9') return std::nullopt;
    node = node * 10 + (what[k] - '0');
  }
  if (node < 1) return std::nullopt;
  return std::make_pair(node, what.substr(dot + 1));
}

// An accepted decision's key: the plant's item, or a full leaf's with its node.
std::string keyOf(const PlantDecision& d) {
  return d.kind == PlantDecision::Kind::Leaf ? keyOf(d.node, d.leaf.item) : keyOf(d.item);
}

// An `accepted` payload (or a correction's item) as the decision that put it in: the plant's
// own item, or a full leaf's with its node.
PlantDecision acceptedItem(const json& p, const std::string& raw) {
  PlantDecision d;
  if (const auto leaf = splitLeafWhat(p.at("what").get<std::string>())) {
    json item = p;
    item["what"] = leaf->second;
    d.kind = PlantDecision::Kind::Leaf;
    d.node = leaf->first;
    d.leaf.kind = Decision::Kind::Accepted;
    d.leaf.item = itemFrom(item, raw);
  } else {
    d.kind = PlantDecision::Kind::Accepted;
    d.item = plantItemFrom(p, raw);
  }
  return d;
}

// Whether an undo's, retake's or correction's payload carries the item it names: the same
// what, row and col (lab schema 10 holds the same on the server).
bool sameItem(const json& p, const PlantDecision& named) {
  try {
    return keyOf(acceptedItem(p, "")) == keyOf(named);
  } catch (const std::exception&) {
    return false;
  }
}

json choiceJson(int node, const LeafChoice& c) {
  json j{{"node", node}, {"kind", m::toString(c.kind)}, {"state", m::toString(c.state)}};
  if (!c.type.empty()) j["type"] = c.type;  // absent when not said (sessions before it read the same)
  return j;
}

constexpr NameTable<PlantDecision::Kind, 11> kEvents{{{PlantDecision::Kind::Accepted, "accepted"},
                                                      {PlantDecision::Kind::Rejected, "rejected"},
                                                      {PlantDecision::Kind::Undone, "undone"},
                                                      {PlantDecision::Kind::LandmarksEnded, "landmarks_ended"},
                                                      {PlantDecision::Kind::LandmarksReopened, "landmarks_reopened"},
                                                      {PlantDecision::Kind::PlantEnded, "plant_ended"},
                                                      {PlantDecision::Kind::PlantReopened, "plant_reopened"},
                                                      {PlantDecision::Kind::LeafChosen, "leaf_chosen"},
                                                      {PlantDecision::Kind::ChoiceUndone, "choice_undone"},
                                                      {PlantDecision::Kind::NodePlaced, "node_placed"},
                                                      {PlantDecision::Kind::PlacementUndone, "placement_undone"}}};

constexpr NameTable<PlantDecision::Kind, 4> kRelocationSteps{{{PlantDecision::Kind::RelocationStarted, "started"},
                                                              {PlantDecision::Kind::RelocationFitted, "fitted"},
                                                              {PlantDecision::Kind::RelocationReopened, "reopened"},
                                                              {PlantDecision::Kind::RelocationCancelled, "cancelled"}}};

json placeJson(int node, const NodePlace& p) {
  return {{"node", node}, {"parent", p.parent}, {"relation", std::string(1, p.relation)}};
}

}  // namespace

std::string PlantCaptureSession::setupToJson(const PlantSessionSetup& s) {
  json j{{"kind", "plant"},
         {"engine", json::parse(CaptureSession::settingsToJson(s.settings))},
         {"protocol", json::parse(m::plantProtocolToJson(s.protocol))},
         {"digitizer", s.digitizer},
         {"caliper", s.caliper},
         {"simulated", s.simulated}};
  if (s.date) j["date"] = m::toIso(*s.date);
  if (s.simulatedPlant) j["simulated_plant"] = json::parse(m::plantMarkersToJson(*s.simulatedPlant));
  if (s.field) j["field_calibration"] = fieldAppliedJson(*s.field);
  if (s.tip) j["tip_calibration"] = tipAppliedJson(*s.tip);
  return j.dump();
}

PlantSessionSetup PlantCaptureSession::setupFromJson(const std::string& text) {
  if (const auto problem = db::settingsProblem(text))
    throw SessionError("the plant session's settings do not read: " + *problem);
  PlantSessionSetup s;
  try {
    const json j = json::parse(text);
    s.settings = CaptureSession::settingsFromJson(j.at("engine").dump());
    s.protocol = m::parsePlantProtocolJson(j.at("protocol").dump(), "the session's protocol");
    s.digitizer = j.value("digitizer", std::string());
    s.caliper = j.value("caliper", std::string());
    s.simulated = j.value("simulated", false);
    if (j.contains("date")) {
      s.date = m::parseSurveyDate(j.at("date").get<std::string>());
      if (!s.date) throw SessionError("the session's date is not a day of the calendar");
    }
    if (j.contains("simulated_plant"))
      s.simulatedPlant = m::parsePlantMarkersJson(j.at("simulated_plant").dump(), "the session's simulated plant");
    s.field = fieldAppliedFromSettings(text, "the plant session");
    s.tip = tipAppliedFromSettings(text, "the plant session");
  } catch (const json::exception& e) {
    throw SessionError(std::string("the plant session's settings do not read: ") + e.what());
  } catch (const m::InputError& e) {
    throw SessionError(std::string("the plant session's settings do not read: ") + e.what());
  }
  return s;
}

std::int64_t PlantCaptureSession::create(db::Store& store, const PlantSessionSetup& setup) {
  checkFieldWithDigitizer(setup.field, setup.digitizer);  // before anything is written
  // The engine refuses a protocol it cannot follow before anything is written.
  try {
    (void)PlantEngine(setup.protocol, setup.settings);
  } catch (const std::invalid_argument& e) {
    throw SessionError(e.what());
  }
  const SessionParties parties = ensureSessionParties(store, setup.project, setup.plant, setup.operatorName,
                                                      setup.station, {setup.digitizer, setup.caliper}, setup.simulated);
  return store.createPlantSession(parties.plant, parties.operatorId, parties.station, toString(setup.settings.mode),
                                  toString(setup.settings.order), setupToJson(setup));
}

PlantEngine PlantCaptureSession::replay(const PlantSessionSetup& setup, const std::vector<db::Event>& events,
                                        std::map<std::string, std::int64_t>* seqs) {
  PlantEngine engine(setup.protocol, setup.settings);
  std::map<std::string, std::int64_t> held;        // the event that accepted each current item
  std::map<std::int64_t, PlantDecision> accepted;  // by seq: what an `undone` names
  for (const db::Event& e : events) {
    const auto fail = [&](const std::string& why) {
      throw SessionError("event " + std::to_string(e.seq) + " (" + e.kind + ") does not fit the plant: " + why);
    };
    try {
      if (const auto problem = db::eventProblem(e.kind, e.payloadJson, e.raw)) fail(*problem);
      const json p = json::parse(e.payloadJson);
      PlantDecision d;
      if (e.kind == "accepted") {
        d = acceptedItem(p, e.raw);
        accepted[e.seq] = d;
        held[keyOf(d)] = e.seq;
      } else if (e.kind == "corrected") {
        // A curator's correction (review): the item named is replaced where it stands.
        const std::int64_t named = p.at("seq").get<std::int64_t>();
        const auto it = accepted.find(named);
        if (it == accepted.end()) fail("it corrects event " + std::to_string(named) + ", which put no item in");
        const auto at = held.find(keyOf(it->second));
        if (at == held.end() || at->second != named) fail("it corrects an item that is no longer there");
        if (!sameItem(p, it->second)) fail("it names event " + std::to_string(named) + " but carries another item");
        PlantDecision fixed = acceptedItem(p.at("corrected"), e.raw);
        if (keyOf(fixed) != keyOf(it->second)) fail("the corrected item is not the one it names");
        const std::string flag = "corrected: " + p.at("reason").get<std::string>();
        bool done = false;
        if (fixed.kind == PlantDecision::Kind::Leaf) {
          fixed.leaf.item.flag = flag;
          done = engine.correctLeaf(fixed.node, fixed.leaf.item);
        } else {
          fixed.item.flag = flag;
          done = engine.correct(fixed.item);
        }
        if (!done) fail("it corrects an item that is not there");
        held.erase(at);
        held[keyOf(fixed)] = e.seq;
        accepted[e.seq] = fixed;
        continue;
      } else if (e.kind == "undone") {
        const auto it = accepted.find(p.at("seq").get<std::int64_t>());
        if (it == accepted.end())
          fail("it undoes event " + std::to_string(p.at("seq").get<std::int64_t>()) + ", which accepted nothing");
        const auto at = held.find(keyOf(it->second));
        if (at == held.end() || at->second != it->first) fail("it undoes an item that is no longer there");
        if (!sameItem(p, it->second)) fail("it names event " + std::to_string(it->first) + " but carries another item");
        d = it->second;
        held.erase(at);
        if (d.kind == PlantDecision::Kind::Leaf)
          d.leaf.kind = Decision::Kind::Undone;
        else
          d.kind = PlantDecision::Kind::Undone;
      } else if (e.kind == "retake") {
        // The item an earlier event put in, taken out to be taken again.
        const auto it = accepted.find(p.at("seq").get<std::int64_t>());
        if (it == accepted.end())
          fail("it retakes event " + std::to_string(p.at("seq").get<std::int64_t>()) + ", which put no item in");
        const auto at = held.find(keyOf(it->second));
        if (at == held.end() || at->second != it->first) fail("it retakes an item that is no longer there");
        if (!sameItem(p, it->second)) fail("it names event " + std::to_string(it->first) + " but carries another item");
        held.erase(at);
        d = it->second;
        if (d.kind == PlantDecision::Kind::Leaf)
          d.leaf.kind = Decision::Kind::RetakeStarted;
        else
          d.kind = PlantDecision::Kind::RetakeStarted;
      } else if (e.kind == "retake_cancelled") {
        // The retaken item put back as it was: held again, under this event.
        d = acceptedItem(p, e.raw);
        accepted[e.seq] = d;
        held[keyOf(d)] = e.seq;
        if (d.kind == PlantDecision::Kind::Leaf)
          d.leaf.kind = Decision::Kind::RetakeCancelled;
        else
          d.kind = PlantDecision::Kind::RetakeCancelled;
      } else if (e.kind == "rows_ended" || e.kind == "rows_reopened") {
        d.kind = PlantDecision::Kind::Leaf;
        d.node = p.at("node").get<int>();
        d.leaf.kind = e.kind == "rows_ended" ? Decision::Kind::RowsEnded : Decision::Kind::RowsReopened;
      } else if (e.kind == "leaf_chosen" || e.kind == "choice_undone") {
        d.kind = e.kind == "leaf_chosen" ? PlantDecision::Kind::LeafChosen : PlantDecision::Kind::ChoiceUndone;
        d.node = p.at("node").get<int>();
        d.choice = {m::leafKindFromString(p.at("kind").get<std::string>()),
                    m::leafStateFromString(p.at("state").get<std::string>()), p.value("type", std::string())};
        if (d.choice.type.size() > kMaxLeafTypeChars)
          fail("its leaf type is " + std::to_string(d.choice.type.size()) + " characters: a leaf type is at most " +
               std::to_string(kMaxLeafTypeChars));
      } else if (e.kind == "node_placed" || e.kind == "placement_undone") {
        d.kind = e.kind == "node_placed" ? PlantDecision::Kind::NodePlaced : PlantDecision::Kind::PlacementUndone;
        d.node = p.at("node").get<int>();
        const std::string relation = p.at("relation").get<std::string>();
        if (relation != "<" && relation != "+") fail("its relation is \"" + relation + "\", not < or +");
        d.place = {p.at("parent").get<int>(), relation[0]};
      } else if (e.kind == "relocation") {
        const auto step = valueIn(kRelocationSteps, p.at("step").get<std::string>());
        if (!step)
          fail("its step is \"" + p.at("step").get<std::string>() + "\", not started, fitted, reopened or cancelled");
        d.kind = *step;
        d.node = p.at("relocation").get<int>();
        if (d.node < 1 || d.node > 999) fail("it names relocation " + std::to_string(d.node));
        if (d.kind == PlantDecision::Kind::RelocationFitted && engine.relocating() == d.node) {
          // The fit is worked out again from the landmarks: it must be one the capture would
          // take (rigid, within tolerance) and the one the technician was shown.
          const RelocationFit fit = engine.fitOf(d.node);
          if (fit.refusal) fail("the move's fit is not one a capture takes: " + *fit.refusal);
          if (p.contains("rms_mm") && std::abs(p.at("rms_mm").get<double>() - fit.rmsMm) > 1e-6)
            fail("it states a fit of " + std::to_string(p.at("rms_mm").get<double>()) +
                 " mm RMS, but its landmarks give " + std::to_string(fit.rmsMm) + " mm");
        }
      } else if (const auto k = valueIn(kEvents, e.kind); k && e.kind != "rejected") {
        d.kind = *k;  // the ends and their reopenings
      } else {
        continue;  // rejections, status, devices: nothing to apply
      }
      if (d.kind == PlantDecision::Kind::NodePlaced && (d.node < 2 || d.node > static_cast<int>(m::kMaxPlantNodes) ||
                                                        d.place.parent < 1 || d.place.parent >= d.node))
        fail("it places node " + std::to_string(d.node) + " on node " + std::to_string(d.place.parent) +
             ", which is not a node before it");
      if (d.kind == PlantDecision::Kind::NodePlaced && d.place.relation == '+' && !engine.hasBranches())
        fail("it starts a branch at node " + std::to_string(d.node) + ", but the plant's protocol has no branch");
      engine.apply(d);
    } catch (const json::exception& x) {
      fail(x.what());
    } catch (const m::InputError& x) {  // a placement the plant's topology does not take
      fail(x.what());
    } catch (const std::invalid_argument& x) {  // an unknown word (UnknownName)
      fail(x.what());
    }
  }
  if (seqs) *seqs = std::move(held);
  return engine;
}

namespace {

// The setup of an open plant session, from its row and settings.
PlantSessionSetup setupOf(const db::SessionInfo& info) {
  PlantSessionSetup setup = PlantCaptureSession::setupFromJson(info.settingsJson);
  setup.project = info.project;
  setup.plant = info.plant;
  setup.operatorName = info.operatorName;
  setup.station = info.station;
  return setup;
}

}  // namespace

PlantCaptureSession::PlantCaptureSession(db::Store& store, std::int64_t id)
    : log_(store, id, kPlantCapture), setup_(setupOf(log_.info())), engine_(setup_.protocol, setup_.settings) {
  rebuild();
}

void PlantCaptureSession::rebuild() {
  const std::vector<db::Event> events = log_.events();
  engine_ = replay(setup_, events, &seqs_);
  status_ = log_.status();
  // An operator's pause survives a restart: the session opens paused until resume().
  const PauseState pause = pauseIn(events);
  paused_ = pause.paused;
  pauseReason_ = pause.reason;
}

PlantFeedback PlantCaptureSession::commit(const PlantDecision& d, std::int64_t monoNs, const std::string& raw) {
  PlantFeedback f;
  f.decision = d;
  if (d.kind == PlantDecision::Kind::Ignored) return f;
  db::EventInput ev;
  ev.monoNs = monoNs;
  std::string key;  // Accepted: the item's key; Undone: the key whose event it retracts
  // An event that puts an item in (accepted, retake_cancelled) or takes the held one back
  // (undone, retake: naming the event that put it in).
  const auto putsIn = [&](const char* kind, const json& item, const std::string& itemRaw, std::string itemKey) {
    ev.kind = kind;
    ev.payloadJson = item.dump();
    ev.raw = itemRaw;
    ev.projection = projectionOf(ev.payloadJson, ev.raw);
    key = std::move(itemKey);
  };
  const auto takesBack = [&](const char* kind, json item, std::string itemKey) {
    key = std::move(itemKey);
    item["seq"] = seqs_.at(key);
    ev.kind = kind;
    ev.payloadJson = item.dump();
    ev.retracts = seqs_.at(key);
  };
  switch (d.kind) {
    case PlantDecision::Kind::Rejected: {
      const PlantStep st = engine_.step();
      ev.kind = "rejected";
      ev.payloadJson =
          json{{"reason", d.reason},
               {"step", {{"what", toString(st.what)}, {"row", nullable(st.index)}, {"col", nullable(st.part)}}}}
              .dump();
      ev.raw = raw;
      break;
    }
    case PlantDecision::Kind::Accepted: putsIn("accepted", plantItemJson(d.item), d.item.raw, keyOf(d.item)); break;
    case PlantDecision::Kind::Undone:
    case PlantDecision::Kind::RetakeStarted:
      takesBack(d.kind == PlantDecision::Kind::Undone ? "undone" : "retake", plantItemJson(d.item), keyOf(d.item));
      break;
    case PlantDecision::Kind::RetakeCancelled:
      putsIn("retake_cancelled", plantItemJson(d.item), d.item.raw, keyOf(d.item));
      break;
    case PlantDecision::Kind::Leaf: {
      const Decision& l = d.leaf;
      json item = itemJson(l.item);
      item["what"] = leafWhat(d.node, l.item);
      switch (l.kind) {
        case Decision::Kind::Accepted:
        case Decision::Kind::RetakeCancelled:
          putsIn(l.kind == Decision::Kind::Accepted ? "accepted" : "retake_cancelled", item, l.item.raw,
                 keyOf(d.node, l.item));
          break;
        case Decision::Kind::Undone:
        case Decision::Kind::RetakeStarted:
          takesBack(l.kind == Decision::Kind::Undone ? "undone" : "retake", item, keyOf(d.node, l.item));
          break;
        case Decision::Kind::RowsEnded:
        case Decision::Kind::RowsReopened:
          ev.kind = l.kind == Decision::Kind::RowsEnded ? "rows_ended" : "rows_reopened";
          ev.payloadJson = json{{"node", d.node}}.dump();
          break;
        default: return f;
      }
      break;
    }
    case PlantDecision::Kind::LeafChosen:
      ev.kind = "leaf_chosen";
      ev.payloadJson = choiceJson(d.node, d.choice).dump();
      break;
    case PlantDecision::Kind::ChoiceUndone:
      ev.kind = "choice_undone";
      ev.payloadJson = choiceJson(d.node, d.previous).dump();
      break;
    case PlantDecision::Kind::NodePlaced:
    case PlantDecision::Kind::PlacementUndone:
      ev.kind = nameIn(kEvents, d.kind);
      ev.payloadJson = placeJson(d.node, d.place).dump();
      break;
    case PlantDecision::Kind::RelocationStarted:
    case PlantDecision::Kind::RelocationFitted:
    case PlantDecision::Kind::RelocationReopened:
    case PlantDecision::Kind::RelocationCancelled: {
      ev.kind = "relocation";
      json j{{"relocation", d.node}, {"step", nameIn(kRelocationSteps, d.kind)}};
      if (d.kind == PlantDecision::Kind::RelocationFitted) {
        j["rms_mm"] = d.fit.rmsMm;  // what the technician was shown; replay fits again
        j["worst_mm"] = d.fit.worstMm;
      }
      ev.payloadJson = j.dump();
      break;
    }
    default:
      ev.kind = nameIn(kEvents, d.kind);
      ev.payloadJson = "{}";
      break;
  }
  try {
    f.seq = log_.append(ev);
  } catch (const db::StoreError& e) {
    f.storeRefused = std::string(e.what()) + ": " + e.remedy();
    if (d.kind != PlantDecision::Kind::Rejected) rebuild();  // the engine as the store has it
    return f;
  }
  if (ev.kind == "accepted" || ev.kind == "retake_cancelled") seqs_[key] = f.seq;
  if (ev.kind == "undone" || ev.kind == "retake") seqs_.erase(key);
  if (engine_.complete() && !ended()) {
    try {
      f.completeSeq = log_.append(statusEvent("complete", setup_.operatorName, "all steps captured", monoNs));
      status_ = "complete";
    } catch (const db::StoreError& e) {
      f.storeRefused = std::string(e.what()) + ": " + e.remedy();  // written on the next open
    }
  }
  return f;
}

PlantFeedback PlantCaptureSession::onStylus(const StylusInput& s) {
  if (ended() || paused_) return {};
  if (!setup_.field) return commit(engine_.onStylus(s), s.tNs, s.raw);
  // Through the checked field's correction; the raw record stays what the digitizer sent.
  StylusInput corrected = s;
  corrected.positionMm = setup_.field->apply(s.positionMm);
  return commit(engine_.onStylus(corrected), s.tNs, s.raw);
}

PlantFeedback PlantCaptureSession::onCaliper(const CaliperInput& c) {
  if (ended()) return {};
  if (paused_) {
    // The reading is kept in the log (the device's text), and changes nothing while paused.
    try {
      (void)log_.append(ignoredReadingEvent(c));
    } catch (const db::StoreError&) {
      // A reading that changes nothing is not worth a refusal: the capture is paused anyway.
    }
    return {};
  }
  const PlantDecision d = engine_.onCaliper(c);
  return commit(d, c.tNs, c.raw);
}

PlantFeedback PlantCaptureSession::undo(std::int64_t monoNs) {
  if (ended() || paused_) return {};
  return commit(engine_.undo(), monoNs, {});
}

PlantFeedback PlantCaptureSession::end(std::int64_t monoNs) {
  if (ended() || paused_) return {};
  return commit(engine_.end(), monoNs, {});
}

PlantFeedback PlantCaptureSession::retake(PlantWhat what, int index, int part, std::int64_t monoNs) {
  if (ended() || paused_) return {};
  return commit(engine_.retake(what, index, part), monoNs, {});
}

PlantFeedback PlantCaptureSession::retakeLeaf(int node, What what, int row, int col, std::int64_t monoNs) {
  if (ended() || paused_) return {};
  return commit(engine_.retakeLeaf(node, what, row, col), monoNs, {});
}

PlantFeedback PlantCaptureSession::chooseLeaf(int node, LeafChoice choice, std::int64_t monoNs) {
  if (ended() || paused_) return {};
  return commit(engine_.chooseLeaf(node, choice), monoNs, {});
}

PlantFeedback PlantCaptureSession::moveTransmitter(std::int64_t monoNs) {
  if (ended() || paused_) return {};
  if (setup_.field) {
    PlantDecision refused;
    refused.kind = PlantDecision::Kind::Rejected;
    refused.reason = setup_.field->moveRefusal();
    return commit(refused, monoNs, {});
  }
  return commit(engine_.moveTransmitter(), monoNs, {});
}

PlantFeedback PlantCaptureSession::branch(int from, std::int64_t monoNs) {
  if (ended() || paused_) return {};
  return commit(engine_.branch(from), monoNs, {});
}

PlantFeedback PlantCaptureSession::abandon(const std::string& why, std::int64_t monoNs) {
  PlantFeedback f;
  if (ended()) return f;
  if (appendInto(statusEvent("abandoned", setup_.operatorName, why, monoNs), f)) status_ = "abandoned";
  return f;
}

bool PlantCaptureSession::appendInto(const db::EventInput& ev, PlantFeedback& f) {
  try {
    f.seq = log_.append(ev);
    return true;
  } catch (const db::StoreError& e) {
    f.storeRefused = std::string(e.what()) + ": " + e.remedy();
    return false;
  }
}

PlantFeedback PlantCaptureSession::pause(const std::string& reason, std::int64_t monoNs) {
  PlantFeedback f;
  if (ended() || paused_) return f;
  if (!appendInto(pausedEvent(reason, monoNs), f)) return f;
  paused_ = true;
  pauseReason_ = reason;
  f.control = PlantFeedback::Control::Paused;
  f.paused = reason;
  return f;
}

PlantFeedback PlantCaptureSession::resume(std::int64_t monoNs) {
  PlantFeedback f;
  if (ended() || !paused_) return f;
  if (!appendInto(resumedEvent(monoNs), f)) return f;
  paused_ = false;
  pauseReason_.clear();
  f.control = PlantFeedback::Control::Resumed;
  return f;
}

PlantFeedback PlantCaptureSession::deviceStatus(const std::string& device, const std::string& state,
                                                const std::string& message, std::int64_t monoNs) {
  PlantFeedback f;
  if (ended()) return f;
  (void)appendInto(deviceEvent(device, state, message, monoNs), f);
  return f;
}

}  // namespace leafdig::acquisition
