#include "leafdig/acquisition/session/session.hpp"

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>

#include "leafdig/db/event_rules.hpp"
#include "leafdig/model/leaf/markers_json.hpp"
#include "leafdig/names/name_table.hpp"
#include "protocol/item_json.hpp"

namespace leafdig::acquisition {
namespace {

using detail::itemFrom;
using detail::itemJson;
using detail::keyOf;
using detail::nullable;
using detail::projectionOf;
using nlohmann::json;
using Key = detail::Key;

}  // namespace

namespace {

// Feedback names are the JSON-lines contract's `event` values (README).
constexpr NameTable<Feedback::Kind, 13> kFeedbackNames{{{Feedback::Kind::Accepted, "accepted"},
                                                        {Feedback::Kind::Rejected, "rejected"},
                                                        {Feedback::Kind::Undone, "undone"},
                                                        {Feedback::Kind::RowsEnded, "rows_ended"},
                                                        {Feedback::Kind::RowsReopened, "rows_reopened"},
                                                        {Feedback::Kind::RetakeStarted, "retake"},
                                                        {Feedback::Kind::RetakeCancelled, "retake_cancelled"},
                                                        {Feedback::Kind::Paused, "paused"},
                                                        {Feedback::Kind::Resumed, "resumed"},
                                                        {Feedback::Kind::Complete, "complete"},
                                                        {Feedback::Kind::Abandoned, "abandoned"},
                                                        {Feedback::Kind::Device, "device"},
                                                        {Feedback::Kind::Relocation, "relocation"}}};

// The stored event kind of each engine decision (docs/schema.md); the same word is the
// feedback announced once it is stored.
constexpr NameTable<Decision::Kind, 7> kDecisionEvents{{{Decision::Kind::Accepted, "accepted"},
                                                        {Decision::Kind::Rejected, "rejected"},
                                                        {Decision::Kind::Undone, "undone"},
                                                        {Decision::Kind::RowsEnded, "rows_ended"},
                                                        {Decision::Kind::RowsReopened, "rows_reopened"},
                                                        {Decision::Kind::RetakeStarted, "retake"},
                                                        {Decision::Kind::RetakeCancelled, "retake_cancelled"}}};
// A move of the transmitter is one event kind, `relocation`, with its step.
constexpr NameTable<Decision::Kind, 4> kRelocationSteps{{{Decision::Kind::RelocationStarted, "started"},
                                                         {Decision::Kind::RelocationFitted, "fitted"},
                                                         {Decision::Kind::RelocationReopened, "reopened"},
                                                         {Decision::Kind::RelocationCancelled, "cancelled"}}};
bool isRelocation(Decision::Kind k) {
  return std::any_of(kRelocationSteps.begin(), kRelocationSteps.end(), [k](const auto& n) { return n.first == k; });
}

}  // namespace

const char* toString(Feedback::Kind k) {
  return nameIn(kFeedbackNames, k);
}

std::string CaptureSession::settingsToJson(const Settings& s) {
  json j{{"mode", toString(s.mode)},
         {"order", toString(s.order)},
         {"double_tap_mm", s.doubleTapMm},
         {"double_tap_ns", s.doubleTapNs},
         {"still_tolerance_mm", s.stillToleranceMm},
         {"still_window_ns", s.stillWindowNs},
         {"long_press_ns", s.longPressNs},
         {"undo_press_ns", s.undoPressNs},
         {"min_thickness_mm", s.minThicknessMm},
         {"max_thickness_mm", s.maxThicknessMm},
         {"repeat_window_ns", s.repeatWindowNs},
         {"spacing_tolerance", s.spacingTolerance},
         {"midrib_tolerance_mm", s.midribToleranceMm},
         {"min_rows", s.minRows},
         {"board_frame", s.boardFrame},
         {"board_min_mm", s.boardMinMm}};
  // Written only when it is not the default, so that a session without it reads the same.
  if (s.relocationToleranceMm != Settings{}.relocationToleranceMm)
    j["relocation_tolerance_mm"] = s.relocationToleranceMm;
  return j.dump();
}

namespace {

Settings settingsFromParsed(const json& j) {
  const json& e = j.contains("engine") ? j.at("engine") : j;
  Settings s;
  s.mode = model::thicknessModeFromString(e.value("mode", std::string("standard")));
  s.order = orderFromString(e.value("order", std::string("sequential")));
  s.doubleTapMm = e.value("double_tap_mm", s.doubleTapMm);
  s.doubleTapNs = e.value("double_tap_ns", s.doubleTapNs);
  s.stillToleranceMm = e.value("still_tolerance_mm", s.stillToleranceMm);
  s.stillWindowNs = e.value("still_window_ns", s.stillWindowNs);
  s.longPressNs = e.value("long_press_ns", s.longPressNs);
  s.undoPressNs = e.value("undo_press_ns", s.undoPressNs);
  s.minThicknessMm = e.value("min_thickness_mm", s.minThicknessMm);
  s.maxThicknessMm = e.value("max_thickness_mm", s.maxThicknessMm);
  s.repeatWindowNs = e.value("repeat_window_ns", s.repeatWindowNs);
  s.spacingTolerance = e.value("spacing_tolerance", s.spacingTolerance);
  s.midribToleranceMm = e.value("midrib_tolerance_mm", s.midribToleranceMm);
  s.minRows = e.value("min_rows", s.minRows);
  s.boardFrame = e.value("board_frame", s.boardFrame);
  s.boardMinMm = e.value("board_min_mm", s.boardMinMm);
  s.relocationToleranceMm = e.value("relocation_tolerance_mm", s.relocationToleranceMm);
  return s;
}

}  // namespace

Settings CaptureSession::settingsFromJson(const std::string& text) {
  // Settings are text from a file or a server: checked as every event is (db::settingsProblem),
  // and any shape leafdig does not write is named, never an internal error.
  if (const auto problem = db::settingsProblem(text))
    throw SessionError("the session's settings cannot be read: " + *problem);
  try {
    return settingsFromParsed(json::parse(text));
  } catch (const json::exception& e) {
    throw SessionError(std::string("the session's settings cannot be read: ") + e.what());
  }
}

std::int64_t CaptureSession::create(db::Store& store, const SessionSetup& setup) {
  checkFieldWithDigitizer(setup.field, setup.digitizer);  // before anything is written
  const SessionParties parties = ensureSessionParties(store, setup.project, setup.plant, setup.operatorName,
                                                      setup.station, {setup.digitizer, setup.caliper}, setup.simulated);
  const std::int64_t leaf = store.ensureLeaf(parties.plant, setup.leafPosition, setup.leafType, setup.measuredAreaMm2);
  json settings{{"engine", json::parse(settingsToJson(setup.settings))},
                {"digitizer", setup.digitizer},
                {"caliper", setup.caliper},
                {"simulated", setup.simulated},
                {"time_scale", setup.timeScale}};
  if (setup.simulatedLeaf) settings["simulated_leaf"] = json::parse(model::markersToJson(*setup.simulatedLeaf));
  if (const auto margin = leafMarginJson(setup)) settings["leaf_margin"] = *margin;
  if (setup.field) settings["field_calibration"] = fieldAppliedJson(*setup.field);
  if (setup.tip) settings["tip_calibration"] = tipAppliedJson(*setup.tip);
  return store.createSession(leaf, parties.operatorId, parties.station, toString(setup.settings.mode),
                             toString(setup.settings.order), settings.dump());
}

void checkFieldWithDigitizer(const std::optional<FieldApplied>& field, const std::string& digitizerSpec) {
  if (field && digitizerSpec.find(",reference=") != std::string::npos)
    throw std::invalid_argument(
        "a field correction applies in the transmitter's frame, and with a reference receiver the stylus is read in "
        "the receiver's: capture with --field-calibration none, or without the reference receiver");
}

std::optional<json> leafMarginJson(const SessionSetup& setup) {
  if (!setup.serration && !setup.toothDepthMm && !setup.marginFromScan) return std::nullopt;
  json j = json::object();
  if (setup.serration) j["serration"] = model::toString(*setup.serration);
  if (setup.toothDepthMm) j["tooth_depth_mm"] = *setup.toothDepthMm;
  if (setup.marginFromScan) {
    json samples = json::array();
    for (const model::MarginSample& m : *setup.marginFromScan)
      samples.push_back({{"spacing_mm", m.spacingMm}, {"outside_mm", m.outsideMm}, {"inside_mm", m.insideMm}});
    j["from_scan"] = samples;
  }
  return j;
}

void readLeafMargin(const std::string& settingsJson, model::LeafInfo& leaf) {
  try {
    const json j = json::parse(settingsJson);
    if (!j.contains("leaf_margin")) return;
    const json& m = j.at("leaf_margin");
    if (m.contains("serration")) leaf.serration = model::serrationFromString(m.at("serration").get<std::string>());
    if (m.contains("tooth_depth_mm")) leaf.toothDepthMm = m.at("tooth_depth_mm").get<double>();
    if (m.contains("from_scan")) {
      model::MarginFromScan samples;
      for (const json& x : m.at("from_scan"))
        samples.push_back(
            {x.at("spacing_mm").get<double>(), x.at("outside_mm").get<double>(), x.at("inside_mm").get<double>()});
      leaf.marginFromScan = samples;
    }
  } catch (const std::exception& e) {
    throw SessionError(std::string("the session's leaf margin cannot be read: ") + e.what());
  }
}

Engine CaptureSession::replay(const Settings& settings, const std::vector<db::Event>& events,
                              std::map<Key, std::int64_t>* seqs) {
  Engine engine(settings);
  std::map<Key, std::int64_t> local;
  auto& map = seqs ? *seqs : local;
  map.clear();
  for (const db::Event& e : events) {
    try {
      if (const auto problem = db::eventProblem(e.kind, e.payloadJson, e.raw)) throw SessionError(*problem);
      Decision d;
      const json p = json::parse(e.payloadJson);
      if (e.kind == "corrected") {
        // A curator's correction: the item is taken out and its corrected value put in.
        Decision out;
        out.kind = Decision::Kind::RetakeStarted;
        out.item = itemFrom(p, e.raw);
        const auto at = map.find(keyOf(out.item));
        if (at == map.end() || at->second != p.at("seq").get<std::int64_t>())
          throw SessionError("it corrects an item that is not there");
        engine.apply(out);
        map[keyOf(out.item)] = e.seq;
        d.kind = Decision::Kind::Accepted;
        d.item = itemFrom(p.at("corrected"), e.raw);
        if (keyOf(d.item) != keyOf(out.item)) throw SessionError("the corrected item is not the one it names");
        d.item.flag = "corrected: " + p.at("reason").get<std::string>();
      } else if (e.kind == "relocation") {
        const std::string step = p.at("step").get<std::string>();
        const auto kind = valueIn(kRelocationSteps, step);
        if (!kind) throw SessionError("its step is \"" + step + "\", not started, fitted, reopened or cancelled");
        d.kind = *kind;
        d.relocation = p.at("relocation").get<int>();
        if (d.relocation < 1 || d.relocation > 999)
          throw SessionError("it names relocation " + std::to_string(d.relocation));
        if (d.kind == Decision::Kind::RelocationFitted && engine.relocating() == d.relocation) {
          // Worked out again from the board points: one a capture takes, and the one shown.
          const Decision fit = engine.fitOf(d.relocation);
          if (fit.kind != Decision::Kind::RelocationFitted)
            throw SessionError("the move's fit is not one a capture takes: " + fit.reason);
          if (p.contains("rms_mm") && std::abs(p.at("rms_mm").get<double>() - fit.fitRmsMm) > 1e-6)
            throw SessionError("it states a fit of " + std::to_string(p.at("rms_mm").get<double>()) +
                               " mm RMS, but its board points give " + std::to_string(fit.fitRmsMm) + " mm");
        }
      } else {
        const auto kind = valueIn(kDecisionEvents, e.kind);
        // Rejections, pauses, device and status events change no item.
        if (!kind || *kind == Decision::Kind::Rejected) continue;
        d.kind = *kind;
        switch (d.kind) {
          case Decision::Kind::Accepted:
          case Decision::Kind::RetakeCancelled:
            d.item = itemFrom(p, e.raw);
            // A frame names a move of the transmitter the session holds (under way or fitted).
            if (d.item.frame > std::max(engine.relocating(), engine.transmitterPositions() - 1))
              throw SessionError("its frame " + std::to_string(d.item.frame) +
                                 " names a move of the transmitter the session does not hold");
            // One item per place: a second one there is not a capture's (a retake takes the first out).
            if (const auto held = map.find(keyOf(d.item)); held != map.end())
              throw SessionError("it puts in an item where event " + std::to_string(held->second) +
                                 " put one that is still there");
            map[keyOf(d.item)] = e.seq;
            break;
          case Decision::Kind::Undone:
          case Decision::Kind::RetakeStarted: {
            d.item = itemFrom(p, e.raw);
            const auto at = map.find(keyOf(d.item));
            if (at == map.end() || at->second != p.at("seq").get<std::int64_t>())
              throw SessionError("it takes out an item that is not there");
            map.erase(at);
            break;
          }
          default: break;  // rows ended or reopened
        }
      }
      const std::size_t before = engine.items().size();
      const int relocating = engine.relocating(), positions = engine.transmitterPositions();
      engine.apply(d);
      if (d.kind == Decision::Kind::Undone && engine.items().size() + 1 != before)
        throw SessionError("nothing was undone");
      if (isRelocation(d.kind) && relocating == engine.relocating() && positions == engine.transmitterPositions())
        throw SessionError("the move of the transmitter does not follow from the events before it");
    } catch (const SessionError& err) {
      throw SessionError("event " + std::to_string(e.seq) + " (" + e.kind + ") does not replay: " + err.what());
    } catch (const std::exception& err) {
      throw SessionError("event " + std::to_string(e.seq) + " (" + e.kind + ") is malformed: " + err.what());
    }
  }
  return engine;
}

CaptureSession::CaptureSession(db::Store& store, std::int64_t id) : log_(store, id, kLeafCapture) {
  const db::SessionInfo& info = log_.info();
  setup_.project = info.project;
  setup_.plant = info.plant;
  setup_.leafPosition = info.leafPosition;
  setup_.leafType = info.leafType;
  setup_.measuredAreaMm2 = info.measuredAreaMm2;
  setup_.operatorName = info.operatorName;
  setup_.station = info.station;
  try {
    const json j = json::parse(info.settingsJson);
    setup_.settings = settingsFromJson(info.settingsJson);
    setup_.digitizer = j.value("digitizer", std::string());
    setup_.caliper = j.value("caliper", std::string());
    setup_.simulated = j.value("simulated", false);
    setup_.timeScale = j.value("time_scale", 1.0);
    if (j.contains("simulated_leaf"))
      setup_.simulatedLeaf = model::parseMarkersJson(j.at("simulated_leaf").dump(), "session " + std::to_string(id));
    setup_.field = fieldAppliedFromSettings(info.settingsJson, "session " + std::to_string(id));
    setup_.tip = tipAppliedFromSettings(info.settingsJson, "session " + std::to_string(id));
  } catch (const std::exception& e) {
    throw SessionError("session " + std::to_string(id) + " has unreadable settings: " + e.what());
  }
  const std::vector<db::Event> events = log_.events();
  engine_ = replay(setup_.settings, events, &seqs_);
  // An operator pause survives a restart: the session opens paused until resume().
  const PauseState pause = pauseIn(events);
  paused_ = pause.paused;
  pauseReason_ = pause.reason;
}

void CaptureSession::rebuild() {
  engine_ = replay(setup_.settings, log_.events(), &seqs_);
  ++version_;
}

std::int64_t CaptureSession::seqOf(const Item& item) const {
  const auto at = seqs_.find(keyOf(item));
  return at == seqs_.end() ? 0 : at->second;
}

std::optional<std::int64_t> CaptureSession::append(const db::EventInput& ev, std::vector<Feedback>& out) {
  try {
    const std::int64_t seq = log_.append(ev);
    ++version_;
    return seq;
  } catch (const db::StoreError& e) {
    // Not written, so not acknowledged: the engine goes back to what the store holds.
    rebuild();
    const bool again = storeBlocked_;
    paused_ = true;
    storeBlocked_ = true;
    pauseReason_ = std::string(e.what()) + (e.remedy().empty() ? "" : ". " + e.remedy()) +
                   ". The last input was not recorded; capture is paused and continues on resume";
    if (again) return std::nullopt;  // already said
    Feedback f;
    f.kind = Feedback::Kind::Paused;
    f.text = pauseReason_;
    out.push_back(f);
    return std::nullopt;
  }
}

std::vector<Feedback> CaptureSession::commit(const Decision& d, std::int64_t monoNs, const std::string& raw) {
  std::vector<Feedback> out;
  if (d.kind == Decision::Kind::Ignored) return out;
  db::EventInput ev;
  ev.monoNs = monoNs;
  const char* relocationStep = isRelocation(d.kind) ? nameIn(kRelocationSteps, d.kind) : nullptr;
  ev.kind = relocationStep ? "relocation" : nameIn(kDecisionEvents, d.kind);
  Feedback f;
  f.kind = *valueIn(kFeedbackNames, ev.kind);
  f.item = d.item;
  switch (d.kind) {
    case Decision::Kind::RelocationStarted:
    case Decision::Kind::RelocationFitted:
    case Decision::Kind::RelocationReopened:
    case Decision::Kind::RelocationCancelled: {
      json j{{"relocation", d.relocation}, {"step", std::string(relocationStep)}};
      if (d.kind == Decision::Kind::RelocationFitted) {
        j["rms_mm"] = d.fitRmsMm;  // what the technician was shown; replay fits again
        j["worst_mm"] = d.fitWorstMm;
      }
      ev.payloadJson = j.dump();
      f.text = relocationStep;
      f.relocation = d.relocation;
      f.fitRmsMm = d.fitRmsMm;
      f.fitWorstMm = d.fitWorstMm;
      f.fitWorstPoint = d.fitWorstPoint;
      break;
    }
    case Decision::Kind::Rejected:
      ev.payloadJson = json{{"reason", d.reason},
                            {"step",
                             {{"what", toString(engine_.step().what)},
                              {"row", nullable(engine_.step().row)},
                              {"col", nullable(engine_.step().col)}}}}
                           .dump();
      ev.raw = raw;
      f.text = d.reason;
      break;
    case Decision::Kind::Accepted:
    case Decision::Kind::RetakeCancelled:
      ev.payloadJson = itemJson(d.item).dump();
      ev.raw = d.item.raw;
      ev.projection = projectionOf(d.item);
      break;
    case Decision::Kind::Undone:
    case Decision::Kind::RetakeStarted: {
      const std::int64_t old = seqOf(d.item);
      json p = itemJson(d.item);
      p["seq"] = old;
      ev.payloadJson = p.dump();
      ev.retracts = old;
      f.undoneSeq = old;
      break;
    }
    case Decision::Kind::RowsEnded:
    case Decision::Kind::RowsReopened:
    case Decision::Kind::Ignored: break;
  }
  const auto seq = append(ev, out);
  if (!seq) return out;
  f.seq = *seq;
  if (f.kind == Feedback::Kind::Accepted || f.kind == Feedback::Kind::RetakeCancelled) seqs_[keyOf(d.item)] = *seq;
  if (f.kind == Feedback::Kind::Undone || f.kind == Feedback::Kind::RetakeStarted) seqs_.erase(keyOf(d.item));
  out.push_back(f);
  closeIfComplete(monoNs, out);
  return out;
}

std::optional<std::int64_t> CaptureSession::appendStatus(const std::string& status, const std::string& why,
                                                         std::int64_t monoNs, std::vector<Feedback>& out) {
  const auto seq = append(statusEvent(status, setup_.operatorName, why, monoNs), out);
  if (seq) {
    ended_ = true;
    status_ = status;
  }
  return seq;
}

void CaptureSession::closeIfComplete(std::int64_t monoNs, std::vector<Feedback>& out) {
  if (!engine_.complete() || ended_) return;
  if (const auto seq = appendStatus("complete", "all steps captured", monoNs, out)) {
    Feedback c;
    c.kind = Feedback::Kind::Complete;
    c.seq = *seq;
    out.push_back(c);
  }
}

std::vector<Feedback> CaptureSession::onStylus(const StylusInput& s) {
  if (paused_ || ended_) return {};
  if (!setup_.field) return commit(engine_.onStylus(s), s.tNs, s.raw);
  // Through the checked field's correction; the raw record stays what the digitizer sent.
  StylusInput corrected = s;
  corrected.positionMm = setup_.field->apply(s.positionMm);
  return commit(engine_.onStylus(corrected), s.tNs, s.raw);
}

std::vector<Feedback> CaptureSession::onCaliper(const CaliperInput& c) {
  if (ended_) return {};
  if (paused_) {
    // The reading is kept in the log (raw device text), but changes nothing while paused.
    std::vector<Feedback> out;
    (void)append(ignoredReadingEvent(c), out);
    return out;
  }
  return commit(engine_.onCaliper(c), c.tNs, c.raw);
}

std::vector<Feedback> CaptureSession::undo(std::int64_t monoNs) {
  if (paused_ || ended_) return {};
  return commit(engine_.undo(), monoNs, {});
}

std::vector<Feedback> CaptureSession::endRows(std::int64_t monoNs) {
  if (paused_ || ended_) return {};
  return commit(engine_.endRows(), monoNs, {});
}

std::vector<Feedback> CaptureSession::moveTransmitter(std::int64_t monoNs) {
  if (paused_ || ended_) return {};
  if (setup_.field) {
    Decision refused;
    refused.kind = Decision::Kind::Rejected;
    refused.reason = setup_.field->moveRefusal();
    return commit(refused, monoNs, {});
  }
  return commit(engine_.moveTransmitter(), monoNs, {});
}

std::vector<Feedback> CaptureSession::retake(What what, int row, int col, std::int64_t monoNs) {
  if (paused_ || ended_) return {};
  return commit(engine_.retake(what, row, col), monoNs, {});
}

std::vector<Feedback> CaptureSession::pause(const std::string& reason, std::int64_t monoNs) {
  std::vector<Feedback> out;
  if (paused_ || ended_) return out;
  if (const auto seq = append(pausedEvent(reason, monoNs), out)) {
    paused_ = true;
    pauseReason_ = reason;
    Feedback f;
    f.kind = Feedback::Kind::Paused;
    f.seq = *seq;
    f.text = reason;
    out.push_back(f);
  }
  return out;
}

std::vector<Feedback> CaptureSession::resume(std::int64_t monoNs) {
  std::vector<Feedback> out;
  if (ended_) return out;
  if (const auto seq = append(resumedEvent(monoNs), out)) {
    paused_ = false;
    storeBlocked_ = false;
    pauseReason_.clear();
    Feedback f;
    f.kind = Feedback::Kind::Resumed;
    f.seq = *seq;
    out.push_back(f);
    // A leaf that was complete when its status could not be written is closed now.
    closeIfComplete(monoNs, out);
  }
  return out;
}

std::vector<Feedback> CaptureSession::abandon(const std::string& why, std::int64_t monoNs) {
  std::vector<Feedback> out;
  if (ended_) return out;
  if (const auto seq = appendStatus("abandoned", why, monoNs, out)) {
    Feedback f;
    f.kind = Feedback::Kind::Abandoned;
    f.seq = *seq;
    f.text = why;
    out.push_back(f);
  }
  return out;
}

std::vector<Feedback> CaptureSession::deviceStatus(const std::string& device, const std::string& state,
                                                   const std::string& message, std::int64_t monoNs) {
  std::vector<Feedback> out;
  if (const auto seq = append(deviceEvent(device, state, message, monoNs), out)) {
    Feedback f;
    f.kind = Feedback::Kind::Device;
    f.seq = *seq;
    f.text = device + ": " + message;
    out.push_back(f);
  }
  return out;
}

Snapshot CaptureSession::snapshot(bool withPreview, bool withMeshes) const {
  Snapshot s;
  s.session = log_.id();
  s.version = version_;
  s.step = engine_.step();
  s.prompt = paused_ ? "Paused: " + pauseReason_ : engine_.prompt();
  s.plan = engine_.plan();
  s.items = engine_.items();
  s.completeRows = engine_.completeRows();
  s.rowsEnded = engine_.rowsEnded();
  s.complete = engine_.complete();
  s.retaking = engine_.retaking();
  s.paused = paused_;
  s.pauseReason = pauseReason_;
  s.status = status_;
  if (withPreview) {
    s.preview = std::make_shared<const Preview>(buildPreview(s.items, engine_.settings(), {}, withMeshes));
    s.previewVersion = s.version;
  }
  return s;
}

}  // namespace leafdig::acquisition
