// The station's main window: a Capture tab (current-step banner, schematic leaf, step list,
// device chips, last-point readout, live 3D preview with the stylus cursor) over a capture
// loop on its own thread (the loop owns the session; snapshots and feedback arrive here
// queued on the UI thread), and a Review tab for curators. Sounds, configurable shortcuts
// (a USB foot pedal types one of them; the Accept key held down is the stylus button),
// settings, session set-up and export are reached from the toolbar.
#pragma once

#include <QLabel>
#include <QListWidget>
#include <QMainWindow>
#include <QTabWidget>
#include <QTimer>
#include <QToolButton>
#include <atomic>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <thread>

#include "capture/sounds.hpp"
#include "leafdig/acquisition/run/capture_run.hpp"
#include "leafdig/acquisition/session/plant_session.hpp"
#include "preview/leaf_schematic.hpp"
#include "preview/preview_widget.hpp"
#include "settings.hpp"

namespace leafdig::station {

class ReviewView;
class PlantView;
class FieldView;
class PlantCaptureView;

struct StationOptions {
  std::string db;
  bool simulate = false;  // simulated FASTRAK + Sylvac and a virtual technician
  double speed = 1.0;
  std::uint64_t seed = 1;
  std::string markers;  // the simulated leaf
  // A simulated plant: a reference receiver on the pot, which turns by potTurnDeg (issue 29).
  bool referenceReceiver = false;
  double potTurnDeg = 0;
  // The simulated digitizer's field bent as by metal nearby (--distortion FILE; issue 50).
  std::shared_ptr<const devices::sim::FieldDistortion> distortion;
  // A new capture's field check (--field-calibration: a check's number, latest or none; issue 50).
  std::string fieldCalibration;
  acquisition::SessionSetup setup;  // project, plant, …, devices (ignored when simulating)
  std::int64_t resume = 0;          // a session to continue; 0: a new one
  QString settingsFile;             // empty: defaultSettingsFile()
  bool audio = true;                // false: no sound cues loaded, the system beep only (--no-audio)
};

class StationWindow : public QMainWindow {
  Q_OBJECT

 public:
  explicit StationWindow(StationOptions options, QWidget* parent = nullptr);
  ~StationWindow() override;
  // Opens the store and the session, starts the devices and the capture thread. Returns
  // false (and shows why in the banner) when the store or the devices cannot be opened.
  bool start();
  // A plant digitized where it stands, in a "Plant capture" tab made current: the plant of
  // `plantMarkers` (a leafdig.plant-markers/1 file) taken by the virtual technician through the
  // simulated devices, by `protocol` (the set-up dialog's; tobacco's by default). False, with the
  // reason in the banner, when it cannot start.
  bool startPlantCapture(const std::string& plantMarkers,
                         const model::PlantProtocol& protocol = model::defaultPlantProtocol());
  // The same tab for a person with the devices of `setup` (its digitizer and caliper specs)
  // digitizing its plant; this station's id when the setup names none.
  bool startPlantCaptureWithDevices(acquisition::PlantSessionSetup setup);
  // Shows the plant set-up dialog and starts what was chosen. False: cancelled or refused.
  bool newPlantDialog();
  [[nodiscard]] PlantCaptureView* plantCapture() const { return plantCapture_; }
  // With --db postgresql://…: the lab server, for review only (capture always writes the
  // station's own file). Opens the Review tab on the server's sessions.
  void reviewLabServer();
  // Ends the capture; an unfinished session is paused with the reason (resumable).
  void stopCapture();
  // Shows the set-up dialog; starts a new session with what was chosen. False: cancelled.
  bool newSessionDialog();
  // Open sessions of this station that were interrupted (not complete, not abandoned).
  [[nodiscard]] std::vector<db::SessionInfo> interruptedSessions() const;
  // Asks whether to resume the newest interrupted session; sets options().resume if so.
  void offerResume();
  // Sends this station's sessions to the lab server of the settings and takes the curators'
  // decisions in (leafdig sync push + pull), on a thread of its own: capture goes on. The
  // outcome is in labStatusText() and the status bar. Does nothing while a sync runs, or
  // without a lab server in the settings.
  void syncWithLab();
  [[nodiscard]] QString labStatusText() const { return labStatus_; }
  [[nodiscard]] bool syncing() const { return syncing_; }

  [[nodiscard]] PreviewWidget* preview() const { return preview_; }
  [[nodiscard]] LeafSchematic* schematic() const { return schematic_; }
  [[nodiscard]] ReviewView* review() const { return review_; }
  [[nodiscard]] PlantView* plantView() const { return plant_; }
  // The Field tab (field/field_view.hpp): checks of the field, the stylus' tip, sentinel divots.
  // Its runs read the station's digitizer, or the simulated one in --distortion's field.
  [[nodiscard]] FieldView* fieldView() const { return fieldView_; }
  [[nodiscard]] QTabWidget* tabs() const { return tabs_; }
  [[nodiscard]] QString bannerText() const { return banner_->text(); }
  [[nodiscard]] QString feedbackText() const { return feedback_->text(); }
  // What the Capture tab says of the field (acquisition::fieldBanner), once a capture started.
  [[nodiscard]] QString fieldText() const { return field_->text(); }
  [[nodiscard]] QString chipText(acquisition::DeviceSet::Role role) const;
  // A device chip's text: name, state, rate and age; message and remedy wrapped into short
  // lines. Under a simulation running `simulationSpeed` times faster than real time, the rate
  // is in the simulation's clock (wall rate / speed), marked as simulated.
  [[nodiscard]] static QString chipLabel(const devices::DeviceStatus& status, acquisition::DeviceSet::Role role,
                                         double simulationSpeed = 1.0);
  [[nodiscard]] const std::optional<acquisition::Snapshot>& lastSnapshot() const { return last_; }
  [[nodiscard]] std::int64_t sessionId() const { return sessionId_; }
  [[nodiscard]] Sounds& sounds() { return *sounds_; }
  [[nodiscard]] const StationSettings& settings() const { return settings_; }
  [[nodiscard]] StationOptions& options() { return options_; }
  [[nodiscard]] acquisition::DeviceSet* devices() const { return run_ ? &run_->devices() : nullptr; }
  [[nodiscard]] acquisition::CaptureRun* run() const { return run_.get(); }
  void applySettings(const StationSettings& s);

  // What the UI does with the loop's output (public for the widget tests).
  void applySnapshot(const acquisition::Snapshot& s);
  void applyFeedback(const acquisition::Feedback& f);
  // Hands a snapshot to the window from any thread (the capture run's loop or its preview
  // worker). It waits in one slot under a std::mutex; the GUI thread takes the newest every
  // 5 ms (takeSnapshot, the mailbox timer) and applies it, so a burst of snapshots is applied
  // once and the hand-over is a lock both threads take, with no Qt call across threads (Qt's
  // queue lock is one ThreadSanitizer cannot see: the functor the capture thread allocated for
  // a queued call was reported when the GUI thread ran it).
  void postSnapshot(const acquisition::Snapshot& s);
  void takeSnapshot();
  // Polls device status and the stylus position (10 Hz / 30 Hz timers call these).
  void refreshDevices();
  void refreshCursor();
  void runAction(Action a);

 signals:
  void captureComplete();

 protected:
  bool eventFilter(QObject* watched, QEvent* event) override;

 private:
  [[nodiscard]] std::string dbPath() const;  // --db, or the station's default file
  [[nodiscard]] QWidget* buildCaptureTab();
  PlantCaptureView* plantCaptureTab();  // made on first use, made current
  // False, with the reason in the banner, when --db is the lab server (capture writes this
  // station's own file).
  bool capturesIntoStationFile();
  void updateFieldSource();
  // A new capture through a field check, with the settings' sentinel divots: they are taken in
  // the Field tab first and `then` runs when they held (false: none to take; `then` not called —
  // true: taken, or refused with the reason in the banner).
  bool sentinelsFirst(const std::function<void()>& then);
  void buildToolBar();
  void connectPreviewAndTimers();
  void command(acquisition::Command c);
  void fillSteps(const acquisition::Snapshot& s);
  void buildShortcuts();
  void toggleDevice(acquisition::DeviceSet::Role role);
  QToolButton* chip(acquisition::DeviceSet::Role role);

  StationOptions options_;
  StationSettings settings_;
  QTabWidget* tabs_ = nullptr;
  QLabel* banner_ = nullptr;
  QLabel* feedback_ = nullptr;
  QLabel* lastPoint_ = nullptr;
  QLabel* field_ = nullptr;
  QListWidget* steps_ = nullptr;
  LeafSchematic* schematic_ = nullptr;
  std::map<acquisition::DeviceSet::Role, QToolButton*> chips_;
  QWidget* chipRow_ = nullptr;
  PreviewWidget* preview_ = nullptr;
  ReviewView* review_ = nullptr;
  PlantView* plant_ = nullptr;
  PlantCaptureView* plantCapture_ = nullptr;
  FieldView* fieldView_ = nullptr;
  // Sentinels that held, for the capture they were taken for (taken by the next start).
  std::optional<acquisition::FieldSentinels> sentinels_;
  Sounds* sounds_ = nullptr;
  QTimer deviceTimer_, cursorTimer_, syncTimer_;
  // Takes the newest snapshot from the mailbox every 5 ms on the GUI thread: no call crosses
  // threads through Qt (ThreadSanitizer cannot see Qt's own queue lock; tests/tsan.supp).
  QTimer mailboxTimer_;
  QAction* syncAction_ = nullptr;
  std::thread syncThread_;  // the last sync with the lab server (joined before the next)
  std::atomic<bool> syncing_{false};
  QString labStatus_;
  std::vector<QObject*> shortcutObjects_;
  std::optional<acquisition::Item> retakeTarget_;

  std::unique_ptr<acquisition::CaptureRun> run_;
  std::int64_t sessionId_ = 0;
  std::optional<acquisition::Snapshot> last_;
  std::mutex mailboxMutex_;
  std::optional<acquisition::Snapshot> mailbox_;  // the newest snapshot not yet applied (under mailboxMutex_)
  std::map<acquisition::DeviceSet::Role, devices::LinkState> lastState_;
};

}  // namespace leafdig::station
