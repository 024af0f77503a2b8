#include "field_cmd.hpp"

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <nlohmann/json.hpp>
#include <thread>

#include "capture/capture_console.hpp"
#include "capture/stdin_commands.hpp"
#include "commands.hpp"
#include "leafdig/acquisition/field/field_applied.hpp"
#include "leafdig/acquisition/field/field_study.hpp"
#include "leafdig/acquisition/run/field_check_run.hpp"
#include "leafdig/acquisition/run/tip_calibration_run.hpp"
#include "leafdig/devices/sim/field_distortion.hpp"
#include "leafdig/model/errors.hpp"
#include "leafdig/model/files.hpp"
#include "leafdig/model/leaf/markers_json.hpp"
#include "leafdig/model/plant/plant_markers.hpp"
#include "leafdig/version.hpp"
#include "signals.hpp"
#include "terminal_text.hpp"

namespace leafdig::cli {
namespace {

namespace acq = leafdig::acquisition;
namespace dev = leafdig::devices;
using nlohmann::json;

struct FieldOptions {
  // model
  std::string fieldModel, out;
  double belowMm = 250, strength = 0.08;
  // check
  std::string jig, db, operatorName = "technician", station, digitizer, distortion, jigPose = "200,-620,0,90", map;
  double toleranceMm = acq::kDefaultFieldToleranceMm, speed = 4;
  std::uint64_t seed = 1;
  bool simulate = false, json = false;
  // show
  std::int64_t id = 0;
  // tip
  std::string simTip, divot = "250,0,-50", tipCalibration;
  double tipToleranceMm = acq::kDefaultTipToleranceMm;
  // study
  std::string plantJigPose = "480,-100,-330,90";
  double noiseMm = 0.25;
  int repeats = 10;
  std::vector<int> counts;
};

// The shipped data's folder (data/ in the source tree or the package): the sample jig, leaves and plant.
std::string dataDir() {
  const std::string samples = samplesDir();
  return samples.empty() ? sourceDataDir() : std::filesystem::path(samples).parent_path().string();
}

std::string defaultJig() {
  return dataDir() + "/fields/three-level.jig.json";
}

Eigen::Isometry3d poseOption(const std::string& text, const std::string& option) {
  try {
    return acq::parseJigPose(text);
  } catch (const std::invalid_argument& e) {
    std::string words = e.what();  // parseJigPose's words name --jig-pose
    if (words.rfind("--jig-pose", 0) == 0) words.replace(0, 10, option);
    throw model::InputError(words);
  }
}

// The simulated FASTRAK of a check, a tip calibration or sentinel divots: its speed and seed, the
// field of --distortion and the stylus of --sim-tip; its virtual technician makes no mistakes.
acq::SimulationOptions simulationOf(double speed, std::uint64_t seed, const std::string& distortion,
                                    const std::string& simTip) {
  acq::SimulationOptions s;
  s.speed = speed;
  s.seed = seed;
  s.mistakes = false;
  s.distortion = distortionOf(distortion);
  s.stylusTipMm = simTipOf(simTip);
  return s;
}

// `field model steel-bench -o FILE`: the shipped preset is this command's output with its
// defaults (data/fields/steel-bench.field.json; a test regenerates it byte for byte).
int runFieldModel(const FieldOptions& o) {
  dev::sim::SteelBenchModel m;
  m.belowMm = o.belowMm;
  m.strength = o.strength;
  const dev::sim::FieldDistortion f = dev::sim::steelBench(m);
  model::writeFileAtomically(o.out, dev::sim::encodeFieldDistortion(f));
  double worst = 0;
  for (const auto& d : f.displacementMm) worst = std::max(worst, std::hypot(d[0], d[1], d[2]));
  std::cerr << "leafdig: wrote " << o.out << ": " << o.fieldModel << " " << f.shape[0] << "×" << f.shape[1] << "×"
            << f.shape[2] << " grid every " << f.spacingMm << " mm, the largest displacement " << std::fixed
            << std::setprecision(1) << worst << " mm\n";
  return 0;
}

// The figure, written next to nothing else: `--map FILE.svg`.
void writeMap(const acq::FieldCalibration& c, const std::string& path) {
  const std::string title = "Field check " + std::to_string(c.id) + " · " + c.device + " · " + c.createdUtc;
  model::writeFileAtomically(
      path, model::fieldErrorMapSvg({&c.jig, &c.result.fit, c.result.toleranceMm, c.result.verdict, title}));
}

// What a run asks the technician to do next: a JSON line with --json, else a line highlighted on
// a terminal.
std::function<void(const std::string&)> promptPrinter(bool asJson) {
  const bool tty = ::isatty(1) != 0;
  return [asJson, tty](const std::string& prompt) {
    if (asJson)
      std::cout << json{{"event", "prompt"}, {"text", prompt}}.dump() << "\n" << std::flush;
    else
      std::cout << "  " << (tty ? "\033[1;7m ▶ " : "▶ ") << terminalText(prompt) << (tty ? " \033[0m" : "") << "\n"
                << std::flush;
  };
}

// A list of the station file's calibrations: their summaries as one JSON array, or a line each
// (`none` when there is none).
template <class Calibration>
int printCalibrations(const std::vector<Calibration>& all, bool asJson, std::string (*summary)(const Calibration&),
                      const std::function<void(std::ostream&, const Calibration&)>& line, const std::string& none) {
  if (asJson) {
    json list = json::array();
    for (const auto& c : all) list.push_back(json::parse(summary(c)));
    std::cout << list.dump() << "\n";
    return 0;
  }
  if (all.empty()) std::cout << none << "\n";
  for (const auto& c : all) {
    std::ostringstream text;
    text << std::fixed << std::setprecision(2);
    line(text, c);
    std::cout << terminalText(text.str()) << "\n";
  }
  return 0;
}

// Runs `run` with Ctrl-C stopping it through `stop` (the capture's signal handling), and gives
// back what it returned.
template <class Run>
auto runStoppable(const std::function<void()>& stop, Run run) -> decltype(run()) {
  std::atomic<bool> done{false};
  setCaptureRunning(true);
  std::thread watcher([&] {
    while (!done) {
      if (interrupted()) stop();
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
  });
  const auto finish = [&] {
    done = true;
    watcher.join();
    setCaptureRunning(false);
  };
  try {
    auto result = run();
    finish();
    return result;
  } catch (...) {
    finish();
    throw;
  }
}

// Exit 0 when the field passes or a correction brings it within tolerance, 3 when it fails.
int verdictCode(const acq::FieldCalibration& c) {
  return c.result.verdict == "fail" ? 3 : 0;
}

// Drives a run of divots on the terminal — the prompts, each decision, a troubled digitizer, `u`
// and `q` typed, Ctrl-C — and gives back what `go` returned (nothing when stopped).
template <class Result>
std::optional<Result> driveDivots(acq::FieldCheckRequest request, bool asJson, const std::string& title,
                                  const std::function<std::optional<Result>(acq::FieldCheckRun&)>& go) {
  const std::size_t jigSize = request.jig.points.size();
  acq::FieldCheckListener listener;
  listener.onPrompt = promptPrinter(asJson);
  std::atomic<bool> finished{false};  // the digitizer stopping after the last divot is no news
  listener.onDecision = [&](const acq::JigCapture::Decision& d) {
    using K = acq::JigCapture::Decision::Kind;
    const char* kind = d.kind == K::Accepted ? "accepted" : d.kind == K::Undone ? "undone" : "rejected";
    if (asJson)
      std::cout << json{{"event", kind}, {"text", d.words}}.dump() << "\n" << std::flush;
    else
      std::cout << "    " << kind << ": " << terminalText(d.words) << "\n" << std::flush;
    if (d.kind == K::Accepted && d.index + 1 == jigSize) finished = true;
  };
  listener.onStatus = [&](const dev::DeviceStatus& s) {
    if (finished || s.state == dev::LinkState::Streaming || s.state == dev::LinkState::Connecting) return;
    std::cerr << "leafdig: " << s.device << ": " << terminalText(s.message)
              << (s.remedy.empty() ? "" : " — " + terminalText(s.remedy)) << "\n";
  };
  acq::FieldCheckRun run(std::move(request), listener);
  if (!asJson)
    std::cout << title << " · " << terminalText(run.store().path()) << "\n  keys (then Enter): u undo · q quit\n";
  StdinCommands input([&](const std::string& line) {
    if (line == "u" || line == "undo")
      run.undo();
    else if (line == "q" || line == "quit")
      run.stop();
    else
      std::cerr << "leafdig: '" << terminalText(line) << "'? type u (undo the last divot) or q (quit)\n";
  });
  std::optional<Result> result = runStoppable([&] { run.stop(); }, [&] { return go(run); });
  input.stop();
  return result;
}

void printCheck(const acq::FieldCalibration& c, const FieldOptions& o) {
  if (o.json)
    std::cout << acq::fieldCheckSummaryJson(c) << "\n";
  else
    std::cout << terminalText(acq::fieldCheckSummaryText(c), true);
}

int runFieldCheck(const FieldOptions& o) {
  if (o.operatorName.empty())
    throw model::InputError("--operator: a field check is signed by who makes it; give a name");
  acq::FieldCheckRequest request;
  request.db = stationDbPath(o.db);
  request.station = o.station;
  request.who = o.operatorName;
  request.jig = model::readJigFile(o.jig.empty() ? defaultJig() : o.jig);
  request.toleranceMm = o.toleranceMm;
  request.digitizer = o.digitizer;
  request.simulated = o.simulate;
  request.tipCalibration = o.tipCalibration;
  if (!o.simulate && o.digitizer.empty())
    throw model::InputError(
        "a field check reads a digitizer: give --digitizer KIND:PORT (fastrak:/dev/ttyUSB0), "
        "or --simulate");
  if (!o.simulate && (!o.distortion.empty() || !o.simTip.empty()))
    throw model::InputError(std::string(o.distortion.empty() ? "--sim-tip" : "--distortion") +
                            " describes the simulated digitizer: it goes with --simulate");
  if (o.simulate) {
    request.simulation = simulationOf(o.speed, o.seed, o.distortion, o.simTip);
    request.jigPose = poseOption(o.jigPose, "--jig-pose");
  }
  const std::optional<acq::FieldCalibration> result = driveDivots<acq::FieldCalibration>(
      std::move(request), o.json, "leafdig field check", [](acq::FieldCheckRun& run) { return run.run(); });
  if (!result) {
    std::cerr << "leafdig: the field check was stopped before every divot was taken: nothing was stored\n";
    return interrupted() ? 130 : 1;
  }
  if (!o.map.empty()) writeMap(*result, o.map);
  printCheck(*result, o);
  return verdictCode(*result);
}

int runFieldList(const FieldOptions& o) {
  const db::Store store(stationDbPath(o.db), true);
  return printCalibrations<acq::FieldCalibration>(
      acq::fieldCalibrations(store), o.json, acq::fieldCheckSummaryJson,
      [](std::ostream& line, const acq::FieldCalibration& c) {
        line << c.id << "  " << c.createdUtc << "  " << c.device << "  RMS " << c.result.fit.rmsMm << " mm  max "
             << c.result.fit.maxMm << " mm  " << c.result.verdict << "  correction "
             << c.result.correction.correction.name() << "  by " << c.operatorName;
      },
      "no field check in " + terminalText(store.path()) + ": run 'leafdig field check'");
}

int runFieldShow(const FieldOptions& o) {
  const db::Store store(stationDbPath(o.db), true);
  for (const auto& c : acq::fieldCalibrations(store)) {
    if (c.id != o.id) continue;
    if (!o.map.empty()) writeMap(c, o.map);
    printCheck(c, o);
    return 0;
  }
  throw model::InputError("no field check " + std::to_string(o.id) + " in " + store.path() +
                          ": 'leafdig field list' shows them");
}

void printTip(const acq::TipCalibration& c, bool asJson) {
  if (asJson)
    std::cout << acq::tipCalibrationSummaryJson(c) << "\n";
  else
    std::cout << terminalText(acq::tipCalibrationSummaryText(c), true);
}

// `field tip`: the stylus pivoting in a divot, its tip fitted and stored (tip_calibration_run.hpp).
int runFieldTip(const FieldOptions& o) {
  if (o.operatorName.empty())
    throw model::InputError("--operator: a tip calibration is signed by who makes it; give a name");
  if (!o.simulate && o.digitizer.empty())
    throw model::InputError(
        "a tip calibration reads a digitizer: give --digitizer KIND:PORT (fastrak:/dev/ttyUSB0), or --simulate");
  if (!o.simulate && (!o.distortion.empty() || !o.simTip.empty()))
    throw model::InputError(std::string(o.distortion.empty() ? "--sim-tip" : "--distortion") +
                            " describes the simulated digitizer: it goes with --simulate");
  acq::TipCalibrationRequest request;
  request.db = stationDbPath(o.db);
  request.station = o.station;
  request.who = o.operatorName;
  request.toleranceMm = o.tipToleranceMm;
  request.digitizer = o.digitizer;
  request.simulated = o.simulate;
  if (o.simulate) {
    request.simulation = simulationOf(o.speed, o.seed, o.distortion, o.simTip);
    request.divotMm = vec3Option(o.divot, "--divot", 2000, "250,0,-50");
  }
  acq::TipCalibrationListener listener;
  listener.onPrompt = promptPrinter(o.json);
  listener.onRefused = [&](const std::string& words) {
    if (o.json)
      std::cout << json{{"event", "rejected"}, {"text", words}}.dump() << "\n" << std::flush;
    else
      std::cout << "    rejected: " << terminalText(words) << "\n" << std::flush;
  };
  listener.onStatus = [&](const dev::DeviceStatus& s) {
    // A lost or troubled digitizer is news; its start and its stop after the fit are not.
    if (s.state != dev::LinkState::Warning && s.state != dev::LinkState::Error) return;
    std::cerr << "leafdig: " << s.device << ": " << terminalText(s.message)
              << (s.remedy.empty() ? "" : " — " + terminalText(s.remedy)) << "\n";
  };
  acq::TipCalibrationRun run(std::move(request), listener);
  if (!o.json)
    std::cout << "leafdig field tip · " << terminalText(stationDbPath(o.db)) << "\n  keys (then Enter): q quit\n";
  StdinCommands input([&](const std::string& line) {
    if (line == "q" || line == "quit")
      run.stop();
    else
      std::cerr << "leafdig: '" << terminalText(line) << "'? type q (quit)\n";
  });
  const std::optional<acq::TipCalibration> result = runStoppable([&] { run.stop(); }, [&] { return run.run(); });
  input.stop();
  if (!result) {
    std::cerr << "leafdig: the tip calibration was stopped before a pivot gave a tip: nothing was stored\n";
    return interrupted() ? 130 : 1;
  }
  printTip(*result, o.json);
  return result->result.verdict == "pass" ? 0 : 3;
}

int runFieldTips(const FieldOptions& o) {
  const db::Store store(stationDbPath(o.db), true);
  return printCalibrations<acq::TipCalibration>(
      acq::tipCalibrations(store), o.json, acq::tipCalibrationSummaryJson,
      [](std::ostream& line, const acq::TipCalibration& c) {
        const auto& f = c.result.fit;
        line << c.id << "  " << c.createdUtc << "  " << c.device << "  tip (" << std::setprecision(1) << f.tipMm.x()
             << ", " << f.tipMm.y() << ", " << f.tipMm.z() << ") mm  RMS " << std::setprecision(2) << f.rmsMm << " mm  "
             << c.result.verdict << "  by " << c.operatorName;
      },
      "no tip calibration in " + terminalText(store.path()) + ": run 'leafdig field tip'");
}

// `field study`: the sample leaves and plant through a bent field, clean, uncorrected and
// corrected, against their truth (field_study.hpp); the report is docs/field-study.md.
acq::FieldStudyInput studyInput(const FieldOptions& o) {
  acq::FieldStudyInput in;
  if (o.distortion.empty()) {
    in.field = dev::sim::steelBench();
    in.fieldName =
        "the steel-bench preset (data/fields/steel-bench.field.json: a steel plate 250 mm below the "
        "transmitter)";
  } else {
    in.field = dev::sim::readFieldDistortion(o.distortion);
    in.fieldName = std::filesystem::path(o.distortion).filename().string();
  }
  in.jig = model::readJigFile(o.jig.empty() ? defaultJig() : o.jig);
  in.leafJigPose = poseOption(o.jigPose, "--jig-pose");
  in.plantJigPose = poseOption(o.plantJigPose, "--plant-jig-pose");
  const std::string data = dataDir();
  for (const char* leaf : {"lower-leaf-n10", "upper-curved-leaf-n14", "upper-small-leaf-n17"})
    in.leaves.emplace_back(leaf, model::readMarkersFile(data + "/samples/" + leaf + ".markers.json"));
  in.plant = std::make_pair(std::string("sample plant"),
                            model::readPlantMarkersFile(data + "/plants/sample.plant-markers.json"));
  in.noiseMm = o.noiseMm;
  in.repeats = o.repeats;
  in.seed = o.seed;
  in.jigCounts = o.counts;
  return in;
}

int runFieldStudy(const FieldOptions& o) {
  const acq::FieldStudyResult r = acq::runFieldStudy(studyInput(o));
  std::string command = "leafdig field study";
  if (!o.distortion.empty()) command += " --distortion " + std::filesystem::path(o.distortion).filename().string();
  if (o.noiseMm != 0.25) {
    std::ostringstream v;
    v << o.noiseMm;
    command += " --noise-mm " + v.str();
  }
  if (o.repeats != 10) command += " --repeats " + std::to_string(o.repeats);
  if (o.seed != 1) command += " --seed " + std::to_string(o.seed);
  if (!o.out.empty()) command += " -o " + std::filesystem::path(o.out).filename().string();
  const std::string report = acq::fieldStudyMarkdown(r, command);
  if (o.out.empty()) {
    std::cout << report;
  } else {
    model::writeFileAtomically(o.out, report);
    std::cerr << "leafdig: wrote " << o.out << "\n";
  }
  return 0;
}

}  // namespace

void addFieldCommands(CLI::App& app, CommandTable& table) {
  auto o = std::make_shared<FieldOptions>();
  CLI::App* field = app.add_subcommand("field",
                                       "The digitizer's magnetic field: simulate it, check it against a jig "
                                       "(docs/devices.md, \"The field\")");
  field->require_subcommand(1);
  CLI::App* fieldModel = field->add_subcommand(
      "model", "Write a leafdig.field-distortion/1 file from a physical model (steel-bench: a steel plate below)");
  fieldModel->add_option("model", o->fieldModel, "steel-bench")->required()->check(CLI::IsMember({"steel-bench"}));
  fieldModel->add_option("-o,--out", o->out, "The file to write")->required();
  fieldModel->add_option("--below-mm", o->belowMm, "The plate's depth under the transmitter, mm (default 250)")
      ->check(CLI::Range(50.0, 2000.0));
  fieldModel
      ->add_option("--strength", o->strength,
                   "The share of the coupling the plate takes back, 0–0.5 (default 0.08: a steel bench top)")
      ->check(CLI::Range(0.0, 0.5));

  CLI::App* check = field->add_subcommand(
      "check", "Digitize a jig's divots in the order prompted: the field's error, a correction, a verdict");
  check->add_option("--jig", o->jig, "A leafdig.jig/1 file (default: the shipped three-level.jig.json)");
  check->add_option("--tolerance-mm", o->toleranceMm, "The RMS error a field may have, mm (default 1.5)")
      ->check(CLI::Range(0.05, 100.0));
  check->add_option("--db", o->db, "SQLite file (default: the station's, under $XDG_DATA_HOME/leafdig)");
  check->add_option("--operator", o->operatorName, "Who checks");
  check->add_option("--station", o->station, "This station's id (default: the settings file's, else the host name)");
  check->add_option("--digitizer", o->digitizer, "KIND:PORT, e.g. fastrak:/dev/ttyUSB0 (patriot, liberty)");
  check->add_flag("--simulate", o->simulate, "The simulated FASTRAK and a virtual technician touching the jig");
  check->add_option("--distortion", o->distortion, kDistortionHelp);
  check->add_option("--sim-tip", o->simTip, kSimTipHelp);
  check->add_option("--tip-calibration", o->tipCalibration, kTipCalibrationHelp);
  check->add_option("--jig-pose", o->jigPose,
                    "Simulation: where the jig lies, x,y,z,yaw_deg in the transmitter's frame (default 200,-620,0,90: "
                    "under a leaf as the simulations lay it)");
  check->add_option("--speed", o->speed, "Simulation: time scale (default 4)")->check(CLI::Range(0.1, 50.0));
  check->add_option("--seed", o->seed, "Simulation: seed of the stylus noise")->check(seedText());
  check->add_option("--map", o->map, "Write the error map, an SVG figure, to this file");
  check->add_flag("--json", o->json, "JSON lines while digitizing; the result as one JSON object");

  CLI::App* list = field->add_subcommand("list", "The station file's field checks, oldest first");
  list->add_option("--db", o->db, "SQLite file (default: the station's)");
  list->add_flag("--json", o->json, "Machine-readable output");
  CLI::App* show = field->add_subcommand("show", "One field check: the field, the correction, the verdict");
  show->add_option("id", o->id, "The check's number (field list)")->required()->check(CLI::PositiveNumber);
  show->add_option("--db", o->db, "SQLite file (default: the station's)");
  show->add_option("--map", o->map, "Write its error map, an SVG figure, to this file");
  show->add_flag("--json", o->json, "Machine-readable output");

  CLI::App* study = field->add_subcommand(
      "study", "The sample leaves and plant through a bent field, uncorrected and corrected, against their truth");
  study->add_option("--distortion", o->distortion,
                    "A leafdig.field-distortion/1 file (default: the steel-bench preset)");
  study->add_option("--jig", o->jig, "A leafdig.jig/1 file (default: the shipped three-level.jig.json)");
  study->add_option("--jig-pose", o->jigPose,
                    "Where the jig lies under the leaves, x,y,z,yaw_deg (default 200,-620,0,90)");
  study->add_option("--plant-jig-pose", o->plantJigPose,
                    "Where the jig lies by the plant, x,y,z,yaw_deg (default 480,-100,-330,90)");
  study->add_option("--noise-mm", o->noiseMm, "The digitizer's noise, sigma per coordinate, mm (default 0.25)")
      ->check(CLI::Range(0.0, 10.0));
  study->add_option("--repeats", o->repeats, "Noise draws per number (default 10)")->check(CLI::Range(1, 1000));
  study->add_option("--seed", o->seed, "Seed of the noise")->check(seedText());
  study->add_option("--counts", o->counts, "Divot counts for the count table (default 6 8 12 16 and every one)")
      ->check(CLI::Range(4, 1000));
  study->add_option("-o,--out", o->out, "Write the report (Markdown) here instead of to the terminal");

  CLI::App* tip = field->add_subcommand(
      "tip", "Tip (pivot) calibration of the stylus: pivot it in one divot; its tip is fitted and kept for captures");
  tip->add_option("--tolerance-mm", o->tipToleranceMm, "The RMS residual a tip may leave, mm (default 1)")
      ->check(CLI::Range(0.01, 20.0));
  tip->add_option("--db", o->db, "SQLite file (default: the station's, under $XDG_DATA_HOME/leafdig)");
  tip->add_option("--operator", o->operatorName, "Who calibrates");
  tip->add_option("--station", o->station, "This station's id (default: the settings file's, else the host name)");
  tip->add_option("--digitizer", o->digitizer, "KIND:PORT, e.g. fastrak:/dev/ttyUSB0 (patriot, liberty)");
  tip->add_flag("--simulate", o->simulate, "The simulated FASTRAK and a virtual technician pivoting its stylus");
  tip->add_option("--sim-tip", o->simTip, kSimTipHelp);
  tip->add_option("--divot", o->divot,
                  "Simulation: where the divot is, x,y,z mm from the transmitter (default 250,0,-50)");
  tip->add_option("--distortion", o->distortion, kDistortionHelp);
  tip->add_option("--speed", o->speed, "Simulation: time scale (default 4)")->check(CLI::Range(0.1, 50.0));
  tip->add_option("--seed", o->seed, "Simulation: seed of the stylus noise")->check(seedText());
  tip->add_flag("--json", o->json, "JSON lines while pivoting; the result as one JSON object");
  CLI::App* tips = field->add_subcommand("tips", "The station file's tip calibrations, oldest first");
  tips->add_option("--db", o->db, "SQLite file (default: the station's)");
  tips->add_flag("--json", o->json, "Machine-readable output");

  table.add(fieldModel, [o] { return runFieldModel(*o); });
  table.add(
      tip, [o] { return runFieldTip(*o); }, "cannot calibrate the tip: ");
  table.add(tips, [o] { return runFieldTips(*o); });
  table.add(
      study, [o] { return runFieldStudy(*o); }, "cannot make the field study: ");
  table.add(
      check, [o] { return runFieldCheck(*o); }, "cannot check the field: ");
  table.add(list, [o] { return runFieldList(*o); });
  table.add(show, [o] { return runFieldShow(*o); });
}

SentinelOutcome takeSentinels(const SentinelAsk& a) {
  SentinelOutcome out;
  out.fieldCalibration = a.fieldCalibration;
  const bool throughCheck = !a.fieldCalibration.empty() && a.fieldCalibration != "none";
  const int count = a.count || throughCheck ? sentinelCount(a.count) : 0;
  if (count == 0) return out;
  const std::string db = stationDbPath(a.db);
  const std::optional<acq::ResolvedFieldCheck> resolved =
      acq::resolveFieldCheck(db::Store(db, true), a.fieldCalibration);
  if (!resolved)
    throw model::InputError(
        "--sentinels takes a field check's divots again: they go with --field-calibration ID|latest");
  const acq::FieldCalibration& c = resolved->check;
  acq::FieldCheckRequest request;
  request.db = db;
  request.station = a.station;
  request.who = a.who;
  request.jig = acq::sentinelJig(c.jig, count);
  request.toleranceMm = c.result.toleranceMm;
  request.digitizer = a.digitizer;
  request.simulated = a.simulate;
  if (a.simulate) {
    request.simulation = simulationOf(a.speed, a.seed, a.distortion, a.simTip);
    request.jigPose = poseOption(a.jigPose, "--jig-pose");
  }
  out.fieldCalibration = std::to_string(c.id);
  out.sentinels = driveDivots<acq::FieldSentinels>(std::move(request), a.json,
                                                   "leafdig: sentinel divots of field check " + std::to_string(c.id),
                                                   [&c](acq::FieldCheckRun& run) { return run.runSentinels(c); });
  if (!out.sentinels) {
    std::cerr << "leafdig: the sentinel divots were stopped before every one was taken: no session was made\n";
    out.exitCode = interrupted() ? 130 : 1;
    return out;
  }
  if (a.json)
    std::cout << json{{"event", "sentinels"},
                      {"text", out.sentinels->words()},
                      {"sentinels", acq::sentinelsJson(*out.sentinels)}}
                     .dump()
              << "\n"
              << std::flush;
  else
    std::cout << "  " << terminalText(out.sentinels->words()) << "\n" << std::flush;
  if (out.sentinels->moved()) {
    std::cerr << "leafdig: " << terminalText(out.sentinels->words()) << "; no session was made\n";
    out.exitCode = 3;
  }
  return out;
}

std::string fieldAccuracySection() {
  FieldOptions o;  // the study's defaults: the steel bench, the sample jig where the leaves lie
  acq::FieldStudyInput in = studyInput(o);
  in.plant.reset();  // the leaves alone
  in.jigCounts = {static_cast<int>(in.jig.points.size())};
  return acq::fieldStudyAccuracySection(acq::runFieldStudy(in), "leafdig field study");
}

}  // namespace leafdig::cli
