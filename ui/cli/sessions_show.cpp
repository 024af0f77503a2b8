// `sessions show`: a session as captured and as reviewed — a leaf's items and metrics, a plant's
// survey table — with the curators' history (split from sessions_cmd.cpp, which registers it).
#include "sessions_show.hpp"

#include <algorithm>
#include <array>
#include <iomanip>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "capture/capture_console.hpp"
#include "leafdig/acquisition/review/plant_export.hpp"
#include "leafdig/acquisition/review/review.hpp"
#include "leafdig/acquisition/session/plant_session.hpp"
#include "leafdig/acquisition/session/session.hpp"
#include "leafdig/db/history.hpp"
#include "leafdig/model/metrics/area_interval.hpp"
#include "leafdig/model/plant/plant_survey.hpp"
#include "plant/plant_cmd.hpp"
#include "terminal_text.hpp"

namespace leafdig::cli {
namespace {

namespace acq = leafdig::acquisition;
namespace m = leafdig::model;
using nlohmann::json;

// A session's field check, and the sentinel divots that confirmed it when they were taken.
void printField(const acq::FieldApplied& field) {
  std::cout << "  field: " << terminalText(field.words()) << "\n";
  if (field.sentinels) std::cout << "  sentinels: " << terminalText(field.sentinels->words()) << "\n";
}

// `sessions show`'s lines for a moved transmitter: each position after the first with its
// points and its fit (`worst` names the landmark — a plant's, or a leaf's board point).
void printTransmitterPositions(const json& positions, const char* landmark, const char* worst) {
  for (const json& t : positions)
    if (t.at("position").get<int>() > 1)
      std::cout << "  transmitter moved: position " << t.at("position").get<int>() << ", " << t.at("points").get<int>()
                << " points, fitted RMS " << std::fixed << std::setprecision(2) << t.at("rms_mm").get<double>()
                << " mm (worst " << t.at("worst_mm").get<double>() << " mm at " << landmark << " "
                << t.at(worst).get<int>() << ")\n"
                << std::defaultfloat;
}

// How far a node's point may be off (acquisition::CapturedSurvey::nodeToleranceMm), said when
// the field or a move makes it more than the digitizer's own: the widest, and what it is made of.
void printNodeTolerance(const acq::CapturedSurvey& captured) {
  if (captured.transmitter.size() < 2 && !captured.fieldHoldoutRmsMm) return;
  double widest = 0, move = 0;
  for (const auto& [node, mm] : captured.nodeToleranceMm) widest = std::max(widest, mm);
  for (const acq::TransmitterPosition& t : captured.transmitter) move = std::max(move, t.rmsMm);
  std::cout << std::fixed << std::setprecision(2) << "  node tolerance (95 %): up to " << widest
            << " mm — the digitizer's " << m::kFastrakSigmaMm << " mm per coordinate";
  if (captured.fieldHoldoutRmsMm)
    std::cout << ", the field correction's " << *captured.fieldHoldoutRmsMm << " mm on divots it did not see";
  if (move > 0) std::cout << ", the moves' fits up to " << move << " mm";
  std::cout << "\n" << std::defaultfloat;
}

// The history as `sessions show --json` and `sessions list --json` give it (db/history.hpp).
json historyJson(const std::vector<db::ReviewEntry>& history) {
  return json::parse(db::reviewHistoryJson(history));
}

// Each decision and correction on a line: who, when, why; a correction's item, its value before
// and after and how far a point moved.
void printHistory(const std::vector<db::ReviewEntry>& history) {
  const auto point = [](const std::array<double, 3>& p) {
    std::ostringstream t;
    t << std::fixed << std::setprecision(1) << "(" << p[0] << ", " << p[1] << ", " << p[2] << ")";
    return t.str();
  };
  for (const auto& r : history) {
    std::ostringstream line;
    line << "  " << r.action;
    if (r.action == "reopened") line << " (was " << terminalText(r.reopens) << ")";
    if (r.action == "corrected") {
      line << " " << terminalText(r.what);
      if (r.row) line << " row " << *r.row;
      if (r.col) line << " col " << *r.col;
      line << ": ";
      if (r.fromMm && r.toMm) {
        line << point(*r.fromMm) << " → " << point(*r.toMm) << " mm, moved " << std::fixed << std::setprecision(1)
             << *r.movedMm() << " mm";
      } else if (r.fromValueMm && r.toValueMm) {
        line << std::fixed << std::setprecision(3) << *r.fromValueMm << " → " << *r.toValueMm << " mm";
      }
      line << ",";
    }
    line << " by " << terminalText(r.who) << " at " << terminalText(r.utc) << " (event " << r.seq << ")";
    if (!r.why.empty()) line << ": " << terminalText(r.why);
    std::cout << line.str() << "\n";
  }
}

// A plant session shown: its step, every point and reading as the events say (in the
// digitizer's frame), each node's leaf as chosen, and the curators' corrections.
int showPlant(const db::EventStore& store, const SessionsOptions& o, const db::SessionInfo& info, json* sink) {
  const db::ChainReport chain = store.verify(o.id);
  const std::vector<db::Event> events = store.events(o.id);
  const acq::PlantSessionSetup setup = acq::PlantCaptureSession::setupFromJson(info.settingsJson);
  const acq::PlantEngine engine = acq::PlantCaptureSession::replay(setup, events);
  const db::Projected projected = db::project(events);
  const auto maybe = [](const std::optional<int>& v) { return v ? json(*v) : json(nullptr); };
  json points = json::array(), readings = json::array(), leaves = json::array(), corrections = json::array();
  // Which transmitter position each of the plant's own points was taken from (issue 29): its
  // event says (no `frame`: the first). Once the transmitter moved, a full leaf's markers and
  // the points a correction placed again say it too.
  const bool moved = engine.toFirst().size() > 1;
  std::map<std::int64_t, int> frames;
  for (const db::Event& e : events)
    if (e.kind == "accepted" || (moved && (e.kind == "corrected" || e.kind == "retake_cancelled"))) {
      const json p = json::parse(e.payloadJson, nullptr, false);
      if (p.is_discarded() || !p.is_object()) continue;
      const json& item = e.kind == "corrected" ? p.value("corrected", json()) : p;
      if (!item.is_object() || !item.contains("what") || !item.at("what").is_string() ||
          (!moved && item.at("what").get<std::string>().rfind("node", 0) == 0))
        continue;
      frames[e.seq] = item.contains("frame") && item.at("frame").is_number_integer() ? item.at("frame").get<int>() : 0;
    }
  // The plant as surveyed (docs/plants.md, "The survey"): its nodes with heights, internodes and
  // stem diameters, its leaves with angles, chords and areas — as soon as the landmarks and the
  // collar give it a frame; until then, why not.
  std::optional<acq::CapturedSurvey> captured;
  std::string surveyProblem;
  try {
    captured = acq::capturedSurvey(store, o.id);
  } catch (const model::InputError& e) {
    surveyProblem = e.what();
  } catch (const acq::SessionError& e) {
    surveyProblem = e.what();
  }
  for (const auto& mk : projected.markers) {
    json point{{"what", mk.what},
               {"row", maybe(mk.row)},
               {"col", maybe(mk.col)},
               {"position_mm", {mk.positionMm[0], mk.positionMm[1], mk.positionMm[2]}}};
    int position = 0;
    if (const auto it = frames.find(mk.seq); it != frames.end()) {
      point["transmitter_position"] = it->second + 1;
      position = it->second;
    }
    // The same point in the plant frame, as exports give it and `sessions correct` takes it by
    // default (a landmark taken again after a move is held in its own position's frame).
    if (captured) {
      Eigen::Vector3d p(mk.positionMm[0], mk.positionMm[1], mk.positionMm[2]);
      if (mk.what == "landmark_again" && position > 0 && position < static_cast<int>(engine.toFirst().size()))
        p = engine.toFirst()[static_cast<std::size_t>(position)] * p;
      const Eigen::Vector3d q = captured->survey.frame.point(p);
      point["position_plant_mm"] = {q.x(), q.y(), q.z()};
    }
    points.push_back(point);
  }
  const json transmitter = json::parse(acq::transmitterPositionsJson(acq::transmitterPositions(engine)));
  for (const auto& t : projected.thickness)
    readings.push_back({{"what", t.what}, {"row", maybe(t.row)}, {"col", maybe(t.col)}, {"value_mm", t.valueMm}});
  for (int node = 1; node <= engine.nodes(); ++node) {
    const acq::LeafChoice c = engine.choiceFor(node);
    json l{{"node", node}, {"kind", model::toString(c.kind)}, {"state", model::toString(c.state)}};
    if (!c.type.empty()) l["type"] = c.type;
    if (const acq::Engine* e = engine.leaf(node)) l["complete"] = e->complete();
    leaves.push_back(l);
  }
  for (const db::Event& e : events)
    if (e.kind == "corrected") {
      const json p = json::parse(e.payloadJson, nullptr, false);
      if (p.is_discarded()) continue;
      const auto text = [&p](const char* key) {
        return p.contains(key) && p.at(key).is_string() ? p.at(key).get<std::string>() : std::string();
      };
      corrections.push_back({{"seq", e.seq},
                             {"corrects", p.value("seq", json(nullptr))},
                             {"what", text("what")},
                             {"row", p.value("row", json(nullptr))},
                             {"col", p.value("col", json(nullptr))},
                             {"who", text("who")},
                             {"reason", text("reason")}});
    }
  const std::vector<db::ReviewEntry> history = db::reviewHistory(events);
  const acq::PlantStep st = engine.step();
  if (o.json) {
    json out{{"id", o.id},
             {"kind", "plant"},
             {"station", info.station},
             {"station_session_id", info.stationSessionId},
             {"status", info.status},
             {"step",
              {{"what", acq::toString(st.what)}, {"index", st.index}, {"part", st.part}, {"prompt", engine.prompt()}}},
             {"nodes", engine.nodes()},
             {"points", points},
             {"readings", readings},
             {"leaves", leaves},
             {"corrections", corrections},
             {"history", historyJson(history)},
             {"transmitter_positions", transmitter},
             {"survey", captured ? acq::capturedSurveyJson(*captured) : json(nullptr)},
             {"survey_problem", surveyProblem},
             {"relocating", engine.relocating() > 0},
             {"events", chain.events},
             {"chain_ok", chain.ok},
             {"problem", chain.problem},
             {"project", info.project},
             {"plant", info.plant},
             {"operator", info.operatorName},
             {"date", setup.date ? json(model::toIso(*setup.date)) : json(nullptr)}};
    if (setup.field) out["field_calibration"] = acq::fieldAppliedJson(*setup.field);
    if (setup.tip) out["tip_calibration"] = acq::tipAppliedJson(*setup.tip);
    if (sink != nullptr)
      *sink = std::move(out);
    else
      std::cout << out.dump() << "\n";
    return 0;
  }
  std::cout << "session " << o.id << " · plant " << terminalText(info.project + "/" + info.plant) << " · "
            << terminalText(info.status) << " · operator " << terminalText(info.operatorName) << "\n"
            << "  step: " << engine.prompt() << "\n  " << engine.nodes() << " nodes, " << points.size() << " points, "
            << readings.size() << " readings, " << corrections.size() << " corrections, " << chain.events
            << " events, chain " << (chain.ok ? "OK" : "BROKEN: " + terminalText(chain.problem)) << "\n";
  if (setup.field) printField(*setup.field);
  if (setup.tip) std::cout << "  stylus tip: " << terminalText(setup.tip->words()) << "\n";
  printTransmitterPositions(transmitter, "landmark", "worst_landmark");
  if (captured) {
    printSurvey(captured->survey, "  survey");
    printNodeTolerance(*captured);
  } else
    std::cout << "  survey: not yet (" << terminalText(surveyProblem) << ")\n";
  printHistory(history);
  return 0;
}

}  // namespace

namespace {

// The session shown: printed, or (sink, with o.json) its JSON handed back.
int show(const db::EventStore& store, const SessionsOptions& o, json* sink) {
  if (const auto info = store.session(o.id); info && info->kind == "plant") return showPlant(store, o, *info, sink);
  const acq::ReviewedSession r = acq::openForReview(store, o.id);
  const db::ChainReport chain = store.verify(o.id);
  // What the events say (a table edited behind them shows as chain_ok false, with the problem).
  const std::vector<db::Event> events = store.events(o.id);
  const db::Projected projected = db::project(events);
  const std::vector<db::ReviewEntry> history = db::reviewHistory(events);
  json tip = nullptr;
  json markers = json::array(), board = json::array(), boardAgain = json::array(), thickness = json::array();
  // A leaf taken across a move of the transmitter: each position, its points and its fit;
  // each marker's position (only once it was moved).
  const int positions = r.engine.transmitterPositions();
  const json transmitter =
      positions > 1 ? json::parse(acq::leafTransmitterPositionsJson(r.engine, false)) : json::array();
  for (const auto& mk : projected.markers) {
    const json pos = {mk.positionMm[0], mk.positionMm[1], mk.positionMm[2]};
    if (mk.what == "tip") {
      tip = pos;
    } else if (mk.what == "board") {
      board.push_back({{"col", mk.col.value_or(0)}, {"position_mm", pos}});
    } else if (mk.what == "board_again") {
      boardAgain.push_back({{"relocation", mk.row.value_or(0)}, {"col", mk.col.value_or(0)}, {"position_mm", pos}});
    } else {
      json m{{"row", mk.row.value_or(0)}, {"col", mk.col.value_or(0)}, {"position_mm", pos}};
      if (positions > 1)
        if (const acq::Item* i =
                acq::findItem(r.engine.items(), acq::What::Marker, mk.row.value_or(0), mk.col.value_or(0)))
          m["transmitter_position"] = i->frame + 1;
      markers.push_back(m);
    }
  }
  for (const auto& t : projected.thickness)
    thickness.push_back({{"what", t.what},
                         {"row", t.row ? json(*t.row) : json(nullptr)},
                         {"col", t.col ? json(*t.col) : json(nullptr)},
                         {"value_mm", t.valueMm}});
  if (o.json) {
    json j{{"id", o.id},
           {"station", r.info.station},
           {"station_session_id", r.info.stationSessionId},
           {"status", r.info.status},
           {"step", stepJson(r.engine.step(), r.engine.prompt())},
           {"tip", tip},
           {"markers", markers},
           {"thickness", thickness},
           {"events", chain.events},
           {"chain_ok", chain.ok},
           {"problem", chain.problem},
           {"project", r.info.project},
           {"plant", r.info.plant},
           {"leaf_position", r.info.leafPosition},
           {"leaf_type", r.info.leafType},
           {"operator", r.info.operatorName},
           {"mode", r.info.mode},
           {"order", r.info.order}};
    if (!board.empty()) j["board"] = board;
    if (!boardAgain.empty()) j["board_again"] = boardAgain;
    if (positions > 1) j["transmitter_positions"] = transmitter;
    if (const auto field = acq::sessionField(r.info)) j["field_calibration"] = acq::fieldAppliedJson(*field);
    if (const auto tip = acq::sessionTip(r.info)) j["tip_calibration"] = acq::tipAppliedJson(*tip);
    j["history"] = historyJson(history);
    if (sink != nullptr)
      *sink = std::move(j);
    else
      std::cout << j.dump() << "\n";
    return 0;
  }
  std::cout << "session " << o.id << " · " << terminalText(r.info.status) << " · "
            << terminalText(r.info.project + "/" + r.info.plant) << "/leaf " << r.info.leafPosition << " · "
            << terminalText(r.info.mode) << " · operator " << terminalText(r.info.operatorName) << "\n"
            << "  step: " << r.engine.prompt() << "\n  " << markers.size() << " markers"
            << (tip.is_null() ? ", no tip" : " + tip") << ", " << thickness.size() << " thickness readings, "
            << chain.events << " events, chain " << (chain.ok ? "OK" : "BROKEN: " + terminalText(chain.problem))
            << "\n";
  if (const auto field = acq::sessionField(r.info)) printField(*field);
  if (const auto tip = acq::sessionTip(r.info)) std::cout << "  stylus tip: " << terminalText(tip->words()) << "\n";
  printTransmitterPositions(transmitter, "board point", "worst_point");
  printHistory(history);
  return 0;
}

}  // namespace

int runShow(const db::EventStore& store, const SessionsOptions& o) {
  return show(store, o, nullptr);
}

// `sessions list`'s filters: every one given must hold.
bool listed(const db::SessionInfo& s, const SessionsOptions& o) {
  if (!o.status.empty() && s.status != o.status) return false;
  if (!o.kind.empty() && s.kind != o.kind) return false;
  if (!o.plant.empty() && s.plant != o.plant) return false;
  if (!o.station.empty() && s.station != o.station) return false;
  // created_utc is ISO 8601 (2026-11-28T10:00:00.000Z): a day compares as text.
  if (!o.since.empty() && s.createdUtc.substr(0, o.since.size()) < o.since) return false;
  return true;
}

json sessionListJson(const db::EventStore& store, const std::vector<db::SessionInfo>& sessions) {
  json a = json::array();
  for (const auto& s : sessions)
    a.push_back({{"id", s.id},
                 {"station", s.station},
                 {"station_session_id", s.stationSessionId},
                 {"project", s.project},
                 {"plant", s.plant},
                 {"kind", s.kind},
                 {"leaf_position", s.leafPosition},
                 {"leaf_type", s.leafType},
                 {"status", s.status},
                 {"operator", s.operatorName},
                 {"mode", s.mode},
                 {"created_utc", s.createdUtc},
                 {"events", s.headSeq},
                 {"decision", [&] {
                    // Only a decided session has a decision: the others' events are not read (a
                    // lab server lists thousands). A reopened session is complete: no decision stands.
                    if (s.status != "approved" && s.status != "rejected") return json(nullptr);
                    const auto d = db::lastDecision(db::reviewHistory(store.events(s.id)));
                    return d ? json::parse(db::reviewEntryJson(*d)) : json(nullptr);
                  }()}});
  return a;
}

json plantSurveysJson(const db::EventStore& store, const std::string& plant) {
  json list = json::array();
  for (const acq::PlantSurveyEntry& e : acq::plantSurveys(store, plant))
    list.push_back({{"session", e.session},
                    {"date", e.date},
                    {"status", e.status},
                    {"project", e.project},
                    {"operator", e.operatorName},
                    {"station", e.station},
                    {"created", e.createdUtc},
                    {"events", e.events},
                    {"verified", e.verified},
                    {"problem", e.problem.empty() ? json(nullptr) : json(e.problem)},
                    {"nodes", e.nodes},
                    {"leaves", {{"full", e.full}, {"quick", e.quick}, {"none", e.noLeaf}}}});
  return json{{"plant", plant}, {"surveys", list}};
}

json sessionJson(const db::EventStore& store, std::int64_t id) {
  SessionsOptions o;
  o.id = id;
  o.json = true;
  json out;
  (void)show(store, o, &out);
  return out;
}

}  // namespace leafdig::cli
