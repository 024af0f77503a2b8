// leafdig-station: the Qt station. `leafdig-station --simulate` starts it with simulated
// devices and a virtual technician, for anyone to try.
#include <QApplication>
#include <QCommandLineParser>
#include <chrono>
#include <cmath>
#include <cstdio>

#include "leafdig/acquisition/run/capture_run.hpp"
#include "leafdig/db/lab.hpp"
#include "leafdig/version.hpp"
#include "plant/plant_view.hpp"
#include "script_modes.hpp"
#include "station_window.hpp"

int main(int argc, char** argv) {
  const auto mainEntered = std::chrono::steady_clock::now();
  QApplication app(argc, argv);
  QApplication::setApplicationName("leafdig-station");
  QApplication::setApplicationVersion(leafdig::kVersion);
  QCommandLineParser p;
  p.setApplicationDescription("leafdig station: guided leaf capture with a live 3D preview");
  p.addHelpOption();
  p.addVersionOption();
  const QCommandLineOption simulate("simulate", "Simulated FASTRAK and Sylvac with a virtual technician");
  const QCommandLineOption db("db", "SQLite file (default: the station's)", "FILE");
  const QCommandLineOption speed("speed", "Time scale of the simulation", "X", "1");
  const QCommandLineOption seed("seed", "Seed of the simulation", "N", "1");
  const QCommandLineOption markers("markers", "Leaf the virtual technician captures", "FILE");
  const QCommandLineOption digitizer("digitizer", "KIND:PORT, e.g. fastrak:/dev/ttyUSB0", "SPEC");
  const QCommandLineOption caliper("caliper", "KIND:PORT or hid:VID:PID", "SPEC");
  const QCommandLineOption resume("resume", "Continue this open session", "ID");
  const QCommandLineOption screenshot("screenshot", "When the leaf is complete, save the window here", "PNG");
  const QCommandLineOption reviewShot("review-screenshot",
                                      "When the leaf is complete, open it in Review and save that view here", "PNG");
  const QCommandLineOption quit("quit-when-complete", "Exit once the leaf is complete (scripts, tests)");
  const QCommandLineOption setupDialog("setup", "Show the session set-up dialog first (also when simulating)");
  const QCommandLineOption settingsFile("settings", "Settings file (default ~/.config/leafdig/station.ini)", "INI");
  const QCommandLineOption firstFrame(
      "quit-after-first-frame",
      "Print when the first frame of the preview is on screen, then exit (start-up benchmark)");
  const QCommandLineOption plantPlan("plant", "Open this plant plan (leafdig.plant/1) in the Plant view", "PLAN");
  const QCommandLineOption plantSession(
      "plant-session", "Open this plant session of --db (a plant captured where it stands) in the Plant view", "ID");
  const QCommandLineOption plantShot(
      "plant-screenshot", "With --plant or --plant-session: save the window once the plant is shown, then exit", "PNG");
  const QCommandLineOption plantMarkers(
      "plant-markers",
      "With --simulate: a plant capture instead of a leaf; the virtual technician digitizes this plant "
      "(leafdig.plant-markers/1) where it stands",
      "FILE");
  const QCommandLineOption plantProtocol(
      "plant-protocol",
      "With --plant-markers or --capture-plant: take the plant by this protocol (leafdig.plant-protocol/1; "
      "default: the built-in tobacco's)",
      "FILE");
  const QCommandLineOption referenceReceiver(
      "reference-receiver",
      "With --simulate --plant-markers: a reference receiver on the pot (receiver 2); every stylus sample is taken "
      "in its frame");
  const QCommandLineOption potTurn(
      "pot-turn", "With --reference-receiver: the simulated pot turns by DEG degrees as the plant is taken", "DEG",
      "0");
  const QCommandLineOption distortion(
      "distortion",
      "With --simulate: the digitizer's field bent as by metal nearby, from a leafdig.field-distortion/1 file "
      "(docs/devices.md, \"The field\")",
      "FILE");
  const QCommandLineOption fieldCalibration(
      "field-calibration",
      "The field check whose correction every stylus sample of a new capture goes through: a check's number "
      "(leafdig field list), latest, or none (default; docs/devices.md, \"Checking the field\")",
      "ID");
  const QCommandLineOption capturePlant(
      "capture-plant",
      "Digitize this plant (its id) where it stands with --digitizer and --caliper, in the plant capture view", "ID");
  const QCommandLineOption screenshotWhen(
      "screenshot-when",
      "With --plant-markers and --screenshot: save the window the first time the prompt starts with this text "
      "(e.g. \"Node 2 · leaf\"), not at the end",
      "PROMPT");
  const QCommandLineOption noAudio("no-audio",
                                   "No sound cues (nothing loaded through Qt Multimedia); the system beep still marks "
                                   "a rejection and a device error");
  const QCommandLineOption checkField(
      "check-field",
      "Check the field in the Field tab with the sample jig (with --simulate: the simulated FASTRAK touching it); "
      "with --screenshot, the window once the check is done; with --quit-when-complete, leave then");
  const QCommandLineOption station(
      "station",
      "This station's id, stored with every session (default: [station] id= in the settings, or the host name)", "ID");
  p.addOptions({simulate,       db,           speed,      seed,          markers,      digitizer,         caliper,
                resume,         screenshot,   reviewShot, quit,          setupDialog,  settingsFile,      firstFrame,
                plantPlan,      plantSession, plantShot,  plantMarkers,  capturePlant, referenceReceiver, potTurn,
                screenshotWhen, noAudio,      station,    plantProtocol, distortion,   fieldCalibration,  checkField});
  p.process(app);

  leafdig::station::StationOptions o;
  o.simulate = p.isSet(simulate);
  o.db = p.value(db).toStdString();
  o.speed = p.value(speed).toDouble();
  o.seed = p.value(seed).toULongLong();
  o.markers = p.value(markers).toStdString();
  o.referenceReceiver = p.isSet(referenceReceiver);
  o.potTurnDeg = p.value(potTurn).toDouble();
  o.fieldCalibration = p.value(fieldCalibration).toStdString();
  try {
    // The station's simulation is the one with --simulate; a turn needs its reference receiver.
    leafdig::acquisition::checkPotTurn(o.potTurnDeg, true, o.referenceReceiver, "pot");
    if (p.isSet(distortion)) {
      if (!o.simulate)
        throw std::invalid_argument("--distortion bends the simulated digitizer's field: add --simulate");
      o.distortion = std::make_shared<const leafdig::devices::sim::FieldDistortion>(
          leafdig::devices::sim::readFieldDistortion(p.value(distortion).toStdString()));
    }
  } catch (const std::invalid_argument& e) {
    std::fprintf(stderr, "leafdig-station: %s\n", e.what());
    return 2;
  }
  o.setup.project = "default";
  o.setup.plant = "plant-1";
  o.setup.operatorName = qEnvironmentVariable("USER", "technician").toStdString();
  o.setup.digitizer = p.value(digitizer).toStdString();
  o.setup.caliper = p.value(caliper).toStdString();
  o.resume = p.value(resume).toLongLong();
  o.settingsFile = p.value(settingsFile);
  o.audio = !p.isSet(noAudio);
  o.setup.station = p.value(station).toStdString();
  if (p.isSet(station)) {
    try {
      leafdig::db::checkStationId(o.setup.station);
    } catch (const leafdig::db::StoreError& e) {
      std::fprintf(stderr, "leafdig-station: %s\n  %s\n", e.what(), e.remedy().c_str());
      return 2;
    }
  }
  if (!(o.speed >= leafdig::acquisition::kMinSimulationSpeed && o.speed <= leafdig::acquisition::kMaxSimulationSpeed)) {
    std::fprintf(stderr, "leafdig-station: --speed must be between 0.1 and 50\n");
    return 2;
  }
  {
    QStringList problems;
    const auto settings = leafdig::station::StationSettings::load(
        o.settingsFile.isEmpty() ? leafdig::station::defaultSettingsFile() : o.settingsFile, &problems);
    for (const auto& problem : problems) std::fprintf(stderr, "leafdig-station: settings: %s\n", qPrintable(problem));
    leafdig::station::applyTheme(app, settings);
  }
  leafdig::station::StationWindow w(o);
  // The window is usable once its preview is on screen (the start-up benchmark).
  if (p.isSet(firstFrame)) leafdig::station::quitAfterFirstFrame(app, w, mainEntered);
  w.show();
  const bool interactive = !p.isSet(quit) && !p.isSet(firstFrame);
  if (leafdig::db::isServerUrl(o.db)) {
    // The lab server: review (and export, plants) only.
    w.reviewLabServer();
    if (p.isSet(reviewShot)) leafdig::station::saveLabReviewScreenshot(app, w, p.value(reviewShot));
    return app.exec();
  }
  if (p.isSet(capturePlant) || p.isSet(plantMarkers)) {
    // A plant digitized where it stands: by a person with the devices given (--capture-plant),
    // or by the virtual technician through the simulated ones (--simulate --plant-markers).
    const bool devices = p.isSet(capturePlant);
    if (devices && (o.simulate || o.setup.digitizer.empty() || o.setup.caliper.empty())) {
      std::fprintf(stderr,
                   "leafdig-station: --capture-plant ID needs --digitizer and --caliper (to try it: --simulate "
                   "--plant-markers FILE)\n");
      return 2;
    }
    if (!devices && !o.simulate) {
      std::fprintf(stderr,
                   "leafdig-station: --plant-markers needs --simulate (with devices: --capture-plant ID "
                   "--digitizer … --caliper …)\n");
      return 2;
    }
    leafdig::acquisition::PlantSessionSetup setup;
    setup.plant = p.value(capturePlant).toStdString();
    setup.project = o.setup.project;
    setup.operatorName = o.setup.operatorName;
    setup.digitizer = o.setup.digitizer;
    setup.caliper = o.setup.caliper;
    if (p.isSet(plantProtocol)) {
      try {
        setup.protocol = leafdig::model::readPlantProtocolFile(p.value(plantProtocol).toStdString());
      } catch (const std::exception& e) {
        std::fprintf(stderr, "leafdig-station: %s\n", e.what());
        return 2;
      }
    }
    const bool started = devices ? w.startPlantCaptureWithDevices(setup)
                                 : w.startPlantCapture(p.value(plantMarkers).toStdString(), setup.protocol);
    if (!started) {
      std::fprintf(stderr, "leafdig-station: %s\n", qPrintable(w.bannerText()));
      return 2;
    }
    leafdig::station::reportWhenPlantComplete(app, w, {p.value(screenshot), p.value(screenshotWhen), p.isSet(quit)});
    return QApplication::exec();
  }
  if (p.isSet(checkField)) {
    // The Field tab alone: a check of the field, no capture.
    if (!leafdig::station::checkFieldNow(app, w, {p.value(screenshot), QString(), p.isSet(quit)})) {
      std::fprintf(stderr, "leafdig-station: %s\n", qPrintable(w.bannerText()));
      return 2;
    }
    return QApplication::exec();
  }
  if (interactive && o.resume == 0 && !p.isSet(plantShot)) w.offerResume();
  // Without devices given (and nothing to resume), the set-up dialog asks for them.
  const bool needSetup = p.isSet(setupDialog) || (!o.simulate && w.options().resume == 0 &&
                                                  (o.setup.digitizer.empty() || o.setup.caliper.empty()));
  if (p.isSet(plantShot) && !o.simulate && o.setup.digitizer.empty()) {
    // A picture of the Plant view alone: no capture to start, no devices to ask for.
  } else if (needSetup) {
    if (!interactive) {
      std::fprintf(stderr, "leafdig-station: give --digitizer and --caliper, or --simulate to try it\n");
      return 2;
    }
    if (!w.newSessionDialog()) {
      if (w.sessionId() == 0 && w.bannerText().startsWith("Cannot"))
        std::fprintf(stderr, "leafdig-station: %s\n", qPrintable(w.bannerText()));
    }
  } else if (!w.start()) {
    std::fprintf(stderr, "leafdig-station: %s\n", w.bannerText().toStdString().c_str());
    if (!interactive) return 1;
  }
  if (p.isSet(plantPlan) || p.isSet(plantSession)) {
    w.tabs()->setCurrentWidget(w.plantView());
    const QString error = p.isSet(plantSession) ? w.plantView()->openCapturedPlant(p.value(plantSession).toLongLong())
                                                : w.plantView()->openPlan(p.value(plantPlan));
    if (!error.isEmpty()) {
      std::fprintf(stderr, "leafdig-station: %s\n", qPrintable(error));
      if (p.isSet(plantShot)) return 2;
    }
    if (p.isSet(plantShot)) leafdig::station::savePlantScreenshot(app, w, p.value(plantShot));
  }
  leafdig::station::reportWhenComplete(app, w, {p.value(screenshot), p.value(reviewShot), p.isSet(quit)});
  return QApplication::exec();
}
