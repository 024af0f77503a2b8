#include "capture/capture_cmd.hpp"

#include <unistd.h>

#include <atomic>
#include <cmath>
#include <exception>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iomanip>
#include <iostream>
#include <map>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <thread>

#include "capture/capture_console.hpp"
#include "capture/plant_capture_cmd.hpp"
#include "capture/stdin_commands.hpp"
#include "commands.hpp"
#include "field_cmd.hpp"
#include "leafdig/acquisition/review/plant_export.hpp"
#include "leafdig/acquisition/review/review.hpp"
#include "leafdig/acquisition/run/capture_run.hpp"
#include "leafdig/acquisition/session/plant_session.hpp"
#include "leafdig/acquisition/session/session.hpp"
#include "leafdig/db/lab.hpp"
#include "leafdig/db/store.hpp"
#include "leafdig/model/errors.hpp"
#include "leafdig/model/files.hpp"
#include "leafdig/model/io/mesh_export.hpp"
#include "leafdig/model/io/model_json.hpp"
#include "leafdig/model/leaf/markers_json.hpp"
#include "leafdig/model/limits.hpp"
#include "leafdig/model/metrics/metrics.hpp"
#include "leafdig/model/synth/synthetic_leaf.hpp"
#include "leafdig/version.hpp"
#include "model/synth_cmd.hpp"
#include "sessions_cmd.hpp"
#include "signals.hpp"
#include "terminal_text.hpp"

namespace leafdig::cli {
namespace {

namespace acq = leafdig::acquisition;
namespace m = leafdig::model;
using nlohmann::json;

std::string samplesDir(const std::string& given) {
  if (!given.empty()) return given;
  const std::string found = leafdig::samplesDir();
  return found.empty() ? "data/samples" : found;
}

// The JSON-lines contract of the README: one object per committed change.
json feedbackJson(const acq::Feedback& f, std::int64_t session) {
  using K = acq::Feedback::Kind;
  json j{{"event", acq::toString(f.kind)}};
  switch (f.kind) {
    case K::Accepted:
    case K::RetakeCancelled:
      j["seq"] = f.seq;
      j["what"] = acq::toString(f.item.what);
      j["row"] = nullable(f.item.row);
      j["col"] = nullable(f.item.col);
      if (acq::isStylusItem(f.item.what))
        j["value"] = {f.item.positionMm[0], f.item.positionMm[1], f.item.positionMm[2]};
      else
        j["value"] = f.item.valueMm;
      if (!f.item.flag.empty()) j["flag"] = f.item.flag;
      break;
    case K::Rejected:
      j["seq"] = f.seq;
      j["reason"] = f.text;
      break;
    case K::Undone:
    case K::RetakeStarted:
      j["seq"] = f.undoneSeq;
      j["event_seq"] = f.seq;
      j["what"] = acq::toString(f.item.what);
      j["row"] = nullable(f.item.row);
      j["col"] = nullable(f.item.col);
      break;
    case K::Complete:
      j["session"] = session;
      j["seq"] = f.seq;
      break;
    case K::Paused:
      j["seq"] = f.seq;
      j["reason"] = f.text;
      break;
    case K::Device:
      j["seq"] = f.seq;
      j["message"] = f.text;
      break;
    case K::Relocation:
      j["seq"] = f.seq;
      j["relocation"] = f.relocation;
      j["step"] = f.text;
      if (f.text == "fitted") {
        j["rms_mm"] = f.fitRmsMm;
        j["worst_mm"] = f.fitWorstMm;
        j["worst_point"] = f.fitWorstPoint;
      }
      break;
    default: j["seq"] = f.seq; break;
  }
  return j;
}

void printTerminal(const acq::Feedback& f) {
  using K = acq::Feedback::Kind;
  switch (f.kind) {
    case K::Accepted: std::cout << "\a  ✓ " << describe(f.item) << "\n"; break;
    case K::Rejected: std::cout << "\a\a  ✗ NOT TAKEN: " << f.text << "\n"; break;
    case K::Undone: std::cout << "  ↶ undone: " << describe(f.item) << "\n"; break;
    case K::RetakeStarted: std::cout << "  ↻ retake: " << describe(f.item) << " is taken out; take it again\n"; break;
    case K::RetakeCancelled: std::cout << "  ↶ retake cancelled: " << describe(f.item) << " is back\n"; break;
    case K::RowsEnded: std::cout << "\a  ✓ rows ended\n"; break;
    case K::RowsReopened: std::cout << "  ↶ rows reopened\n"; break;
    case K::Paused: std::cout << "\a\a  ‖ PAUSED: " << f.text << "\n"; break;
    case K::Resumed: std::cout << "  ▶ resumed\n"; break;
    case K::Complete: std::cout << "\a  ✓ LEAF COMPLETE\n"; break;
    case K::Abandoned: std::cout << "  ✗ session abandoned: " << f.text << "\n"; break;
    case K::Device: std::cout << "  ⚙ " << f.text << "\n"; break;
    case K::Relocation:
      if (f.text == "started")
        std::cout << "\a  ⇄ transmitter moved (position " << f.relocation + 1
                  << "): take the three board points again\n";
      else if (f.text == "fitted")
        std::cout << "\a  ✓ transmitter position " << f.relocation + 1 << " fitted: RMS " << std::setprecision(2)
                  << std::fixed << f.fitRmsMm << " mm, worst board point " << f.fitWorstPoint << " " << f.fitWorstMm
                  << " mm\n";
      else
        std::cout << "  ↶ move of the transmitter " << f.text << "\n";
      break;
  }
}

struct RunResult {
  int exitCode = 0;
  acq::Snapshot last;
  acq::VirtualOperator::Stats stats;
};

acq::RunRequest requestFrom(const CaptureOptions& o, std::optional<std::int64_t> resumeId) {
  if (db::isServerUrl(o.db))
    throw std::invalid_argument(
        "capture writes the station's own file, not the lab server: give --db FILE, and send it with "
        "'leafdig sync push --db FILE --to " +
        db::redactUrl(o.db) + "'");
  acq::RunRequest r;
  r.db = stationDbPath(o.db);
  r.resume = resumeId.value_or(0);
  acq::SessionSetup& s = r.setup;
  s.project = o.project;
  s.plant = o.plant;
  s.leafPosition = o.leafPosition;
  s.leafType = o.leafType;
  if (!o.serration.empty()) s.serration = m::serrationFromString(o.serration);
  if (o.toothDepthMm) {
    if (!(*o.toothDepthMm > 0 && *o.toothDepthMm <= m::kMaxThicknessMm))
      throw std::invalid_argument("--tooth-depth must be a depth in mm, above 0 and at most 100");
    if (!s.serration || *s.serration == m::Serration::None)
      throw std::invalid_argument("--tooth-depth is the depth of the teeth --serration declares: give --serration too");
    s.toothDepthMm = o.toothDepthMm;
  }
  s.operatorName = o.operatorName;
  if (!o.station.empty()) db::checkStationId(o.station);
  s.station = o.station;
  s.settings.mode = m::thicknessModeFromString(o.mode);
  s.settings.order = acq::orderFromString(o.order);
  // A simulated move of the transmitter is fitted to the board's three points: it takes them.
  s.settings.boardFrame = o.board || (o.simulate && o.relocateSourceAfter > 0);
  if (o.relocationToleranceMm) s.settings.relocationToleranceMm = *o.relocationToleranceMm;
  s.simulated = o.simulate;
  if (resumeId) {
    r.digitizer = o.digitizer;
    r.caliper = o.caliper;
  } else {
    s.digitizer = o.digitizer;
    s.caliper = o.caliper;
    if (o.referenceReceiver && !s.digitizer.empty() && s.digitizer.find(",reference=") == std::string::npos)
      s.digitizer += ",reference=2";
  }
  r.simulation.referenceReceiver = o.referenceReceiver;
  r.simulation.potTurnDeg = o.potTurnDeg;
  r.simulation.relocateSourceAfter = o.relocateSourceAfter;
  r.simulation.speed = o.speed.value_or(1.0);
  r.speed = o.speed;
  r.simulation.seed = o.seed;
  r.simulation.digitizerFaults = o.faults;
  r.simulation.caliperFaults = o.caliperFaults;
  r.simulation.mistakes = !o.noMistakes;
  r.leafFile = o.markers;
  if (o.stylusNoiseMm) r.simulation.stylusNoiseMm = *o.stylusNoiseMm;
  r.simulation.distortion = distortionOf(o.distortion);
  r.fieldCalibration = o.fieldCalibration == "none" ? "" : o.fieldCalibration;
  r.tipCalibration = o.tipCalibration;
  r.simulation.stylusTipMm = simTipOf(o.simTip);
  // The terminal draws no model: JSON lines need no preview at all, and the human terminal
  // only its "provisional thickness" note (the model, not its meshes). Building the preview's
  // meshes (two adaptive levels since issue 26, for the station's window) on the capture
  // thread after every item would only delay the next decision — on a loaded machine, or
  // under ASan, past the simulated technician's patience, who then pressed the old marker
  // again (a plant-library test's captures ran into its 15-minute limit that way).
  r.preview = o.json ? acq::PreviewDetail::None : acq::PreviewDetail::Model;
  if (!o.synth.empty()) {
    if (!o.simulate && !resumeId) throw std::invalid_argument("--synth is the simulated leaf: add --simulate");
    if (!o.markers.empty()) throw std::invalid_argument("give --markers or --synth, not both");
    SynthChoice choice = parseSynthSpec(o.synth);
    choice.id = "SYN-" + choice.shape + "-" + std::to_string(o.seed);
    // The exact leaf: the simulated stylus adds the noise.
    r.leaf = m::SyntheticLeaf(synthSpecFrom(choice)).markers(0.0, o.seed);
  }
  return r;
}

// Runs one capture (new or resumed) to its end, a quit, or Ctrl-C. `onStart` is called with
// the session's id before anything is captured.
RunResult runSession(const acq::RunRequest& request, const CaptureOptions& o, bool quiet,
                     const std::function<void(std::int64_t)>& onStart = {}) {
  RunResult result;
  std::string lastPrompt;
  std::int64_t id = 0;
  // Read once, before the run makes a session: a bad setting is refused with nothing written.
  const double maxCheckAgeHours = fieldCheckMaxAge(o.fieldCheckMaxAgeHours);
  // A simulated technician that gets nowhere (every input refused, or none made) is stopped
  // with words after --give-up-after seconds, not waited on for ever.
  GiveUpWatch progress(o.giveUpAfterS);
  acq::RunObserver observer;
  observer.onFeedback = [&](const acq::Feedback& f) {
    if (f.kind == acq::Feedback::Kind::Rejected)
      progress.refused(f.text);
    else if (f.kind != acq::Feedback::Kind::Device)
      progress.progressed();
    if (quiet) return;
    if (o.json)
      std::cout << feedbackJson(f, id).dump() << "\n" << std::flush;
    else
      printTerminal(f);
  };
  observer.onSnapshot = [&](const acq::Snapshot& s) {
    progress.at(s.prompt, s.paused);
    if (quiet || s.prompt == lastPrompt) return;
    lastPrompt = s.prompt;
    if (o.json) {
      std::cout << json{{"event", "prompt"}, {"text", s.prompt}}.dump() << "\n" << std::flush;
    } else {
      int points = 0, readings = 0;
      for (const auto& i : s.items) (acq::isStylusItem(i.what) ? points : readings)++;
      // Large and unmissable on a terminal: bold, reversed.
      const bool tty = ::isatty(1) != 0;
      std::cout << "\n  " << (tty ? "\033[1;7m ▶ " : "▶ ") << s.prompt << (tty ? " \033[0m" : "") << "\n    [" << points
                << " points, " << readings << " readings, " << s.completeRows << " complete rows"
                << (s.preview && s.preview->provisionalThickness ? "; preview with provisional thickness" : "") << "]\n"
                << std::flush;
    }
  };
  acq::CaptureRun run(request, observer);
  if (interrupted())
    throw db::StoreError(db::StoreErrorKind::Interrupted, "capture interrupted while opening",
                         "nothing was captured; run the command again");
  setCaptureRunning(true);
  id = run.sessionId();
  if (onStart) onStart(id);
  if (!quiet && !o.json)
    std::cout << "leafdig capture · session " << id << " · " << terminalText(run.setup().project) << " / "
              << terminalText(run.setup().plant) << " / leaf " << run.setup().leafPosition << " · "
              << m::toString(run.setup().settings.mode) << " mode\n  digitizer "
              << run.devices().spec(acq::DeviceSet::Role::Digitizer) << " · caliper "
              << run.devices().spec(acq::DeviceSet::Role::Caliper) << "\n  "
              << terminalText(acq::fieldBanner(db::Store(run.dbPath(), true), run.setup().field, maxCheckAgeHours))
              << (run.setup().tip ? "\n  stylus tip: " + terminalText(run.setup().tip->words()) : std::string())
              << "\n  keys (then Enter): u undo · e end rows · r WHAT ROW POINT retake · p pause · resume · "
                 "abandon [why] · q quit\n";
  run.start();
  // Commands on standard input (keys in a terminal, lines from a script).
  std::atomic<bool> done{false};
  StdinCommands input([&](const std::string& cmd) {
    try {
      run.command(acq::parseCommand(cmd));
    } catch (const std::invalid_argument& e) {
      std::cerr << "leafdig: " << e.what() << "\n";
    }
  });
  std::atomic<bool> stuck{false};
  std::string stuckWords;  // written by the watcher before `stuck`, read after it is joined
  std::thread watcher([&] {
    while (!done && !run.finished()) {
      if (interrupted()) run.requestStop();
      if (run.simulated() && !stuck) {
        if (std::string words = progress.overdue("capture", id, run.dbPath()); !words.empty()) {
          stuckWords = std::move(words);
          stuck = true;
          run.requestStop();
        }
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
  });
  run.wait();
  done = true;
  input.stop();
  watcher.join();
  result.last = run.shutdown(interrupted() ? "capture interrupted"
                             : stuck       ? "the simulated technician got nowhere"
                                           : "capture stopped by the operator");
  result.stats = run.operatorStats();
  result.exitCode = interrupted() ? 130 : 0;
  if (stuck && !interrupted()) {
    std::cerr << stuckWords;
    result.exitCode = 1;
  }
  if (!quiet && !o.json && !result.last.complete && result.last.status == "open")
    std::cout << "  session " << id << " kept at: " << result.last.prompt
              << "\n  continue with: leafdig sessions resume " << id << " --db " << run.dbPath() << "\n";
  return result;
}

}  // namespace

namespace {

int runCapture(const CaptureOptions& o, std::optional<std::int64_t> resumeId) {
  if (!o.simulate && !resumeId && (o.digitizer.empty() || o.caliper.empty()))
    throw std::invalid_argument(
        "capture needs --digitizer KIND:PORT and --caliper KIND:PORT (or --simulate): see 'leafdig devices list'");
  acq::checkPotTurn(o.potTurnDeg, o.simulate, o.referenceReceiver, "board");
  if (!o.distortion.empty() && !o.simulate)
    throw std::invalid_argument(
        "--distortion bends the simulated digitizer's field: it goes with --simulate (a real field is what it is)");
  if (!o.simTip.empty() && !o.simulate)
    throw std::invalid_argument("--sim-tip describes the simulated stylus: it goes with --simulate");
  if (o.relocateSourceAfter != 0 && !o.simulate)
    throw std::invalid_argument(
        "--relocate-source-after moves the simulated transmitter: it goes with --simulate (with devices, type "
        "'move' when you move the transmitter; the capture needs --board)");
  if (o.relocateSourceAfter < 0 || o.relocateSourceAfter > 10000)
    throw std::invalid_argument("--relocate-source-after must be a number of points, 1 to 10000 (0: never)");
  checkRelocationTolerance(o.relocationToleranceMm, resumeId.has_value());
  installSignalHandlers();
  acq::RunRequest request = requestFrom(o, resumeId);
  if (resumeId && o.sentinels.value_or(0) != 0)
    throw std::invalid_argument(
        "a resumed session goes on through the field check it began with: leave out --sentinels");
  if (!resumeId) {
    // Sentinel divots of the field check, before the session is made (field_cmd.hpp).
    const SentinelOutcome s = takeSentinels(sentinelAskOf(o, o.digitizer, o.speed.value_or(1.0)));
    if (s.exitCode != 0) return s.exitCode;
    if (s.sentinels) {
      request.sentinels = s.sentinels;
      request.fieldCalibration = s.fieldCalibration;
    }
  }
  const RunResult r = runSession(request, o, false, [&](std::int64_t id) {
    if (o.json) std::cout << json{{"event", "session"}, {"session", id}}.dump() << "\n" << std::flush;
  });
  return r.exitCode;
}

// ---- demo -------------------------------------------------------------------------------------
// The synthetic leaves the demo captures after the samples: varied shapes with a known area.
const char* const kDemoSynthLeaves[] = {
    "shape=ovate,serration=round,teeth=14,rows=10,length=420",
    "shape=obovate,rows=8,length=380",
    "shape=elliptic,serration=sharp,teeth=18,rows=12,length=360",
    "shape=oblong,rows=9,length=450",
    "shape=tobacco,rows=14,length=560",
};

// After the leaves, the demo's technician digitizes the sample plant where it stands, node by
// node (docs/plants.md), and exports its MTG, CSV, markers and survey.
int demoPlant(const CaptureOptions& c, const std::string& samples, const std::string& out, std::uint64_t seed) {
  const std::filesystem::path file = std::filesystem::path(samples).parent_path() / "plants/sample.plant-markers.json";
  if (!std::filesystem::exists(file)) {
    std::cout << "\n  (no sample plant beside " << samples << ": the plant is left out)\n";
    return 0;
  }
  acq::PlantSessionSetup setup = acq::simulatedPlantSetup(m::readPlantMarkersFile(file));
  setup.project = c.project;
  setup.station = c.station;
  db::Store store(c.db);
  const std::int64_t id = acq::PlantCaptureSession::create(store, setup);
  std::cout << "\n  session " << id << ": the sample plant where it stands (" << setup.simulatedPlant->nodes.size()
            << " nodes) ... " << std::flush;
  acq::SimulationOptions sim;
  sim.speed = c.speed.value_or(8.0);
  sim.seed = seed + 100;
  sim.stylusNoiseMm = c.stylusNoiseMm.value_or(0.3);
  sim.distortion = distortionOf(c.distortion);
  sim.mistakes = false;
  const auto t0 = std::chrono::steady_clock::now();
  const acq::PlantRunStats stats = simulatePlant(store, id, sim, {}, c.giveUpAfterS);
  const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (store.session(id)->status != "complete") {
    std::cout << "not complete\n";
    return interrupted() ? 130 : 1;
  }
  const acq::PlantExport p = acq::exportPlantSession(store, id, {"mtg", "csv", "markers", "json", "glb", "can"}, out);
  std::cout << "complete in " << std::fixed << std::setprecision(1) << secs << " s; " << stats.accepted
            << " events accepted, " << stats.rejected << " inputs rejected\n    survey: " << p.survey.nodes.size()
            << " nodes, " << p.survey.leaves.size() << " leaves; wrote";
  for (const auto& f : p.written) std::cout << " " << std::filesystem::path(f).filename().string();
  for (const auto& n : p.notes) std::cout << "\n    " << n;
  const db::ChainReport chain = store.verify(id);
  std::cout << "\n    hash chain: " << (chain.ok ? "OK" : "BROKEN") << " (" << chain.events << " events)\n";
  return chain.ok ? 0 : 1;
}

int runDemo(const CaptureOptions& o) {
  const std::string dir = samplesDir(o.samples);
  struct DemoLeaf {
    std::string name;
    std::string file;   // a sample
    std::string synth;  // or a synthetic leaf
  };
  std::vector<DemoLeaf> leaves;
  for (const auto& e : std::filesystem::directory_iterator(dir))
    if (e.path().string().ends_with(".markers.json"))
      leaves.push_back({e.path().filename().string(), e.path().string(), ""});
  std::sort(leaves.begin(), leaves.end(), [](const DemoLeaf& a, const DemoLeaf& b) { return a.file < b.file; });
  if (leaves.empty()) throw std::invalid_argument("no *.markers.json in " + dir + ": give --samples DIR");
  if (o.synthLeaves < 0 || o.synthLeaves > 20) throw std::invalid_argument("--synth-leaves must be between 0 and 20");
  for (int k = 0; k < o.synthLeaves; ++k) {
    const std::string spec = kDemoSynthLeaves[static_cast<std::size_t>(k) % std::size(kDemoSynthLeaves)];
    leaves.push_back({"synthetic " + spec, "", spec});
  }
  if (o.speed) acq::checkSimulationSpeed(*o.speed);  // before anything is made
  const std::string out = o.out.empty() ? "out/demo" : o.out;
  std::filesystem::create_directories(out);
  CaptureOptions c = o;
  c.db = o.db.empty() ? out + "/demo.sqlite" : o.db;
  c.simulate = true;
  c.project = "demo";
  std::cout << "leafdig demo: a virtual technician captures " << leaves.size()
            << " leaves with a simulated FASTRAK and Sylvac caliper over pseudo-terminals\n  database " << c.db << "\n";
  installSignalHandlers();
  int position = 0;
  for (const DemoLeaf& leaf : leaves) {
    c.plant = "plant-1";
    c.leafPosition = ++position;
    c.seed = o.seed + static_cast<std::uint64_t>(position);
    c.markers = leaf.file;
    c.synth = leaf.synth;
    acq::RunRequest request = requestFrom(c, std::nullopt);
    // The demo prints a line per leaf and draws nothing: no live preview (its meshes, built
    // after every item, made a demo under ASan on a loaded machine take 15 minutes, not 2).
    request.preview = acq::PreviewDetail::None;
    const std::size_t rows = request.leaf ? request.leaf->rows.size() : m::readMarkersFile(leaf.file).rows.size();
    std::int64_t id = 0;
    const auto t0 = std::chrono::steady_clock::now();
    const RunResult r = runSession(request, c, /*quiet=*/true, [&](std::int64_t session) {
      id = session;
      std::cout << "\n  session " << id << ": " << leaf.name << " (" << rows << " rows) ... " << std::flush;
    });
    const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (!r.last.complete) {
      std::cout << "not complete (" << r.last.prompt << ")\n";
      return interrupted() ? 130 : 1;
    }
    db::Store store(c.db);
    int rejected = 0;
    for (const auto& e : store.events(id)) rejected += e.kind == "rejected";
    std::cout << "complete in " << std::fixed << std::setprecision(1) << secs << " s; " << r.last.items.size()
              << " items, " << rejected << " inputs rejected (" << r.stats.doubleTaps << " double press, "
              << r.stats.outOfOrder << " out of order, " << r.stats.bounces << " caliper bounce), "
              << r.stats.wrongPointsUndone << " slip undone with the stylus\n";
    SessionsOptions e;
    e.db = c.db;
    e.id = id;
    e.out = out;
    e.warnUnapproved = false;  // the demo's own simulated captures
    if (const int rc = runExport(store, e); rc != 0) return rc;
    // The captured leaf's area against what is known of the leaf: the exact area of a
    // synthetic leaf, the leaf-area-meter reading of a sample.
    const acq::LeafSummary summary = acq::summarize(acq::openForReview(store, id));
    if (const auto& ac = summary.metrics.areaConstraint) {
      std::cout << "    area " << std::setprecision(0) << ac->modelMm2 << " mm^2 against "
                << (leaf.synth.empty() ? "the leaf area meter's " : "the exact ") << ac->measuredMm2
                << " mm^2: " << std::showpos << std::setprecision(2) << ac->differencePercent << std::noshowpos << " %"
                << (ac->exceeded ? " (over the 5 % threshold)" : "") << "\n";
    }
    if (const auto& u = summary.metrics.areaInterval) {
      const bool inside = summary.metrics.areaConstraint &&
                          summary.metrics.areaConstraint->measuredMm2 >= u->low95Mm2 &&
                          summary.metrics.areaConstraint->measuredMm2 <= u->high95Mm2;
      std::ostringstream line;
      line << std::fixed << std::setprecision(0) << "    95 % interval " << u->low95Mm2 << " - " << u->high95Mm2
           << " mm^2"
           << (summary.metrics.areaConstraint ? (inside ? ", holds the known area" : ", misses the known area") : "");
      std::cout << line.str() << "\n";
    }
    for (const auto& w : summary.metrics.warnings)
      std::cout << "    warning (" << w.name << "): " << terminalText(w.message) << "\n";
    const db::ChainReport chain = store.verify(id);
    std::cout << "    hash chain: " << (chain.ok ? "OK" : "BROKEN") << " (" << chain.events << " events)\n";
  }
  if (const int rc = demoPlant(c, dir, out, o.seed); rc != 0) return rc;
  std::cout << "\nDone. Inspect with: leafdig sessions list --db " << c.db << "\n";
  return 0;
}
void declareCaptureCommands(CLI::App& app, CommandTable& table, CaptureOptions& o) {
  const auto addCaptureOptions = [&o](CLI::App* c) {
    c->add_option("--db", o.db, "SQLite file (default: the station's, under $XDG_DATA_HOME/leafdig)");
    c->add_flag("--json", o.json, "One JSON object per line, each after it is committed (README: the contract)");
    c->add_option("--digitizer", o.digitizer, "KIND:PORT, e.g. fastrak:/dev/ttyUSB0 (patriot, liberty, microscribe)");
    c->add_option("--caliper", o.caliper,
                  "KIND:PORT or hid:VID:PID, e.g. sylvac:/dev/ttyUSB1, mitutoyo:PORT, hid:0fe7:4001");
    c->add_flag("--simulate", o.simulate, "Capture with the built-in simulators and a virtual operator");
    c->add_option("--markers", o.markers, "Leaf the virtual operator captures (leafdig.markers/1; default a sample)");
    c->add_option("--synth", o.synth,
                  "Or a synthetic leaf with a known area, e.g. shape=ovate,serration=round,teeth=14,rows=10 "
                  "(keys: shape length width symmetry serration tooth-depth teeth tooth-direction droop cup twist "
                  "wave wavelength rows; docs/synthetic-leaves.md)");
    c->add_option("--stylus-noise", o.stylusNoiseMm, "Noise of the simulated stylus per axis, σ in mm (default 0.3)");
    c->add_option("--distortion", o.distortion, kDistortionHelp);
    c->add_option("--field-calibration", o.fieldCalibration, kFieldCalibrationHelp);
    c->add_option("--field-check-max-age-hours", o.fieldCheckMaxAgeHours, kFieldCheckMaxAgeHelp);
    c->add_option("--tip-calibration", o.tipCalibration, kTipCalibrationHelp);
    c->add_option("--sim-tip", o.simTip, kSimTipHelp);
    c->add_option("--faults", o.faults,
                  "Digitizer faults, e.g. garbage=0.01,unplug=0.002:0.5 (see 'leafdig sim --help')");
    c->add_option("--caliper-faults", o.caliperFaults, "Caliper faults, same syntax");
    c->add_option("--seed", o.seed, "Seed of the simulation (noise, mistakes, faults)")->check(seedText());
    c->add_option("--speed", o.speed, "Time scale of the simulated operator and devices (e.g. 10)");
    c->add_flag("--no-mistakes", o.noMistakes, "The virtual operator makes no deliberate mistakes");
    c->add_option("--give-up-after", o.giveUpAfterS,
                  "Simulation: stop, in words, a capture that gets nowhere for this many seconds (default 180)")
        ->check(CLI::Range(1.0, 86400.0));
    c->add_option(
        "--station", o.station,
        "This station's id, stored with the session (default: [station] id= in ~/.config/leafdig/station.ini, "
        "else the host name)");
  };
  CLI::App* capture = app.add_subcommand("capture", "Guided capture of one leaf into the station's database");
  addCaptureOptions(capture);
  capture->add_option("--sentinels", o.sentinels, kSentinelsHelp);
  capture
      ->add_option("--jig-pose", o.jigPose,
                   "Simulation: where the jig lies for the sentinel divots, x,y,z,yaw_deg (as leafdig field check's)")
      ->capture_default_str();
  capture->add_option("--project", o.project, "Project name (created when new)");
  capture->add_option("--plant", o.plant, "Plant name (created when new)");
  capture->add_option("--leaf-position", o.leafPosition, "Leaf position on the stem, from the base (1, 2, …)")
      ->check(CLI::PositiveNumber);
  capture->add_option("--leaf-type", o.leafType,
                      "Leaf type for the organ library (e.g. lower, middle, upper; plant plans draw by it)");
  capture
      ->add_option("--serration", o.serration,
                   "The leaf's margin: none (entire), round, sharp, straight or acuminate teeth; the area interval "
                   "accounts for teeth the markers cannot see (default: not declared, and the interval says so)")
      ->check(CLI::IsMember(wordsIn(model::kSerrationNames)));
  capture->add_option("--tooth-depth", o.toothDepthMm, "Depth of the teeth in mm (default: 1.5 % of the leaf's width)");
  capture->add_option("--mode", o.mode, "standard (default), full or small")
      ->check(CLI::IsMember(wordsIn(model::kThicknessModeNames)));
  capture->add_option("--order", o.order, "sequential (default: all points, then thicknesses) or interleaved")
      ->check(CLI::IsMember(wordsIn(acquisition::kOrderNames)));
  capture->add_option("--operator", o.operatorName, "Who captures");
  capture->add_flag("--board", o.board, "Start with a 3-point board frame (origin, +X, +Y)");
  capture->add_flag("--reference-receiver", o.referenceReceiver,
                    "Receiver 2 is fixed to the leaf's board: every stylus sample is taken in its frame (devices: the "
                    "digitizer spec's ,reference=2; simulation: the simulated FASTRAK's second receiver)");
  capture->add_option("--pot-turn", o.potTurnDeg,
                      "Simulation with --reference-receiver: the board turns by DEG degrees, smoothly, as the rows "
                      "are taken");
  capture->add_option("--relocation-tolerance", o.relocationToleranceMm,
                      "A move of the transmitter is refused when its fit's RMS residual is above this, in mm "
                      "(0.1–10; default 1.5): set when a capture begins");
  capture->add_option("--relocate-source-after", o.relocateSourceAfter,
                      "Simulation: after N accepted points the transmitter moves to a new random pose (seeded) and the "
                      "virtual technician takes the board's three points again (implies --board)");

  // `sessions resume` goes on with a capture: the capture's options (sessions_cmd.cpp declares the rest).
  CLI::App* resume = addSessionsCommands(app, table);
  addCaptureOptions(resume);
  resume->add_option("id", o.id, "Session id")->required();

  CLI::App* demo = app.add_subcommand(
      "demo", "A virtual technician captures the sample leaves over simulated devices; exports and a summary");
  demo->add_option("--db", o.db, "SQLite file (default: OUT/demo.sqlite)");
  demo->add_option("--out", o.out, "Directory for the database and exports (default out/demo)");
  demo->add_option("--samples", o.samples, "Directory of *.markers.json leaves (default: data/samples)");
  demo->add_option("--speed", o.speed, "Time scale (default 8)");
  demo->add_option("--seed", o.seed, "Seed")->check(seedText());
  demo->add_option("--give-up-after", o.giveUpAfterS,
                   "Stop, in words, a capture that gets nowhere for this many seconds (default 180)")
      ->check(CLI::Range(1.0, 86400.0));
  demo->add_option("--synth-leaves", o.synthLeaves,
                   "Synthetic leaves with a known area captured after the samples (default 2, up to 20)");
  demo->add_option("--stylus-noise", o.stylusNoiseMm, "Noise of the simulated stylus per axis, σ in mm (default 0.3)");
  demo->add_option("--distortion", o.distortion, kDistortionHelp);
  demo->add_option("--station", o.station,
                   "This station's id, stored with every session (default: settings, host name)");
}

}  // namespace

void addCaptureCommands(CLI::App& app, CommandTable& table) {
  auto o = std::make_shared<CaptureOptions>();
  declareCaptureCommands(app, table, *o);
  table.add(app.get_subcommand("capture"), [o] { return runCapture(*o, std::nullopt); });
  CLI::App* demo = app.get_subcommand("demo");
  table.add(demo, [o, demo] {
    CaptureOptions d = *o;
    if (demo->count("--speed") == 0) d.speed = 8.0;
    return runDemo(d);
  });
  table.add(app.get_subcommand("sessions")->get_subcommand("resume"), [o] { return runCapture(*o, o->id); });
}

}  // namespace leafdig::cli
