// The station's capture window: the current-step banner, the step list, device chips and
// the live 3D preview, over a capture loop that runs on its own thread (the loop owns the
// session; snapshots and feedback arrive here queued on the UI thread).
#pragma once

#include <QLabel>
#include <QListWidget>
#include <QMainWindow>
#include <atomic>
#include <map>
#include <memory>
#include <optional>
#include <thread>

#include "leafdig/acquisition/capture_loop.hpp"
#include "leafdig/acquisition/simulation.hpp"
#include "preview_widget.hpp"

namespace leafdig::station {

struct StationOptions {
  std::string db;
  bool simulate = false;
  double speed = 1.0;
  std::uint64_t seed = 1;
  std::string markers;  // the simulated leaf
  std::string project = "default", plant = "plant-1", operatorName = "technician";
  int leafPosition = 1;
  std::string digitizer, caliper;
  std::int64_t resume = 0;  // a session to continue; 0: a new one
};

class StationWindow : public QMainWindow {
  Q_OBJECT

 public:
  explicit StationWindow(StationOptions options, QWidget* parent = nullptr);
  ~StationWindow() override;
  // Opens the store and the session, starts the devices and the capture thread. Returns
  // false (and shows why in the banner) when the store or the devices cannot be opened.
  bool start();
  void stopCapture();

  [[nodiscard]] PreviewWidget* preview() const { return preview_; }
  [[nodiscard]] QString bannerText() const { return banner_->text(); }
  [[nodiscard]] const std::optional<acquisition::Snapshot>& lastSnapshot() const { return last_; }
  [[nodiscard]] std::int64_t sessionId() const { return sessionId_; }

  // What the UI does with the loop's output (public for the widget tests).
  void applySnapshot(const acquisition::Snapshot& s);
  void applyFeedback(const acquisition::Feedback& f);

 signals:
  void captureComplete();

 private:
  void command(acquisition::Command::Kind kind);
  void fillSteps(const acquisition::Snapshot& s);

  StationOptions options_;
  QLabel* banner_ = nullptr;
  QLabel* feedback_ = nullptr;
  QListWidget* steps_ = nullptr;
  std::map<std::string, QLabel*> chips_;
  QWidget* chipRow_ = nullptr;
  PreviewWidget* preview_ = nullptr;

  std::unique_ptr<db::Store> store_;
  std::unique_ptr<acquisition::CaptureSession> session_;
  std::unique_ptr<acquisition::CaptureLoop> loop_;
  std::unique_ptr<acquisition::SimulatedRig> rig_;
  std::unique_ptr<acquisition::VirtualOperator> operator_;
  std::unique_ptr<acquisition::DeviceSet> devices_;
  std::thread captureThread_;
  std::int64_t sessionId_ = 0;
  std::optional<acquisition::Snapshot> last_;
};

}  // namespace leafdig::station
