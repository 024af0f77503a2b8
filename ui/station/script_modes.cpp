#include "script_modes.hpp"

#include <QImage>
#include <QTimer>
#include <cstdio>
#include <memory>

#include "field/field_view.hpp"
#include "plant/plant_capture_view.hpp"
#include "plant/plant_view.hpp"
#include "review/review_view.hpp"

namespace leafdig::station {

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

void quitAfterFirstFrame(QApplication& app, StationWindow& w, std::chrono::steady_clock::time_point mainEntered) {
  QObject::connect(
      w.preview(), &PreviewWidget::frameSwapped, &app,
      [&app, &w, mainEntered] {
        const auto now = std::chrono::steady_clock::now();
        std::printf("first_frame steady_ns %lld main_ms %.1f\n",
                    static_cast<long long>(
                        std::chrono::duration_cast<std::chrono::nanoseconds>(now.time_since_epoch()).count()),
                    std::chrono::duration<double, std::milli>(now - mainEntered).count());
        std::fflush(stdout);
        // Leave from the event loop, not from inside the frame's own paint.
        QTimer::singleShot(0, &app, [&app, &w] {
          w.stopCapture();
          app.quit();
        });
      },
      Qt::SingleShotConnection);
}

void saveLabReviewScreenshot(QApplication& app, StationWindow& w, const QString& png) {
  QTimer::singleShot(1500, &app, [&app, &w, png] {
    const QImage shot = w.grab().toImage();
    const bool saved = shot.save(png);
    std::printf("review screenshot %s\n", saved ? "saved" : "NOT saved");
    app.exit(saved ? 0 : 1);
  });
}

void savePlantScreenshot(QApplication& app, StationWindow& w, const QString& png) {
  QTimer::singleShot(1500, &app, [&app, &w, png] {
    w.plantView()->preview()->redraw();
    PreviewWidget::grabWindow(&w).save(png);
    std::printf("plant shown: %s\n", qPrintable(w.plantView()->summaryText()));
    std::fflush(stdout);
    w.stopCapture();
    app.quit();
  });
}

void reportWhenComplete(QApplication& app, StationWindow& w, const CompletionReport& report) {
  QObject::connect(&w, &StationWindow::captureComplete, &app, [&app, &w, report] {
    // Let the last snapshot reach the screen, then report and (optionally) leave.
    QTimer::singleShot(400, &app, [&app, &w, report] {
      w.preview()->redraw();
      const QImage frame = w.preview()->grabFramebuffer();
      const int pixels = drawnPixels(frame);
      if (!report.screenshot.isEmpty()) PreviewWidget::grabWindow(&w).save(report.screenshot);
      if (!report.reviewScreenshot.isEmpty()) {
        w.tabs()->setCurrentIndex(1);
        w.review()->refreshSessions();
        (void)w.review()->openSession(w.sessionId());
        QApplication::processEvents();
        PreviewWidget::grabWindow(&w).save(report.reviewScreenshot);
        // What the curator reads beside the screenshot, for the end-to-end test to check.
        for (const QString& line : w.review()->metricsText().split('\n'))
          std::printf("review metrics: %s\n", qPrintable(line));
      }
      std::printf("complete session %lld preview_triangles %zu preview_pixels %d frame_ms %.2f\n",
                  static_cast<long long>(w.sessionId()), w.preview()->trianglesDrawn(), pixels,
                  w.preview()->lastFrameMs());
      std::fflush(stdout);
      if (report.quit) {
        w.stopCapture();
        app.quit();
      }
    });
  });
}

void reportWhenPlantComplete(QApplication& app, StationWindow& w, const PlantCompletionReport& report) {
  PlantCaptureView* view = w.plantCapture();
  if (!report.screenshot.isEmpty() && !report.when.isEmpty()) {
    // The first time the prompt gets there: let the preview catch up, then save.
    auto saved = std::make_shared<bool>(false);
    QObject::connect(view, &PlantCaptureView::stepChanged, &app, [&w, report, saved](const QString& prompt, bool) {
      if (*saved || !prompt.startsWith(report.when)) return;
      *saved = true;
      QTimer::singleShot(600, &w, [&w, report] {
        w.plantCapture()->plantPreview()->redraw();
        const bool ok = PreviewWidget::grabWindow(&w).save(report.screenshot);
        std::printf("plant screenshot at \"%s\" %s\n", qPrintable(report.when), ok ? "saved" : "NOT saved");
        std::fflush(stdout);
      });
    });
  }
  QObject::connect(view, &PlantCaptureView::plantComplete, &app, [&app, &w, report] {
    QTimer::singleShot(600, &app, [&app, &w, report] {
      PlantCaptureView* v = w.plantCapture();
      v->plantPreview()->redraw();
      if (!report.screenshot.isEmpty() && report.when.isEmpty()) PreviewWidget::grabWindow(&w).save(report.screenshot);
      const auto& p = v->preview();
      std::printf("plant complete session %lld nodes %d leaves %d preview_triangles %zu\n",
                  static_cast<long long>(v->sessionId()), v->engine() ? v->engine()->nodes() : 0, p ? p->leaves : 0,
                  v->plantPreview()->trianglesDrawn());
      std::fflush(stdout);
      if (report.quit) {
        w.stopCapture();
        app.quit();
      }
    });
  });
}

bool checkFieldNow(QApplication& app, StationWindow& w, const CompletionReport& report) {
  FieldView* field = w.fieldView();
  w.tabs()->setCurrentWidget(field);
  QObject::connect(field, &FieldView::finished, &app, [&app, &w, field, report] {
    QTimer::singleShot(300, &app, [&app, &w, field, report] {
      if (!report.screenshot.isEmpty()) w.grab().save(report.screenshot);
      if (const auto& map = field->map()->map()) {
        std::size_t arrows = 0;
        for (const auto& panel : map->panels) arrows += panel.arrows.size();
        std::printf("field check done map_arrows %zu\n", arrows);
        for (const QString& line : field->resultText().split('\n')) std::printf("field: %s\n", qPrintable(line));
      } else {
        std::printf("field check stopped: %s\n", qPrintable(field->resultText()));
      }
      std::fflush(stdout);
      if (report.quit) app.quit();
    });
  });
  const QString error = field->startCheck();
  if (!error.isEmpty()) return false;
  return true;
}

}  // namespace leafdig::station
