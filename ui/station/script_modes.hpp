#pragma once
// What the station does for scripts, tests and benchmarks besides being used: report the first
// frame and leave (the start-up benchmark), save screenshots of the capture, the review and the
// Plant view, and say when a leaf is complete. main.cpp parses the command line and calls these.
#include <QApplication>
#include <QString>
#include <chrono>

#include "station_window.hpp"

namespace leafdig::station {

// When the preview's first frame is on screen: print "first_frame steady_ns … main_ms …" and
// quit (the benchmark that started the process compares the clock with its own).
void quitAfterFirstFrame(QApplication& app, StationWindow& w, std::chrono::steady_clock::time_point mainEntered);

// The lab server's review, saved to `png` after it had time to load; exits 0 when saved.
void saveLabReviewScreenshot(QApplication& app, StationWindow& w, const QString& png);

// The window with the Plant view shown, saved to `png`; then the station quits.
void savePlantScreenshot(QApplication& app, StationWindow& w, const QString& png);

// When the capture completes: the window to `screenshot`, the session in Review to
// `reviewScreenshot` with its metrics printed, a line "complete session … preview_triangles …";
// then quit if asked. Empty paths save nothing.
struct CompletionReport {
  QString screenshot;
  QString reviewScreenshot;
  bool quit = false;
};
void reportWhenComplete(QApplication& app, StationWindow& w, const CompletionReport& report);

// A plant capture (--plant-markers): the window to `screenshot` when the prompt first starts
// with `when` (empty: when the plant is complete), a line "plant complete session … nodes …
// leaves … preview_triangles …" at the end; then quit if asked.
struct PlantCompletionReport {
  QString screenshot;
  QString when;
  bool quit = false;
};
void reportWhenPlantComplete(QApplication& app, StationWindow& w, const PlantCompletionReport& report);

// A check of the field in the Field tab (--check-field), started now: when it ends, the window to
// `report.screenshot`, a line "field check done map_arrows N" and the check's summary, each line
// after "field: " (or "field check stopped: …"), then quit if asked. False (the reason in the banner) when it cannot
// start.
bool checkFieldNow(QApplication& app, StationWindow& w, const CompletionReport& report);

}  // namespace leafdig::station
