// `leafdig plant capture`: a plant digitized where it stands — by a technician with the
// digitizer and caliper on the ports given (`--digitizer`, `--caliper`, commands on standard
// input) or by the virtual technician through the simulated FASTRAK and caliper (`--simulate`;
// docs/plants.md, "Simulated plant capture" and "Real devices"), every decision committed to a
// plant session before it is printed; `--resume ID` goes on with an interrupted one. `--json`
// prints one object per committed change, the session first and `complete` last, as `capture
// --json` does.
#include "capture/plant_capture_cmd.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <thread>
#include <variant>

#include "capture/capture_console.hpp"
#include "capture/stdin_commands.hpp"
#include "commands.hpp"
#include "field_cmd.hpp"
#include "leafdig/acquisition/live/device_set.hpp"
#include "leafdig/acquisition/live/plant_loop.hpp"
#include "leafdig/acquisition/protocol/plant_engine.hpp"
#include "leafdig/acquisition/review/plant_export.hpp"
#include "leafdig/acquisition/run/capture_run.hpp"
#include "leafdig/acquisition/session/session.hpp"
#include "leafdig/acquisition/sim/plant_simulation.hpp"
#include "leafdig/db/lab.hpp"
#include "leafdig/model/errors.hpp"
#include "leafdig/model/plant/plant_markers.hpp"
#include "leafdig/model/plant/plant_protocol.hpp"
#include "leafdig/version.hpp"
#include "plant/plant_cmd.hpp"
#include "sessions_show.hpp"
#include "signals.hpp"
#include "terminal_text.hpp"

namespace leafdig::cli {

namespace acq = leafdig::acquisition;
namespace db = leafdig::db;
namespace m = leafdig::model;
using nlohmann::json;

namespace {

struct PlantCaptureOptions {
  bool simulate = false;
  std::string plantMarkers, protocol, db, project = "plants", operatorName = "technician", station, date;
  std::string digitizer, caliper, plant;  // real devices
  double stylusNoiseMm = 0.3, speed = 1.0;
  std::string distortion;                       // --distortion: the simulated field (issue 50)
  std::string fieldCalibration;                 // --field-calibration ID|latest|none (issue 50)
  std::string tipCalibration;                   // --tip-calibration ID|latest|none (issue 50)
  std::string simTip;                           // --sim-tip x,y,z: the simulated stylus' sensor offset
  std::optional<double> fieldCheckMaxAgeHours;  // --field-check-max-age-hours (capture_console.hpp)
  std::optional<int> sentinels;                 // --sentinels N (capture_console.hpp)
  std::string jigPose = "200,-620,0,90";        // simulation: where the jig lies for the sentinels
  double giveUpAfterS = 180;                    // simulation: a technician that gets nowhere this long is stopped
  int relocateSourceAfter = 0;
  std::optional<double> relocationToleranceMm;  // --relocation-tolerance: a new session's
  bool referenceReceiver = false;
  double potTurnDeg = 0;
  std::uint64_t seed = 1;
  std::int64_t resume = 0;
  bool json = false;
};

json nullable(int v) {
  return v > 0 ? json(v) : json(nullptr);
}

json feedbackJson(const acq::PlantFeedback& f, const acq::PlantCaptureSession& s) {
  using K = acq::PlantDecision::Kind;
  const acq::PlantDecision& d = f.decision;
  json j;
  if (f.storeRefused) return json{{"event", "store_refused"}, {"message", *f.storeRefused}};
  if (f.control == acq::PlantFeedback::Control::Paused)
    return json{{"event", "paused"}, {"reason", f.paused}, {"seq", f.seq}, {"prompt", s.engine().prompt()}};
  if (f.control == acq::PlantFeedback::Control::Resumed)
    return json{{"event", "resumed"}, {"seq", f.seq}, {"prompt", s.engine().prompt()}};
  switch (d.kind) {
    case K::Accepted:
    case K::Undone:
    case K::RetakeStarted:
    case K::RetakeCancelled:
      j = {{"event", d.kind == K::Accepted        ? "accepted"
                     : d.kind == K::Undone        ? "undone"
                     : d.kind == K::RetakeStarted ? "retake"
                                                  : "retake_cancelled"},
           {"what", acq::toString(d.item.what)},
           {"index", nullable(d.item.index)},
           {"part", nullable(d.item.part)}};
      if (acq::isStylusItem(d.item.what))
        j["value"] = {d.item.positionMm[0], d.item.positionMm[1], d.item.positionMm[2]};
      else
        j["value"] = d.item.valueMm;
      break;
    case K::Leaf: {
      using L = acq::Decision::Kind;
      j = {{"event", d.leaf.kind == L::Accepted          ? "accepted"
                     : d.leaf.kind == L::Undone          ? "undone"
                     : d.leaf.kind == L::RowsEnded       ? "rows_ended"
                     : d.leaf.kind == L::RetakeStarted   ? "retake"
                     : d.leaf.kind == L::RetakeCancelled ? "retake_cancelled"
                                                         : "rows_reopened"},
           {"node", d.node}};
      if (d.leaf.kind != L::RowsEnded && d.leaf.kind != L::RowsReopened) {
        j["what"] = acq::toString(d.leaf.item.what);
        j["row"] = nullable(d.leaf.item.row);
        j["col"] = nullable(d.leaf.item.col);
      }
      break;
    }
    case K::Rejected: j = {{"event", "rejected"}, {"reason", d.reason}}; break;
    case K::LeafChosen:
    case K::ChoiceUndone:
      j = {{"event", d.kind == K::LeafChosen ? "leaf_chosen" : "choice_undone"},
           {"node", d.node},
           {"kind", m::toString(d.kind == K::LeafChosen ? d.choice.kind : d.previous.kind)},
           {"state", m::toString(d.kind == K::LeafChosen ? d.choice.state : d.previous.state)}};
      break;
    case K::LandmarksEnded: j = {{"event", "landmarks_ended"}}; break;
    case K::LandmarksReopened: j = {{"event", "landmarks_reopened"}}; break;
    case K::PlantEnded: j = {{"event", "plant_ended"}}; break;
    case K::PlantReopened: j = {{"event", "plant_reopened"}}; break;
    case K::NodePlaced:
    case K::PlacementUndone:
      j = {{"event", d.kind == K::NodePlaced ? "node_placed" : "placement_undone"},
           {"node", d.node},
           {"parent", d.place.parent},
           {"relation", std::string(1, d.place.relation)}};
      break;
    case K::RelocationStarted:
    case K::RelocationFitted:
    case K::RelocationReopened:
    case K::RelocationCancelled:
      j = {{"event", "relocation"},
           {"relocation", d.node},
           {"step", d.kind == K::RelocationStarted    ? "started"
                    : d.kind == K::RelocationFitted   ? "fitted"
                    : d.kind == K::RelocationReopened ? "reopened"
                                                      : "cancelled"}};
      if (d.kind == K::RelocationFitted) {
        j["rms_mm"] = d.fit.rmsMm;
        j["worst_mm"] = d.fit.worstMm;
      }
      break;
    case K::Ignored: break;
  }
  j["seq"] = f.seq;
  j["prompt"] = s.engine().prompt();
  return j;
}

// What a committed decision prints: a JSON line, or a line of words.
void printFeedback(const PlantCaptureOptions& o, std::int64_t id, const acq::PlantFeedback& f,
                   const acq::PlantCaptureSession& s) {
  if (o.json) {
    std::cout << feedbackJson(f, s).dump() << "\n";
    if (f.completeSeq)
      std::cout
          << json{{"event", "complete"}, {"session", id}, {"seq", *f.completeSeq}, {"nodes", s.engine().nodes()}}.dump()
          << "\n";
    std::cout << std::flush;
    return;
  }
  const json j = feedbackJson(f, s);
  std::cout << "  " << (f.decision.kind == acq::PlantDecision::Kind::Rejected ? "✗ " : "✓ ")
            << terminalText(j.value("event", std::string())) << " · now: " << terminalText(s.engine().prompt())
            << (f.decision.kind == acq::PlantDecision::Kind::Rejected ? " (" + terminalText(f.decision.reason) + ")"
                                                                      : std::string())
            << "\n"
            << std::flush;
}

// A plant captured with the devices on the operator's ports: the loop on this thread, commands
// from standard input, Ctrl-C stops between two events (the session stays open).
acq::PlantRunStats captureWithDevices(const PlantCaptureOptions& o, db::Store& store, std::int64_t id,
                                      const std::string& digitizer, const std::string& caliper) {
  installSignalHandlers();
  acq::PlantCaptureLoop loop(store, id);
  std::mutex out;
  acq::DeviceSet ports(digitizer, caliper, loop.sinks([&](const devices::DeviceStatus& st) {
    static thread_local std::string last;
    const std::string said = std::string(devices::toString(st.state)) + st.message;
    if (said == last) return;  // a rate change alone is not news
    last = said;
    const std::lock_guard lock(out);
    if (o.json)
      std::cout << json{{"event", "device"},     {"device", st.device},
                        {"where", st.where},     {"state", devices::toString(st.state)},
                        {"message", st.message}, {"remedy", st.remedy}}
                       .dump()
                << "\n"
                << std::flush;
    else
      std::cerr << "  " << terminalText(st.device) << " (" << terminalText(st.where)
                << "): " << devices::toString(st.state) << (st.message.empty() ? "" : " · " + terminalText(st.message))
                << (st.remedy.empty() ? "" : " · " + terminalText(st.remedy)) << "\n";
  }));
  if (!o.json)
    std::cout
        << "  commands (then Enter): undo · end · leaf N full|quick|none [state] [type] · retake WHAT [N [PART]] · "
           "retake node N WHAT [ROW [POINT]] · pause [why] · resume · "
           "quit\n  now: "
        << terminalText(loop.session().engine().prompt()) << "\n"
        << std::flush;
  ports.start();
  std::atomic<bool> done{false};
  StdinCommands input([&](const std::string& cmd) {
    try {
      loop.command(acq::parsePlantCommand(cmd));
    } catch (const std::invalid_argument& e) {
      const std::lock_guard lock(out);
      std::cerr << "leafdig: " << e.what() << "\n";
    }
  });
  std::thread watcher([&] {
    while (!done) {
      if (interrupted()) loop.stop();
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
  });
  acq::PlantRunStats stats;
  try {
    stats = loop.run({[&](const acq::PlantFeedback& f, const acq::PlantCaptureSession& s) {
      const std::lock_guard lock(out);
      printFeedback(o, id, f, s);
    }});
  } catch (...) {
    done = true;
    input.stop();
    watcher.join();
    throw;
  }
  done = true;
  input.stop();
  watcher.join();
  ports.stop();
  return stats;
}

int runPlantCapture(const PlantCaptureOptions& o) {
  const bool real = !o.simulate && o.resume == 0;
  if (real && (o.digitizer.empty() || o.caliper.empty()))
    throw std::invalid_argument(
        "give the devices, e.g. --digitizer fastrak:/dev/ttyUSB0 --caliper sylvac:/dev/ttyUSB1 (leafdig devices list "
        "shows the ports), or --simulate to try it with the virtual technician");
  if (o.simulate && (!o.digitizer.empty() || !o.caliper.empty()))
    throw std::invalid_argument(
        "--simulate uses the simulated FASTRAK and caliper: leave out --digitizer and --caliper");
  if (!o.digitizer.empty()) (void)acq::parseDigitizerSpec(o.digitizer);  // refused before anything is written
  if (!o.caliper.empty()) (void)acq::parseCaliperSpec(o.caliper);
  if (real && o.plant.empty())
    throw std::invalid_argument("name the plant you digitize: --plant ID (e.g. --plant tobacco-p12)");
  acq::checkSimulationSpeed(o.speed);
  checkRelocationTolerance(o.relocationToleranceMm, o.resume != 0);
  if (!o.distortion.empty() && !o.simulate)
    throw std::invalid_argument(
        "--distortion bends the simulated digitizer's field: it goes with --simulate (a real field is what it is)");
  // Read once; a bad setting is refused before anything is written.
  const double maxCheckAgeHours = fieldCheckMaxAge(o.fieldCheckMaxAgeHours);
  if (o.resume != 0 && !o.fieldCalibration.empty() && o.fieldCalibration != "none")
    throw std::invalid_argument(
        "a resumed session goes on through the field check it began with (sessions show "
        "says which): leave out --field-calibration");
  if (o.resume != 0 && !o.tipCalibration.empty())
    throw std::invalid_argument(
        "a resumed session goes on with the tip calibration it began with (sessions show says which): leave out "
        "--tip-calibration");
  if (!o.simTip.empty() && !o.simulate)
    throw std::invalid_argument("--sim-tip describes the simulated stylus: it goes with --simulate");
  if (o.relocateSourceAfter > 0 && !o.simulate)
    throw std::invalid_argument(
        "--relocate-source-after moves the simulated transmitter: it goes with --simulate (with devices, type "
        "'move' when you move the transmitter)");
  // A resumed simulation goes on as it was begun (with or without the reference receiver):
  // checked against the session below.
  acq::checkPotTurn(o.potTurnDeg, o.simulate || o.resume != 0, o.referenceReceiver || o.resume != 0, "pot");
  if (!(o.stylusNoiseMm >= 0.0 && o.stylusNoiseMm <= 20.0))
    throw std::invalid_argument("the stylus noise must be between 0 and 20 mm");
  std::int64_t id = o.resume;
  std::unique_ptr<db::Store> store;
  std::string digitizer = o.digitizer, caliper = o.caliper;
  // With devices, --reference-receiver is the spec's ",reference=2" (receiver 2 on the pot).
  if (o.referenceReceiver && !digitizer.empty() && digitizer.find(",reference=") == std::string::npos)
    digitizer += ",reference=2";
  // Sentinel divots of the field check, before the session is made (field_cmd.hpp).
  SentinelOutcome sentinels;
  sentinels.fieldCalibration = o.fieldCalibration;
  if (o.resume != 0 && o.sentinels.value_or(0) != 0)
    throw std::invalid_argument(
        "a resumed session goes on through the field check it began with: leave out --sentinels");
  if (o.resume == 0) {
    installSignalHandlers();
    sentinels = takeSentinels(sentinelAskOf(o, digitizer, o.speed));
    if (sentinels.exitCode != 0) return sentinels.exitCode;
  }
  // A new session: what the operator typed, read before the store is touched.
  const auto createSession = [&](acq::PlantSessionSetup setup) {
    setup.project = o.project;
    setup.operatorName = o.operatorName;
    setup.station = o.station;
    if (o.relocationToleranceMm) setup.settings.relocationToleranceMm = *o.relocationToleranceMm;
    if (!o.protocol.empty()) setup.protocol = m::readPlantProtocolFile(o.protocol);
    // A simulated plant the protocol cannot take (a full leaf under a protocol of quick leaves, a
    // branch without a branch axis) is refused here, before a session is made — the virtual
    // technician would otherwise press in vain until it gave up (issue 47, 23).
    if (setup.simulatedPlant) {
      // The protocol itself first, in the words the capture refuses it with.
      std::optional<acq::PlantEngine> engine;
      try {
        engine.emplace(setup.protocol, setup.settings);
      } catch (const std::invalid_argument& e) {
        throw acq::SessionError(e.what());
      }
      const auto leafOf = [&](bool onBranch) -> const m::ProtocolLeaf* {
        for (const m::ProtocolEntity& e : setup.protocol.entities)
          if (e.leaf) {
            for (const m::ProtocolEntity& axis : setup.protocol.entities)
              if (!axis.leaf && axis.name == e.parent && (axis.order == 2) == onBranch) return &*e.leaf;
          }
        return nullptr;
      };
      // Each node's axis as the plant's own topology gives it (model::plantTopology).
      const std::vector<m::NodeLink> links = m::plantTopology(setup.simulatedPlant->nodes, "the simulated plant");
      for (std::size_t k = 0; k < setup.simulatedPlant->nodes.size(); ++k) {
        const m::PlantNode& n = setup.simulatedPlant->nodes[k];
        const bool onBranch = links[k].order == 2;
        if (n.branchesFrom && !engine->hasBranches())
          throw std::invalid_argument("the simulated plant's node " + std::to_string(k + 1) +
                                      " starts a branch, but the protocol has no branch: simulate it with a "
                                      "protocol that has one (data/protocols/branched.plant-protocol.json)");
        const m::LeafKind kind = std::holds_alternative<m::MarkerSet>(n.leaf)   ? m::LeafKind::Full
                                 : std::holds_alternative<m::QuickLeaf>(n.leaf) ? m::LeafKind::Quick
                                                                                : m::LeafKind::None;
        if (kind == m::LeafKind::None) continue;
        const m::ProtocolLeaf* leaf = leafOf(onBranch);
        if (!leaf || !leaf->allows(kind))
          throw std::invalid_argument("the simulated plant's node " + std::to_string(k + 1) + " has a " +
                                      m::toString(kind) + " leaf, which the protocol (" + setup.protocol.species +
                                      ") does not take: give a protocol that takes it, or another --plant-markers");
      }
    }
    if (!o.date.empty()) {
      setup.date = m::parseSurveyDate(o.date);
      if (!setup.date) throw std::invalid_argument("--date " + o.date + ": give the survey's day as YYYY-MM-DD");
    }
    store = std::make_unique<db::Store>(o.db.empty() ? db::Store::defaultPath() : o.db);
    setup.field = acq::resolveFieldCalibration(*store, sentinels.fieldCalibration);
    acq::attachSentinels(setup.field, sentinels.sentinels);
    setup.tip = acq::resolveTipCalibration(*store, o.tipCalibration,
                                           acq::tipDevice(setup.digitizer, setup.simulatedPlant.has_value()));
    id = acq::PlantCaptureSession::create(*store, setup);
  };
  if (real) {
    acq::PlantSessionSetup setup;
    setup.plant = o.plant;
    setup.digitizer = digitizer;
    setup.caliper = o.caliper;
    createSession(std::move(setup));
  } else if (id == 0) {
    // The sample plant beside the sample leaves (the source tree, or where the package put them).
    const std::string samples = leafdig::samplesDir();
    const std::string data =
        samples.empty() ? leafdig::sourceDataDir() : std::filesystem::path(samples).parent_path().string();
    const std::string file = o.plantMarkers.empty() ? data + "/plants/sample.plant-markers.json" : o.plantMarkers;
    acq::PlantSessionSetup setup = acq::simulatedPlantSetup(m::readPlantMarkersFile(file));
    if (o.referenceReceiver) setup.digitizer += ",reference=2";  // kept: a resumed capture goes on with it
    createSession(std::move(setup));
  } else {
    store = std::make_unique<db::Store>(o.db.empty() ? db::Store::defaultPath() : o.db);
    // A session taken with devices goes on with them (the ports given now, else the recorded ones).
    const auto info = store->session(id);
    if (info && info->kind == "plant") {
      const acq::PlantSessionSetup recorded = acq::PlantCaptureSession::setupFromJson(info->settingsJson);
      if (o.potTurnDeg != 0.0 &&
          (!recorded.simulatedPlant || acq::parseDigitizerSpec(recorded.digitizer).referenceStation == 0))
        throw std::invalid_argument("plant session " + std::to_string(id) +
                                    " was not begun as a simulation with a reference receiver: --pot-turn would "
                                    "move the plant under the stylus; resume it without --pot-turn");
      if (!recorded.simulatedPlant) {
        if (o.simulate)
          throw std::invalid_argument("plant session " + std::to_string(id) +
                                      " was taken with devices: resume it without --simulate");
        if (digitizer.empty()) digitizer = recorded.digitizer;
        if (caliper.empty()) caliper = recorded.caliper;
        if (digitizer.empty() || caliper.empty())
          throw std::invalid_argument("plant session " + std::to_string(id) +
                                      " records no devices: give --digitizer and --caliper");
      }
    }
  }
  const bool withDevices = !digitizer.empty();
  // The session's field and tip as it keeps them (a new one's just resolved, a resumed one's own).
  const acq::PlantSessionSetup kept = acq::PlantCaptureSession::setupFromJson(store->session(id)->settingsJson);
  const std::optional<acq::TipApplied>& tip = kept.tip;
  if (o.json)
    std::cout << json{{"event", "session"}, {"session", id}}.dump() << "\n" << std::flush;
  else
    std::cout << "leafdig plant capture · plant session " << id << " · "
              << (withDevices ? "digitizer " + terminalText(digitizer) + " · caliper " + terminalText(caliper)
                              : std::string("simulated FASTRAK and caliper"))
              << "\n  " << terminalText(acq::fieldBanner(*store, kept.field, maxCheckAgeHours))
              << (tip ? "\n  stylus tip: " + terminalText(tip->words()) : std::string()) << "\n";
  if (withDevices) {
    const acq::PlantRunStats stats = captureWithDevices(o, *store, id, acq::withTip(digitizer, tip), caliper);
    const auto info = store->session(id);
    const bool complete = info && info->status == "complete";
    if (!o.json)
      std::cout << "  plant session " << id << (complete ? " complete" : " kept open") << ": " << stats.accepted
                << " accepted, " << stats.rejected << " rejected"
                << (complete ? std::string()
                             : "\n  continue with: leafdig plant capture --resume " + std::to_string(id) + " --db " +
                                   store->path())
                << "\n";
    return interrupted() ? 130 : 0;
  }

  acq::SimulationOptions sim;
  sim.speed = o.speed;
  sim.seed = o.seed;
  sim.stylusNoiseMm = o.stylusNoiseMm;
  sim.distortion = distortionOf(o.distortion);
  sim.stylusTipMm = simTipOf(o.simTip);
  sim.relocateSourceAfter = o.relocateSourceAfter;
  sim.potTurnDeg = o.potTurnDeg;  // the reference receiver: as the session was begun
  sim.mistakes = false;
  bool gaveUp = false;
  const acq::PlantRunStats stats = simulatePlant(
      *store, id, sim,
      [&](const acq::PlantFeedback& f, const acq::PlantCaptureSession& s) { printFeedback(o, id, f, s); },
      o.giveUpAfterS, &gaveUp);
  const auto info = store->session(id);
  const bool complete = info && info->status == "complete";
  if (!o.json)
    std::cout << "  plant session " << id << (complete ? " complete" : " kept open") << ": " << stats.accepted
              << " accepted, " << stats.rejected << " rejected, " << stats.gestures << " presses, " << stats.readings
              << " caliper readings"
              << (complete ? std::string()
                           : "\n  continue with: leafdig plant capture --resume " + std::to_string(id) + " --db " +
                                 store->path())
              << "\n";
  return interrupted() ? 130 : gaveUp ? 1 : 0;
}

struct SurveysOptions {
  std::string plant;
  std::string db;
  bool json = false;
};

int runSurveys(const SurveysOptions& o) {
  const std::string path = o.db.empty() ? db::Store::defaultPath() : o.db;
  if (path.rfind("postgresql://", 0) != 0 && !std::filesystem::exists(path))
    throw std::invalid_argument("no station database at " + path + ": name it with --db (leafdig capture writes it)");
  const std::unique_ptr<db::EventStore> store = db::openEventStore(path, true);
  if (o.json) {
    std::cout << plantSurveysJson(*store, o.plant).dump() << "\n";
    return 0;
  }
  const std::vector<acq::PlantSurveyEntry> surveys = acq::plantSurveys(*store, o.plant);
  std::cout << "plant " << terminalText(o.plant) << ": " << surveys.size() << " survey(s) in " << terminalText(path)
            << "\n";
  for (const acq::PlantSurveyEntry& e : surveys) {
    std::cout << "  " << terminalText(e.date) << "  session " << e.session << "  " << terminalText(e.status);
    if (e.verified && !e.problem.empty())
      std::cout << "  does not read: " << terminalText(e.problem);
    else if (e.verified)
      std::cout << "  " << e.nodes << " nodes (" << e.full << " full, " << e.quick << " quick, " << e.noLeaf
                << " without a leaf)";
    else
      std::cout << "  FAILS 'sessions verify': not read";
    std::cout << "  by " << terminalText(e.operatorName) << " at " << terminalText(e.station) << "\n";
  }
  if (surveys.empty()) std::cout << "  (none: `leafdig sessions list --db " << path << "` shows what the file holds)\n";
  return 0;
}

}  // namespace

void addPlantSurveysCommand(CLI::App& plant, CommandTable& table) {
  auto o = std::make_shared<SurveysOptions>();
  CLI::App* surveys =
      plant.add_subcommand("surveys", "List every dated survey (plant session) of one plant, oldest first");
  surveys->add_option("plant", o->plant, "The plant's id, as digitized (e.g. tobacco-p12)")->required();
  surveys->add_option("--db", o->db, "Station database (default: ~/.local/share/leafdig/station.sqlite)");
  surveys->add_flag("--json", o->json, "One JSON object: the plant and its surveys");
  table.add(surveys, [o] { return runSurveys(*o); });
}

acq::PlantRunStats simulatePlant(
    db::Store& store, std::int64_t id, const acq::SimulationOptions& options,
    const std::function<void(const acq::PlantFeedback&, const acq::PlantCaptureSession&)>& onFeedback,
    double giveUpAfterS, bool* gaveUp) {
  installSignalHandlers();
  GiveUpWatch progress(giveUpAfterS);  // as runSession's, for a leaf
  const auto told = [&](const acq::PlantFeedback& f, const acq::PlantCaptureSession& s) {
    if (f.decision.kind == acq::PlantDecision::Kind::Rejected)
      progress.refused(f.decision.reason);
    else
      progress.progressed();
    progress.at(s.engine().prompt(), s.paused());
    if (onFeedback) onFeedback(f, s);
  };
  // Ctrl-C or SIGTERM stops the capture between two events; the session stays open.
  std::atomic<bool> stop{false}, running{true}, stuck{false};
  std::string stuckWords;  // written by the watcher before `stuck`, read after it is joined
  std::thread watcher([&] {
    while (running) {
      if (interrupted()) stop = true;
      if (!stuck) {
        if (std::string words = progress.overdue("plant capture", id, store.path()); !words.empty()) {
          stuckWords = std::move(words);
          stuck = true;
          stop = true;
        }
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
  });
  try {
    const acq::PlantRunStats stats = acq::runSimulatedPlant(store, id, options, told, stop);
    running = false;
    watcher.join();
    if (stuck && !interrupted()) std::cerr << stuckWords;
    if (gaveUp) *gaveUp = stuck && !interrupted();
    return stats;
  } catch (...) {
    running = false;
    watcher.join();
    throw;
  }
}

void addPlantCaptureCommand(CLI::App& plant, CommandTable& table) {
  auto o = std::make_shared<PlantCaptureOptions>();
  CLI::App* capture = plant.add_subcommand(
      "capture", "Digitize a plant where it stands, node by node, into a plant session (devices, or --simulate)");
  capture->add_option("--digitizer", o->digitizer, "KIND:PORT of the digitizer, e.g. fastrak:/dev/ttyUSB0");
  capture->add_option("--caliper", o->caliper, "KIND:PORT or hid:VID:PID of the caliper, e.g. sylvac:/dev/ttyUSB1");
  capture->add_option("--plant", o->plant, "The plant's id (with devices; a simulation takes the file's)");
  capture->add_flag("--simulate", o->simulate,
                    "The virtual technician digitizes --plant-markers through the simulated FASTRAK and caliper");
  capture->add_option(
      "--plant-markers", o->plantMarkers,
      "The plant the virtual technician digitizes (leafdig.plant-markers/1; default: the sample plant)");
  capture->add_option("--protocol", o->protocol, "Plant protocol file (default: the built-in tobacco protocol)");
  capture->add_option("--db", o->db, "Station database (default: ~/.local/share/leafdig/station.sqlite)");
  capture->add_option("--project", o->project, "Project the plant belongs to")->capture_default_str();
  capture->add_option("--operator", o->operatorName, "Who digitizes")->capture_default_str();
  capture->add_option("--station", o->station, "This station's id (default: the settings file's, else the host name)");
  capture->add_option("--date", o->date, "The survey's day, YYYY-MM-DD (default: the plant-markers file's)");
  capture->add_option("--distortion", o->distortion, kDistortionHelp);
  capture->add_option("--field-calibration", o->fieldCalibration, kFieldCalibrationHelp);
  capture->add_option("--field-check-max-age-hours", o->fieldCheckMaxAgeHours, kFieldCheckMaxAgeHelp);
  capture->add_option("--sentinels", o->sentinels, kSentinelsHelp);
  capture
      ->add_option("--jig-pose", o->jigPose,
                   "Simulation: where the jig lies for the sentinel divots, x,y,z,yaw_deg (as leafdig field check's)")
      ->capture_default_str();
  capture->add_option("--tip-calibration", o->tipCalibration, kTipCalibrationHelp);
  capture->add_option("--sim-tip", o->simTip, kSimTipHelp);
  capture->add_option("--stylus-noise", o->stylusNoiseMm, "Simulated stylus noise, mm (σ per axis)")
      ->capture_default_str();
  capture->add_option("--seed", o->seed, "Simulation seed")->check(seedText())->capture_default_str();
  capture->add_option("--relocation-tolerance", o->relocationToleranceMm,
                      "A move of the transmitter is refused when its fit's RMS residual is above this, in mm "
                      "(0.1–10; default 1.5): set when a capture begins");
  capture
      ->add_option("--relocate-source-after", o->relocateSourceAfter,
                   "Simulation: after N accepted points the transmitter moves to a new random pose (seeded) and "
                   "the landmarks are taken again (0: never)")
      ->check(CLI::Range(0, 100000))
      ->capture_default_str();
  capture->add_flag("--reference-receiver", o->referenceReceiver,
                    "Receiver 2 is fixed to the pot: every stylus sample is taken in its frame (devices: the "
                    "digitizer spec's ,reference=2; simulation: the simulated FASTRAK's second receiver)");
  capture
      ->add_option("--pot-turn", o->potTurnDeg,
                   "Simulation with --reference-receiver: the pot turns by DEG degrees about the vertical, smoothly, "
                   "as the technician goes up the plant")
      ->capture_default_str();
  capture->add_option("--speed", o->speed, "Simulation speed (1 = real time, up to 50)")->capture_default_str();
  capture
      ->add_option("--give-up-after", o->giveUpAfterS,
                   "Simulation: stop, in words, a capture that gets nowhere for this many seconds")
      ->check(CLI::Range(1.0, 86400.0))
      ->capture_default_str();
  capture->add_option("--resume", o->resume, "Go on with an interrupted plant session");
  capture->add_flag("--json", o->json, "One JSON object per committed change (session first, complete last)");
  table.add(capture, [o] { return runPlantCapture(*o); });
}

}  // namespace leafdig::cli
