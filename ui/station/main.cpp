// leafdig-station: the Qt station. `leafdig-station --simulate` starts it with simulated
// devices and a virtual technician, for anyone to try.
#include <QApplication>
#include <QCommandLineParser>
#include <QImage>
#include <QScreen>
#include <QTimer>
#include <chrono>
#include <cstdio>

#include "leafdig/db/lab.hpp"
#include "leafdig/version.hpp"
#include "plant_view.hpp"
#include "review_view.hpp"
#include "station_window.hpp"

namespace {

// Pixels of the preview that are not the background: the preview really drew geometry.
int drawnPixels(const QImage& image) {
  const QRgb background = image.pixel(0, 0);
  int n = 0;
  for (int y = 0; y < image.height(); y += 2)
    for (int x = 0; x < image.width(); x += 2) n += image.pixel(x, y) != background;
  return n;
}

}  // namespace

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
  const QCommandLineOption plantShot("plant-screenshot",
                                     "With --plant: save the window once the plant is shown, then exit", "PNG");
  const QCommandLineOption noAudio("no-audio",
                                   "No sound cues (nothing loaded through Qt Multimedia); the system beep still marks "
                                   "a rejection and a device error");
  const QCommandLineOption station(
      "station",
      "This station's id, stored with every session (default: [station] id= in the settings, or the host name)", "ID");
  p.addOptions({simulate, db, speed, seed, markers, digitizer, caliper, resume, screenshot, reviewShot, quit,
                setupDialog, settingsFile, firstFrame, plantPlan, plantShot, noAudio, station});
  p.process(app);

  leafdig::station::StationOptions o;
  o.simulate = p.isSet(simulate);
  o.db = p.value(db).toStdString();
  o.speed = p.value(speed).toDouble();
  o.seed = p.value(seed).toULongLong();
  o.markers = p.value(markers).toStdString();
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
  if (!(o.speed > 0 && o.speed <= 50)) {
    std::fprintf(stderr, "leafdig-station: --speed must be in (0, 50]\n");
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
  if (p.isSet(firstFrame)) {
    // The window is usable once its preview is on screen: report the steady clock (the
    // benchmark that started this process compares it with its own) and leave.
    QObject::connect(
        w.preview(), &leafdig::station::PreviewWidget::frameSwapped, &app,
        [&] {
          const auto now = std::chrono::steady_clock::now();
          std::printf("first_frame steady_ns %lld main_ms %.1f\n",
                      static_cast<long long>(
                          std::chrono::duration_cast<std::chrono::nanoseconds>(now.time_since_epoch()).count()),
                      std::chrono::duration<double, std::milli>(now - mainEntered).count());
          std::fflush(stdout);
          // Leave from the event loop, not from inside the frame's own paint.
          QTimer::singleShot(0, &app, [&] {
            w.stopCapture();
            app.quit();
          });
        },
        Qt::SingleShotConnection);
  }
  w.show();
  const bool interactive = !p.isSet(quit) && !p.isSet(firstFrame);
  if (leafdig::db::isServerUrl(o.db)) {
    // The lab server: review (and export, plants) only.
    w.reviewLabServer();
    if (p.isSet(reviewShot)) {
      QTimer::singleShot(1500, &app, [&] {
        const QImage shot = w.grab().toImage();
        const bool saved = shot.save(p.value(reviewShot));
        std::printf("review screenshot %s\n", saved ? "saved" : "NOT saved");
        app.exit(saved ? 0 : 1);
      });
    }
    return app.exec();
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
  if (p.isSet(plantPlan)) {
    w.tabs()->setCurrentWidget(w.plantView());
    const QString error = w.plantView()->openPlan(p.value(plantPlan));
    if (!error.isEmpty()) {
      std::fprintf(stderr, "leafdig-station: %s\n", qPrintable(error));
      if (p.isSet(plantShot)) return 2;
    }
    if (p.isSet(plantShot)) {
      QTimer::singleShot(1500, &app, [&] {
        w.plantView()->preview()->redraw();
        leafdig::station::PreviewWidget::grabWindow(&w).save(p.value(plantShot));
        std::printf("plant shown: %s\n", qPrintable(w.plantView()->summaryText()));
        std::fflush(stdout);
        w.stopCapture();
        app.quit();
      });
    }
  }
  const QString shot = p.value(screenshot);
  QObject::connect(&w, &leafdig::station::StationWindow::captureComplete, &app, [&] {
    // Let the last snapshot reach the screen, then report and (optionally) leave.
    QTimer::singleShot(400, &app, [&] {
      w.preview()->redraw();
      const QImage frame = w.preview()->grabFramebuffer();
      const int pixels = drawnPixels(frame);
      if (!shot.isEmpty()) leafdig::station::PreviewWidget::grabWindow(&w).save(shot);
      if (p.isSet(reviewShot)) {
        w.tabs()->setCurrentIndex(1);
        w.review()->refreshSessions();
        (void)w.review()->openSession(w.sessionId());
        QApplication::processEvents();
        leafdig::station::PreviewWidget::grabWindow(&w).save(p.value(reviewShot));
        // What the curator reads beside the screenshot, for the end-to-end test to check.
        for (const QString& line : w.review()->metricsText().split('\n'))
          std::printf("review metrics: %s\n", qPrintable(line));
      }
      std::printf("complete session %lld preview_triangles %zu preview_pixels %d frame_ms %.2f\n",
                  static_cast<long long>(w.sessionId()), w.preview()->trianglesDrawn(), pixels,
                  w.preview()->lastFrameMs());
      std::fflush(stdout);
      if (p.isSet(quit)) {
        w.stopCapture();
        app.quit();
      }
    });
  });
  return QApplication::exec();
}
