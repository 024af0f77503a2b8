#include "leafdig/acquisition/plant_session.hpp"

#include <algorithm>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <utility>

#include "item_json.hpp"
#include "leafdig/acquisition/session.hpp"
#include "leafdig/model/errors.hpp"
#include "leafdig/model/files.hpp"
#include "leafdig/model/io/survey_export.hpp"
#include "leafdig/names/name_table.hpp"

namespace leafdig::acquisition {

namespace {

using detail::itemFrom;
using detail::itemJson;
using detail::nullable;
using nlohmann::json;
namespace m = leafdig::model;

// A full leaf's item travels with its node in `what`: "node3.marker".
std::string leafWhat(int node, const Item& i) {
  return "node" + std::to_string(node) + "." + toString(i.what);
}

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

json plantItemJson(const PlantItem& i) {
  json j{{"what", toString(i.what)}, {"row", nullable(i.index)}, {"col", nullable(i.part)}};
  if (isStylusItem(i.what))
    j["position_mm"] = {i.positionMm[0], i.positionMm[1], i.positionMm[2]};
  else
    j["value_mm"] = i.valueMm;
  if (!i.flag.empty()) j["flag"] = i.flag;
  return j;
}

PlantItem plantItemFrom(const json& j, const std::string& raw) {
  PlantItem i;
  i.what = plantWhatFromString(j.at("what").get<std::string>());
  i.index = j.value("row", json(nullptr)).is_null() ? 0 : j.at("row").get<int>();
  i.part = j.value("col", json(nullptr)).is_null() ? 0 : j.at("col").get<int>();
  if (j.contains("position_mm"))
    for (std::size_t k = 0; k < 3; ++k) i.positionMm[k] = j.at("position_mm").at(k).get<double>();
  if (j.contains("value_mm")) i.valueMm = j.at("value_mm").get<double>();
  i.flag = j.value("flag", std::string());
  i.raw = raw;
  return i;
}

db::Projection projectionOf(const json& item, bool stylus, const std::string& raw) {
  db::Projection p;
  p.kind = stylus ? db::Projection::Kind::Marker : db::Projection::Kind::Thickness;
  p.what = item.at("what").get<std::string>();
  if (!item.at("row").is_null()) p.row = item.at("row").get<int>();
  if (!item.at("col").is_null()) p.col = item.at("col").get<int>();
  if (stylus)
    for (std::size_t k = 0; k < 3; ++k) p.positionMm[k] = item.at("position_mm").at(k).get<double>();
  else
    p.valueMm = item.at("value_mm").get<double>();
  p.raw = raw;
  return p;
}

// The key of an item currently held: which event accepted it is kept under this.
std::string keyOf(const PlantItem& i) {
  return std::string(toString(i.what)) + ":" + std::to_string(i.index) + ":" + std::to_string(i.part);
}
std::string keyOf(int node, const Item& i) {
  return leafWhat(node, i) + ":" + std::to_string(i.row) + ":" + std::to_string(i.col);
}

json choiceJson(int node, const LeafChoice& c) {
  return {{"node", node}, {"kind", m::toString(c.kind)}, {"state", m::toString(c.state)}};
}

constexpr NameTable<PlantDecision::Kind, 9> kEvents{{{PlantDecision::Kind::Accepted, "accepted"},
                                                     {PlantDecision::Kind::Rejected, "rejected"},
                                                     {PlantDecision::Kind::Undone, "undone"},
                                                     {PlantDecision::Kind::LandmarksEnded, "landmarks_ended"},
                                                     {PlantDecision::Kind::LandmarksReopened, "landmarks_reopened"},
                                                     {PlantDecision::Kind::PlantEnded, "plant_ended"},
                                                     {PlantDecision::Kind::PlantReopened, "plant_reopened"},
                                                     {PlantDecision::Kind::LeafChosen, "leaf_chosen"},
                                                     {PlantDecision::Kind::ChoiceUndone, "choice_undone"}}};

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
  return j.dump();
}

PlantSessionSetup PlantCaptureSession::setupFromJson(const std::string& text) {
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
  } catch (const json::exception& e) {
    throw SessionError(std::string("the plant session's settings do not read: ") + e.what());
  } catch (const m::InputError& e) {
    throw SessionError(std::string("the plant session's settings do not read: ") + e.what());
  }
  return s;
}

std::int64_t PlantCaptureSession::create(db::Store& store, const PlantSessionSetup& setup) {
  // The engine refuses a protocol it cannot follow before anything is written.
  try {
    (void)PlantEngine(setup.protocol, setup.settings);
  } catch (const std::invalid_argument& e) {
    throw SessionError(e.what());
  }
  const std::int64_t plant = store.ensurePlant(store.ensureProject(setup.project), setup.plant);
  const std::int64_t op = store.ensureOperator(setup.operatorName);
  for (const std::string& spec : {setup.digitizer, setup.caliper}) {
    if (spec.empty()) continue;
    const auto colon = spec.find(':');
    (void)store.ensureDevice(spec.substr(0, colon), colon == std::string::npos ? "" : spec.substr(colon + 1),
                             setup.simulated ? "simulated" : "");
  }
  const std::string station = setup.station.empty() ? thisStation() : setup.station;
  return store.createPlantSession(plant, op, station, toString(setup.settings.mode), toString(setup.settings.order),
                                  setupToJson(setup));
}

PlantEngine PlantCaptureSession::replay(const PlantSessionSetup& setup, const std::vector<db::Event>& events) {
  PlantEngine engine(setup.protocol, setup.settings);
  std::map<std::int64_t, PlantDecision> accepted;  // by seq: what an `undone` names
  for (const db::Event& e : events) {
    const auto fail = [&](const std::string& why) {
      throw SessionError("event " + std::to_string(e.seq) + " (" + e.kind + ") does not fit the plant: " + why);
    };
    try {
      const json p = json::parse(e.payloadJson);
      PlantDecision d;
      if (e.kind == "accepted") {
        const std::string what = p.at("what").get<std::string>();
        if (const auto leaf = splitLeafWhat(what)) {
          json item = p;
          item["what"] = leaf->second;
          d.kind = PlantDecision::Kind::Leaf;
          d.node = leaf->first;
          d.leaf.kind = Decision::Kind::Accepted;
          d.leaf.item = itemFrom(item, e.raw);
        } else {
          d.kind = PlantDecision::Kind::Accepted;
          d.item = plantItemFrom(p, e.raw);
        }
        accepted[e.seq] = d;
      } else if (e.kind == "undone") {
        const auto it = accepted.find(p.at("seq").get<std::int64_t>());
        if (it == accepted.end())
          fail("it undoes event " + std::to_string(p.at("seq").get<std::int64_t>()) + ", which accepted nothing");
        d = it->second;
        if (d.kind == PlantDecision::Kind::Leaf)
          d.leaf.kind = Decision::Kind::Undone;
        else
          d.kind = PlantDecision::Kind::Undone;
      } else if (e.kind == "rows_ended" || e.kind == "rows_reopened") {
        d.kind = PlantDecision::Kind::Leaf;
        d.node = p.at("node").get<int>();
        d.leaf.kind = e.kind == "rows_ended" ? Decision::Kind::RowsEnded : Decision::Kind::RowsReopened;
      } else if (e.kind == "leaf_chosen" || e.kind == "choice_undone") {
        d.kind = e.kind == "leaf_chosen" ? PlantDecision::Kind::LeafChosen : PlantDecision::Kind::ChoiceUndone;
        d.node = p.at("node").get<int>();
        d.choice = {m::leafKindFromString(p.at("kind").get<std::string>()),
                    m::leafStateFromString(p.at("state").get<std::string>())};
      } else if (const auto k = valueIn(kEvents, e.kind); k && e.kind != "rejected") {
        d.kind = *k;  // the ends and their reopenings
      } else {
        continue;  // rejections, status, devices: nothing to apply
      }
      engine.apply(d);
    } catch (const json::exception& x) {
      fail(x.what());
    } catch (const std::invalid_argument& x) {  // an unknown word (UnknownName)
      fail(x.what());
    }
  }
  return engine;
}

PlantCaptureSession::PlantCaptureSession(db::Store& store, std::int64_t id)
    : store_(store), id_(id), engine_(m::defaultPlantProtocol()) {
  const auto info = store_.session(id);
  if (!info) throw SessionError("no session " + std::to_string(id) + " in " + store_.path());
  if (info->kind != "plant")
    throw SessionError("session " + std::to_string(id) + " captures one leaf, not a plant: `leafdig sessions resume " +
                       std::to_string(id) + "` goes on with it");
  if (info->status != "open")
    throw SessionError("plant session " + std::to_string(id) + " is " + info->status + ": only open sessions go on");
  setup_ = setupFromJson(info->settingsJson);
  setup_.project = info->project;
  setup_.plant = info->plant;
  setup_.operatorName = info->operatorName;
  setup_.station = info->station;
  const db::ChainReport chain = store_.verify(id);
  if (!chain.ok) throw SessionError("plant session " + std::to_string(id) + " does not verify: " + chain.problem);
  rebuild();
}

void PlantCaptureSession::rebuild() {
  const std::vector<db::Event> events = store_.events(id_);
  engine_ = replay(setup_, events);
  seqs_.clear();
  std::map<std::int64_t, std::string> keys;
  for (const db::Event& e : events) {
    const json p = json::parse(e.payloadJson);
    if (e.kind == "accepted") {
      const std::string what = p.at("what").get<std::string>();
      std::string key = what + ":" + std::to_string(p.value("row", json(nullptr)).is_null() ? 0 : p["row"].get<int>()) +
                        ":" + std::to_string(p.value("col", json(nullptr)).is_null() ? 0 : p["col"].get<int>());
      keys[e.seq] = key;
      seqs_[key] = e.seq;
    } else if (e.kind == "undone") {
      seqs_.erase(keys[p.at("seq").get<std::int64_t>()]);
    } else if (e.kind == "status") {
      status_ = p.at("status").get<std::string>();
    }
  }
  ended_ = status_ != "open";
}

PlantFeedback PlantCaptureSession::commit(const PlantDecision& d, std::int64_t monoNs, const std::string& raw) {
  PlantFeedback f;
  f.decision = d;
  if (d.kind == PlantDecision::Kind::Ignored) return f;
  db::EventInput ev;
  ev.monoNs = monoNs;
  std::string key;  // Accepted: the item's key; Undone: the key whose event it retracts
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
    case PlantDecision::Kind::Accepted: {
      const json item = plantItemJson(d.item);
      ev.kind = "accepted";
      ev.payloadJson = item.dump();
      ev.raw = d.item.raw;
      ev.projection = projectionOf(item, isStylusItem(d.item.what), d.item.raw);
      key = keyOf(d.item);
      break;
    }
    case PlantDecision::Kind::Undone: {
      key = keyOf(d.item);
      json item = plantItemJson(d.item);
      item["seq"] = seqs_.at(key);
      ev.kind = "undone";
      ev.payloadJson = item.dump();
      ev.retracts = seqs_.at(key);
      break;
    }
    case PlantDecision::Kind::Leaf: {
      const Decision& l = d.leaf;
      json item = itemJson(l.item);
      item["what"] = leafWhat(d.node, l.item);
      switch (l.kind) {
        case Decision::Kind::Accepted:
          ev.kind = "accepted";
          ev.payloadJson = item.dump();
          ev.raw = l.item.raw;
          ev.projection = projectionOf(item, isStylusItem(l.item.what), l.item.raw);
          key = keyOf(d.node, l.item);
          break;
        case Decision::Kind::Undone:
          key = keyOf(d.node, l.item);
          item["seq"] = seqs_.at(key);
          ev.kind = "undone";
          ev.payloadJson = item.dump();
          ev.retracts = seqs_.at(key);
          break;
        case Decision::Kind::RowsEnded:
        case Decision::Kind::RowsReopened:
          ev.kind = l.kind == Decision::Kind::RowsEnded ? "rows_ended" : "rows_reopened";
          ev.payloadJson = json{{"node", d.node}}.dump();
          break;
        default: return f;  // retakes inside a plant's leaf are not offered
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
    default:
      ev.kind = nameIn(kEvents, d.kind);
      ev.payloadJson = "{}";
      break;
  }
  try {
    f.seq = store_.append(id_, ev);
  } catch (const db::StoreError& e) {
    f.storeRefused = std::string(e.what()) + ": " + e.remedy();
    if (d.kind != PlantDecision::Kind::Rejected) rebuild();  // the engine as the store has it
    return f;
  }
  if (ev.kind == "accepted") seqs_[key] = f.seq;
  if (ev.kind == "undone") seqs_.erase(key);
  if (engine_.complete() && !ended_) {
    db::EventInput done;
    done.kind = "status";
    done.monoNs = monoNs;
    done.payloadJson = json{{"status", "complete"}, {"who", setup_.operatorName}, {"why", "all steps captured"}}.dump();
    done.setsStatus = "complete";
    try {
      f.completeSeq = store_.append(id_, done);
      ended_ = true;
      status_ = "complete";
    } catch (const db::StoreError& e) {
      f.storeRefused = std::string(e.what()) + ": " + e.remedy();  // written on the next open
    }
  }
  return f;
}

PlantFeedback PlantCaptureSession::onStylus(const StylusInput& s) {
  if (ended_) return {};
  const PlantDecision d = engine_.onStylus(s);
  return commit(d, s.tNs, s.raw);
}

PlantFeedback PlantCaptureSession::onCaliper(const CaliperInput& c) {
  if (ended_) return {};
  const PlantDecision d = engine_.onCaliper(c);
  return commit(d, c.tNs, c.raw);
}

PlantFeedback PlantCaptureSession::undo(std::int64_t monoNs) {
  if (ended_) return {};
  return commit(engine_.undo(), monoNs, {});
}

PlantFeedback PlantCaptureSession::end(std::int64_t monoNs) {
  if (ended_) return {};
  return commit(engine_.end(), monoNs, {});
}

PlantFeedback PlantCaptureSession::chooseLeaf(int node, LeafChoice choice, std::int64_t monoNs) {
  if (ended_) return {};
  return commit(engine_.chooseLeaf(node, choice), monoNs, {});
}

PlantFeedback PlantCaptureSession::abandon(const std::string& why, std::int64_t monoNs) {
  PlantFeedback f;
  if (ended_) return f;
  db::EventInput ev;
  ev.kind = "status";
  ev.monoNs = monoNs;
  ev.payloadJson = json{{"status", "abandoned"}, {"who", setup_.operatorName}, {"why", why}}.dump();
  ev.setsStatus = "abandoned";
  try {
    f.seq = store_.append(id_, ev);
    ended_ = true;
    status_ = "abandoned";
  } catch (const db::StoreError& e) {
    f.storeRefused = std::string(e.what()) + ": " + e.remedy();
  }
  return f;
}

const std::vector<std::string>& plantExportFormats() {
  static const std::vector<std::string> formats{"mtg", "csv", "markers", "json"};
  return formats;
}

PlantExport exportPlantSession(db::EventStore& store, std::int64_t id, const std::vector<std::string>& formats,
                               const std::string& outDir) {
  if (outDir.empty()) throw std::invalid_argument("choose a destination directory for the export");
  const std::vector<std::string>& all = plantExportFormats();
  const std::vector<std::string> chosen = formats.empty() ? all : formats;
  for (const std::string& f : chosen)
    if (std::find(all.begin(), all.end(), f) == all.end())
      throw std::invalid_argument("unknown export format '" + f + "' for a plant session: use mtg, csv, markers, json");
  const auto info = store.session(id);
  if (!info) throw SessionError("there is no session " + std::to_string(id) + " in " + store.describe());
  if (info->kind != "plant")
    throw SessionError("session " + std::to_string(id) +
                       " captured one leaf: `leafdig sessions export` without a "
                       "plant's formats writes it");
  const db::ChainReport chain = store.verify(id);
  if (!chain.ok)
    throw SessionError("session " + std::to_string(id) + " fails 'sessions verify' (event " +
                       std::to_string(chain.firstBadSeq.value_or(0)) + ": " + chain.problem +
                       "): it cannot be exported");
  const PlantSessionSetup setup = PlantCaptureSession::setupFromJson(info->settingsJson);
  const PlantEngine engine = PlantCaptureSession::replay(setup, store.events(id));
  m::PlantMarkers plant = engine.captured(info->plant);
  plant.date = setup.date;
  if (!plant.date) plant.date = m::parseSurveyDate(info->createdUtc.substr(0, 10));
  PlantExport out;
  try {
    out.survey = m::surveyPlant(plant);
  } catch (const m::InputError& e) {
    throw m::InputError("plant session " + std::to_string(id) + " holds no whole plant yet (" + e.what() +
                        "): go on with `leafdig plant capture --resume " + std::to_string(id) + "`");
  }
  const m::SurveyDate day = plant.date.value_or(m::SurveyDate{2000, 1, 1});
  const std::string base = outDir + "/session-" + std::to_string(id);
  std::vector<std::pair<std::string, std::string>> files;
  for (const std::string& f : chosen) {
    if (f == "mtg") files.emplace_back(base + ".mtg", m::encodeSurveyMtg(out.survey, day));
    if (f == "csv") files.emplace_back(base + ".plant.csv", m::encodeSurveyCsv(out.survey, day));
    if (f == "markers") files.emplace_back(base + ".plant-markers.json", m::plantMarkersToJson(plant));
    if (f == "json") files.emplace_back(base + ".survey.json", m::plantSurveyToJson(out.survey) + "\n");
  }
  std::filesystem::create_directories(outDir);
  for (const auto& [path, bytes] : files) {
    m::writeFileAtomically(path, bytes);
    const auto dot = path.find('.', path.rfind('/') + 1);
    (void)store.recordExport(id, path, path.substr(dot + 1));
    out.written.push_back(path);
  }
  return out;
}

}  // namespace leafdig::acquisition
