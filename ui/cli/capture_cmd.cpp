#include "capture_cmd.hpp"

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

#include "commands.hpp"
#include "leafdig/acquisition/capture_run.hpp"
#include "leafdig/acquisition/plant_export.hpp"
#include "leafdig/acquisition/plant_session.hpp"
#include "leafdig/acquisition/review.hpp"
#include "leafdig/acquisition/session.hpp"
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
#include "plant_capture_cmd.hpp"
#include "signals.hpp"
#include "stdin_commands.hpp"
#include "synth_cmd.hpp"
#include "terminal_text.hpp"

namespace leafdig::cli {
namespace {

namespace acq = leafdig::acquisition;
namespace m = leafdig::model;
using nlohmann::json;

std::string dbPath(const CaptureOptions& o) {
  return o.db.empty() ? db::Store::defaultPath() : o.db;
}

std::string samplesDir(const std::string& given) {
  if (!given.empty()) return given;
  const std::string found = leafdig::samplesDir();
  return found.empty() ? "data/samples" : found;
}

json nullable(int v) {
  return v > 0 ? json(v) : json(nullptr);
}

json stepJson(const acq::Step& s, const std::string& prompt) {
  return {{"what", acq::toString(s.what)}, {"row", nullable(s.row)}, {"col", nullable(s.col)}, {"prompt", prompt}};
}

std::string describe(const acq::Item& i) {
  std::ostringstream s;
  s << std::fixed << std::setprecision(1);
  if (i.what == acq::What::Tip)
    s << "tip";
  else if (i.what == acq::What::Board)
    s << "board point " << i.col;
  else if (i.what == acq::What::BoardAgain)
    s << "board point " << i.col << " again (transmitter position " << i.row + 1 << ")";
  else if (i.what == acq::What::Marker)
    s << "row " << i.row << " point " << i.col;
  else if (i.what == acq::What::EdgeThickness)
    s << "margin thickness";
  else
    s << "row " << i.row << " " << acq::toString(i.what)
      << (i.what == acq::What::PointThickness ? " at point " + std::to_string(i.col) : "");
  if (acq::isStylusItem(i.what))
    s << " (" << i.positionMm[0] << ", " << i.positionMm[1] << ", " << i.positionMm[2] << ") mm";
  else
    s << std::setprecision(3) << " " << i.valueMm << " mm";
  if (!i.flag.empty()) s << " [" << i.flag << "]";
  return s.str();
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
  r.db = dbPath(o);
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
              << run.devices().spec(acq::DeviceSet::Role::Caliper)
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

GiveUpWatch::GiveUpWatch(double seconds) : seconds_(seconds), lastProgress_(std::chrono::steady_clock::now()) {}

void GiveUpWatch::progressed() {
  std::lock_guard lock(mutex_);
  lastProgress_ = std::chrono::steady_clock::now();
  refusedSince_ = 0;
}

void GiveUpWatch::refused(const std::string& reason) {
  std::lock_guard lock(mutex_);
  lastRefusal_ = reason;
  ++refusedSince_;
}

void GiveUpWatch::at(const std::string& prompt, bool paused) {
  std::lock_guard lock(mutex_);
  if (paused != paused_) lastProgress_ = std::chrono::steady_clock::now();  // a pause is no lack of progress
  paused_ = paused;
  where_ = prompt;
}

std::string GiveUpWatch::overdue(const std::string& capture, std::int64_t id, const std::string& db) const {
  std::lock_guard lock(mutex_);
  if (paused_ || std::chrono::steady_clock::now() - lastProgress_ <= std::chrono::duration<double>(seconds_)) return {};
  std::ostringstream why;
  why << std::fixed << std::setprecision(0) << "leafdig: the simulated technician got nowhere for " << seconds_ << " s "
      << (where_.empty() ? "before its first input was taken" : "at '" + where_ + "'") << " (" << refusedSince_
      << " inputs refused since the last accepted one"
      << (lastRefusal_.empty() ? "" : "; the last: '" + lastRefusal_ + "'") << "): the " << capture
      << " was stopped and kept. This is a fault of the simulation or of the station: report it with 'leafdig "
         "sessions show "
      << id << " --db " << db << "'\n";
  return why.str();
}

void checkRelocationTolerance(const std::optional<double>& mm, bool resuming) {
  if (!mm) return;
  if (!(*mm >= 0.1 && *mm <= 10.0))
    throw std::invalid_argument("--relocation-tolerance must be a residual in mm, 0.1 to 10 (default 1.5)");
  if (resuming)
    throw std::invalid_argument(
        "--relocation-tolerance is set when a capture begins: a resumed session keeps its own (leave it out)");
}

namespace {

int runCapture(const CaptureOptions& o, std::optional<std::int64_t> resumeId) {
  if (!o.simulate && !resumeId && (o.digitizer.empty() || o.caliper.empty()))
    throw std::invalid_argument(
        "capture needs --digitizer KIND:PORT and --caliper KIND:PORT (or --simulate): see 'leafdig devices list'");
  if (o.potTurnDeg != 0.0 && !(o.simulate && o.referenceReceiver))
    throw std::invalid_argument(
        "--pot-turn turns the simulated board with the reference receiver on it: it goes with --simulate "
        "--reference-receiver (without one, a turning board moves the leaf under the stylus)");
  if (!(std::abs(o.potTurnDeg) <= 360.0))
    throw std::invalid_argument("--pot-turn must be between -360 and 360 degrees");
  if (o.relocateSourceAfter != 0 && !o.simulate)
    throw std::invalid_argument(
        "--relocate-source-after moves the simulated transmitter: it goes with --simulate (with devices, type "
        "'move' when you move the transmitter; the capture needs --board)");
  if (o.relocateSourceAfter < 0 || o.relocateSourceAfter > 10000)
    throw std::invalid_argument("--relocate-source-after must be a number of points, 1 to 10000 (0: never)");
  checkRelocationTolerance(o.relocationToleranceMm, resumeId.has_value());
  installSignalHandlers();
  const RunResult r = runSession(requestFrom(o, resumeId), o, false, [&](std::int64_t id) {
    if (o.json) std::cout << json{{"event", "session"}, {"session", id}}.dump() << "\n" << std::flush;
  });
  return r.exitCode;
}

// ---- sessions ---------------------------------------------------------------------------------
int runList(const db::EventStore& store, const CaptureOptions& o) {
  const auto sessions = store.sessions();
  if (o.json) {
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
                   {"events", s.headSeq}});
    std::cout << a.dump() << "\n";
    return 0;
  }
  // On the lab server each session also carries its station and the id it has there.
  const bool server = db::isServerUrl(o.db);
  std::cout << std::left << std::setw(6) << "id" << (server ? "station:id            " : "") << std::setw(10)
            << "status" << std::setw(28) << "leaf" << std::setw(14) << "operator" << std::setw(8) << "events"
            << "created (UTC)\n";
  for (const auto& s : sessions) {
    std::cout << std::setw(6) << s.id;
    if (server) std::cout << std::setw(22) << terminalText(s.station + ":" + std::to_string(s.stationSessionId));
    std::cout << std::setw(10) << terminalText(s.status) << std::setw(28)
              << terminalText(s.project + "/" + s.plant + "/" +
                              (s.kind == "leaf" ? std::to_string(s.leafPosition) : std::string("(plant)")))
              << std::setw(14) << terminalText(s.operatorName) << std::setw(8) << s.headSeq
              << terminalText(s.createdUtc) << "\n";
  }
  if (sessions.empty()) std::cout << "(no sessions in " << terminalText(store.describe()) << ")\n";
  return 0;
}

// A plant session shown: its step, every point and reading as the events say (in the
// digitizer's frame), each node's leaf as chosen, and the curators' corrections.
int runShowPlant(const db::EventStore& store, const CaptureOptions& o, const db::SessionInfo& info) {
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
  for (const auto& mk : projected.markers) {
    json point{{"what", mk.what},
               {"row", maybe(mk.row)},
               {"col", maybe(mk.col)},
               {"position_mm", {mk.positionMm[0], mk.positionMm[1], mk.positionMm[2]}}};
    if (const auto it = frames.find(mk.seq); it != frames.end()) point["transmitter_position"] = it->second + 1;
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
  const acq::PlantStep st = engine.step();
  if (o.json) {
    std::cout << json{{"id", o.id},
                      {"kind", "plant"},
                      {"station", info.station},
                      {"station_session_id", info.stationSessionId},
                      {"status", info.status},
                      {"step",
                       {{"what", acq::toString(st.what)},
                        {"index", st.index},
                        {"part", st.part},
                        {"prompt", engine.prompt()}}},
                      {"nodes", engine.nodes()},
                      {"points", points},
                      {"readings", readings},
                      {"leaves", leaves},
                      {"corrections", corrections},
                      {"transmitter_positions", transmitter},
                      {"relocating", engine.relocating() > 0},
                      {"events", chain.events},
                      {"chain_ok", chain.ok},
                      {"problem", chain.problem},
                      {"project", info.project},
                      {"plant", info.plant},
                      {"operator", info.operatorName},
                      {"date", setup.date ? json(model::toIso(*setup.date)) : json(nullptr)}}
                     .dump()
              << "\n";
    return 0;
  }
  std::cout << "session " << o.id << " · plant " << terminalText(info.project + "/" + info.plant) << " · "
            << terminalText(info.status) << " · operator " << terminalText(info.operatorName) << "\n"
            << "  step: " << engine.prompt() << "\n  " << engine.nodes() << " nodes, " << points.size() << " points, "
            << readings.size() << " readings, " << corrections.size() << " corrections, " << chain.events
            << " events, chain " << (chain.ok ? "OK" : "BROKEN: " + terminalText(chain.problem)) << "\n";
  printTransmitterPositions(transmitter, "landmark", "worst_landmark");
  for (const json& c : corrections)
    std::cout << "  corrected (event " << c.at("seq").dump() << "): " << terminalText(c.at("what").get<std::string>())
              << " row " << c.at("row").dump() << " by " << terminalText(c.at("who").get<std::string>()) << ": "
              << terminalText(c.at("reason").get<std::string>()) << "\n";
  return 0;
}

int runShow(const db::EventStore& store, const CaptureOptions& o) {
  if (const auto info = store.session(o.id); info && info->kind == "plant") return runShowPlant(store, o, *info);
  const acq::ReviewedSession r = acq::openForReview(store, o.id);
  const db::ChainReport chain = store.verify(o.id);
  // What the events say (a table edited behind them shows as chain_ok false, with the problem).
  const db::Projected projected = db::project(store.events(o.id));
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
  printTransmitterPositions(transmitter, "board point", "worst_point");
  return 0;
}

int runVerify(const db::EventStore& store, const CaptureOptions& o) {
  std::vector<std::int64_t> ids;
  const bool all = o.all || o.id == 0;
  if (all)
    for (const auto& s : store.sessions()) ids.push_back(s.id);
  else
    ids.push_back(o.id);
  bool ok = true;
  json a = json::array();
  for (const auto id : ids) {
    db::ChainReport c;
    try {
      c = store.verify(id);
    } catch (const db::StoreError& e) {  // a damaged page under this session's events
      c.ok = false;
      c.problem = e.what();
    }
    ok = ok && c.ok;
    if (o.json)
      a.push_back({{"session", id},
                   {"chain_ok", c.ok},
                   {"events", c.events},
                   {"first_bad_seq", c.firstBadSeq ? json(*c.firstBadSeq) : json(nullptr)},
                   {"problem", c.problem},
                   {"genesis_form", c.genesisForm}});
    else
      std::cout << "session " << id << ": " << c.events << " events, "
                << (c.ok ? "chain OK"
                         : "CHAIN BROKEN at event " + std::to_string(c.firstBadSeq.value_or(0)) + ": " +
                               terminalText(c.problem))
                << (c.ok && c.genesisForm < 2
                        ? " (written before the station was in the chain: its station id is not covered)"
                        : "")
                << "\n";
  }
  // Every page of a station's file as well (opening for capture checks only what capture
  // touches); the lab server checks its own pages.
  const auto* file = dynamic_cast<const db::Store*>(&store);
  if (all && file) {
    const std::string pages = file->checkPages();
    if (pages != "ok") {
      ok = false;
      std::cerr << "leafdig: " << file->path() << " has damaged pages (" << pages
                << "): restore it from a backup; the file was not modified\n";
    } else if (!o.json) {
      std::cout << "pages: every page of " << file->path() << " checked, OK\n";
    }
  }
  if (o.json) std::cout << a.dump() << "\n";
  return ok ? 0 : 1;
}

// Who signs a review: in a station's file, --who; on the lab server, the login, or "--who
// (login)" (EventStore::signature; the server refuses any other signature: lab schema 11).
std::string signer(const db::EventStore& store, const std::string& who) {
  if (!store.login() && who.find_first_not_of(" \t\r\n\v\f") == std::string::npos)
    throw std::invalid_argument("a curator signs every review of a station's file: give --who NAME");
  return store.signature(who);
}

int runReview(db::EventStore& store, CaptureOptions o, const std::string& status) {
  o.who = signer(store, o.who);
  const auto seq = acq::review(store, o.id, status, o.who, o.why);
  if (o.json)
    std::cout << json{{"session", o.id}, {"status", status}, {"seq", seq}, {"who", o.who}}.dump() << "\n";
  else
    std::cout << "session " << o.id << " " << status << " by " << terminalText(o.who) << " (event " << seq << ")\n";
  return 0;
}

int runCorrect(db::EventStore& store, CaptureOptions o) {
  o.who = signer(store, o.who);
  acq::Correction c;
  acq::setCorrectionItem(c, o.what, o.node);  // --what and --node
  c.row = o.row;
  c.col = o.col;
  c.reason = o.why;
  c.who = o.who;
  if (!o.position.empty()) {
    if (o.position.size() != 3) throw std::invalid_argument("--position takes x,y,z in mm");
    c.positionMm = acq::Vec3{o.position[0], o.position[1], o.position[2]};
  }
  if (o.value) c.valueMm = *o.value;
  const auto seq = acq::correct(store, o.id, c);
  if (o.json)
    std::cout << json{{"session", o.id}, {"corrected", o.what}, {"seq", seq}, {"who", o.who}}.dump() << "\n";
  else
    std::cout << "session " << o.id << ": " << terminalText(o.what) << " corrected by " << terminalText(o.who)
              << " (event " << seq << ")\n";
  return 0;
}

int runExport(db::EventStore& store, const CaptureOptions& o) {
  if (const auto info = store.session(o.id); info && info->kind == "plant" && o.node == 0) {
    const acq::PlantExport p = acq::exportPlantSession(store, o.id, o.formats, o.out);
    if (o.json) {
      std::cout << json{{"session", o.id}, {"kind", "plant"}, {"outputs", p.written}, {"notes", p.notes}}.dump()
                << "\n";
    } else {
      std::cout << "plant session " << o.id << ": " << p.survey.nodes.size() << " nodes, " << p.survey.leaves.size()
                << " leaves\n";
      for (const auto& f : p.written) std::cout << "  wrote " << terminalText(f) << "\n";
      for (const auto& n : p.notes) std::cout << "  note: " << terminalText(n) << "\n";
    }
    return 0;
  }
  acq::ExportRequest request;
  request.formats = o.formats;
  request.frame = o.frame;
  request.blade = o.blade;
  request.outDir = o.out;
  if (o.node != 0) request.node = o.node;
  const acq::ExportResult r = acq::exportSession(store, o.id, request);
  if (o.json) {
    std::cout
        << json{{"session", o.id}, {"outputs", r.written}, {"metrics", json::parse(m::metricsToJson(r.metrics))}}.dump()
        << "\n";
  } else {
    std::cout << "session " << o.id << ": " << r.rows << " rows, blade area " << std::fixed << std::setprecision(0)
              << r.metrics.blade.areaMm2 << " mm^2\n";
    for (const auto& p : r.written) std::cout << "  wrote " << terminalText(p) << "\n";
  }
  return 0;
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
    CaptureOptions e = c;
    e.id = id;
    e.out = out;
    e.json = false;
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

void declareCaptureCommands(CLI::App& app, CaptureOptions& o) {
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
      ->check(CLI::IsMember({"none", "round", "sharp", "straight", "acuminate"}));
  capture->add_option("--tooth-depth", o.toothDepthMm, "Depth of the teeth in mm (default: 1.5 % of the leaf's width)");
  capture->add_option("--mode", o.mode, "standard (default), full or small")
      ->check(CLI::IsMember({"standard", "full", "small"}));
  capture->add_option("--order", o.order, "sequential (default: all points, then thicknesses) or interleaved")
      ->check(CLI::IsMember({"sequential", "interleaved"}));
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

  CLI::App* sessions = app.add_subcommand("sessions", "List, inspect, verify, resume, review and export sessions");
  sessions->require_subcommand(1);
  CLI::App* list = sessions->add_subcommand("list", "All sessions in the database");
  CLI::App* show = sessions->add_subcommand("show", "One session: step, markers, readings, chain");
  CLI::App* verify = sessions->add_subcommand("verify", "Recompute the hash chain of a session (or all)");
  CLI::App* resume = sessions->add_subcommand("resume", "Continue an open session at its exact step");
  CLI::App* approve = sessions->add_subcommand("approve", "Curator: approve a complete session");
  CLI::App* reject = sessions->add_subcommand("reject", "Curator: reject a session, saying why");
  CLI::App* corr = sessions->add_subcommand("correct", "Curator: correct one marker or reading, saying why");
  CLI::App* exp = sessions->add_subcommand("export", "Export a session's leaf: meshes, model, markers, CSV");
  for (CLI::App* c : {list, show, verify, approve, reject, corr, exp}) {
    c->add_option("--db", o.db,
                  "SQLite file (default: the station's), or the lab server's postgresql:// URL (docs/lab.md)");
    c->add_flag("--json", o.json, "JSON output");
  }
  addCaptureOptions(resume);
  for (CLI::App* c : {show, resume, approve, reject, corr, exp}) c->add_option("id", o.id, "Session id")->required();
  corr->add_option("--what", o.what,
                   "A leaf's board, board_again, tip, marker, midrib_thickness, vein_origin_thickness, "
                   "point_thickness, edge_thickness; a plant's landmark, landmark_again, collar, collar_diameter, "
                   "point, reading, quick_point (a board point or landmark after a move of the transmitter moves the "
                   "points of that move with it)")
      ->required();
  // 1-based when given (issue 47: --col 0 used to correct column 1); left out where none applies.
  corr->add_option("--row", o.row,
                   "Row (1-based; where it applies; board_again: the move); a plant's landmark or node number")
      ->check(CLI::Range(1, 100000));
  corr->add_option("--col", o.col,
                   "Column (1-based; where it applies; board: the board point); a plant item's part "
                   "(landmark_again: the move)")
      ->check(CLI::Range(1, 100000));
  corr->add_option("--node", o.node, "A plant session: the node whose full leaf holds the item");
  corr->add_option("--position", o.position, "Corrected marker position x,y,z in mm")->delimiter(',')->expected(3);
  corr->add_option("--value", o.value, "Corrected thickness (a plant: stem diameter) in mm");
  corr->add_option("--who", o.who,
                   "Curator's name (on the lab server stored as \"NAME (login)\"; left out: the login)");
  corr->add_option("--why", o.why, "Reason")->required();
  verify->add_option("id", o.id, "Session id (default: all)");
  verify->add_flag("--all", o.all, "Every session");
  for (CLI::App* c : {approve, reject}) {
    c->add_option("--who", o.who, "Curator's name (on the lab server stored as \"NAME (login)\"; left out: the login)");
    c->add_option("--why", o.why, "Reason (required to reject)");
  }
  exp->add_option("--out", o.out, "Directory to write into")->required();
  exp->add_option("--format", o.formats,
                  "glb, obj, ply, stl, model, markers, csv (default: all); a plant session: mtg, csv, markers, json, "
                  "glb, obj, ply, stl, can, model, plan")
      ->delimiter(',');
  exp->add_option("--node", o.node,
                  "A plant session's full leaf alone, the one at this node (the leaf's formats: glb, obj, ply, stl, "
                  "model, markers, csv)")
      ->check(CLI::Range(1, 9999));
  exp->add_option("--frame", o.frame, "leaf (default) or digitizer")->check(CLI::IsMember({"leaf", "digitizer"}));
  exp->add_option("--blade", o.blade, "interp (default), approx, bezier, nurbs")
      ->check(CLI::IsMember({"interp", "approx", "bezier", "nurbs"}));

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
  demo->add_option("--station", o.station,
                   "This station's id, stored with every session (default: settings, host name)");
}

// Runs a `sessions` command on the store of --db (read-only unless it writes).
template <class Run>
int withStore(const CaptureOptions& o, bool writes, Run run) {
  if (!db::isServerUrl(o.db) && !std::filesystem::exists(dbPath(o)))
    throw std::invalid_argument("no database at " + db::redactUrl(dbPath(o)) +
                                ": give --db FILE (capture creates one), or the lab server as postgresql://…");
  const std::unique_ptr<db::EventStore> store = db::openEventStore(dbPath(o), !writes);
  return run(*store, o);
}

}  // namespace

void addCaptureCommands(CLI::App& app, CommandTable& table) {
  auto o = std::make_shared<CaptureOptions>();
  declareCaptureCommands(app, *o);
  table.add(app.get_subcommand("capture"), [o] { return runCapture(*o, std::nullopt); });
  CLI::App* demo = app.get_subcommand("demo");
  table.add(demo, [o, demo] {
    CaptureOptions d = *o;
    if (demo->count("--speed") == 0) d.speed = 8.0;
    return runDemo(d);
  });
  CLI::App* s = app.get_subcommand("sessions");
  table.add(s->get_subcommand("resume"), [o] { return runCapture(*o, o->id); });
  table.add(s->get_subcommand("list"), [o] { return withStore(*o, false, runList); });
  table.add(s->get_subcommand("show"), [o] { return withStore(*o, false, runShow); });
  table.add(s->get_subcommand("verify"), [o] { return withStore(*o, false, runVerify); });
  table.add(s->get_subcommand("approve"), [o] {
    return withStore(*o, true,
                     [](db::EventStore& store, const CaptureOptions& c) { return runReview(store, c, "approved"); });
  });
  table.add(s->get_subcommand("reject"), [o] {
    return withStore(*o, true,
                     [](db::EventStore& store, const CaptureOptions& c) { return runReview(store, c, "rejected"); });
  });
  table.add(s->get_subcommand("correct"), [o] { return withStore(*o, true, runCorrect); });
  table.add(
      s->get_subcommand("export"), [o] { return withStore(*o, true, runExport); }, "cannot export: ");
}

}  // namespace leafdig::cli
