// The plant capture view (docs/plants.md, "The station's plant capture view"): a plant digitized
// where it stands, as the technician follows it — the prompt in large words, the plant's
// topology as a tree (landmarks, collar, node by node with its stem diameter and its leaf) with
// the current entity selected, the 3-D plant growing in the plant frame as points are
// committed, and beside it the leaf view while a full leaf is being taken.
//
// Threads: the capture (the session and its store, the simulated devices and the virtual
// technician) runs on a thread of its own; every committed decision hands a copy of the plant's
// engine to the GUI thread (the tree and the prompt, at once) and to a preview thread, which
// builds the plant's preview (acquisition/session/plant_preview.hpp) from the newest state only and
// hands it to the GUI thread. Each hand-over is a one-slot mailbox under a std::mutex, which the
// GUI thread looks into at 60 Hz (a timer, not a cross-thread Qt call): a burst of decisions is
// shown once, and nothing waits for the drawing.
#pragma once

#include <QTimer>
#include <QWidget>
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include "leafdig/acquisition/live/plant_loop.hpp"
#include "leafdig/acquisition/session/plant_preview.hpp"
#include "leafdig/acquisition/session/plant_session.hpp"
#include "leafdig/acquisition/sim/simulation.hpp"

class QComboBox;
class QLabel;
class QPushButton;
class QTreeWidget;
class QTreeWidgetItem;

namespace leafdig::station {

class PreviewWidget;

class PlantCaptureView : public QWidget {
  Q_OBJECT

 public:
  explicit PlantCaptureView(QWidget* parent = nullptr);
  ~PlantCaptureView() override;  // stop()

  // A new plant session in `db` (created as needed) that the virtual technician digitizes
  // through the simulated FASTRAK and caliper: the plant of `plantMarkersFile` (a
  // leafdig.plant-markers/1 file), or, with `resume`, the plant session of that id going on
  // where it stopped; taken by `protocol` (the built-in tobacco's by default). Returns what went
  // wrong in words (empty: started).
  QString startSimulated(const std::string& db, const std::string& plantMarkersFile,
                         const acquisition::SimulationOptions& simulation, const std::string& operatorName,
                         const std::string& station, std::int64_t resume = 0,
                         const model::PlantProtocol& protocol = model::defaultPlantProtocol());
  // A new plant session of `setup` (its plant, project, operator, station and the devices'
  // specs) taken by a person with the digitizer and caliper on those ports: the stylus and the
  // caliper as in the leaf capture, and the buttons for what a press cannot say (undo, end,
  // a node's leaf). Returns what went wrong in words (empty: started; nothing written when a
  // spec does not parse).
  QString startWithDevices(const std::string& db, const acquisition::PlantSessionSetup& setup);
  // The field check a new session's samples go through (a check's number, latest, or none/empty).
  void setFieldCalibration(std::string which) { fieldCalibration_ = std::move(which); }
  // Sentinel divots of that check taken just before (the Field tab), kept with it by the next
  // new session.
  void setSentinels(std::optional<acquisition::FieldSentinels> s) { sentinels_ = std::move(s); }
  // How old a field check may be before the field's line says so (the settings' hours).
  void setFieldCheckMaxAgeHours(double hours) { fieldCheckMaxAgeHours_ = hours; }
  // The field the plant is captured through (acquisition::fieldBanner), once a capture started.
  [[nodiscard]] QString fieldText() const;
  // Stops the capture (an unfinished session stays open: `leafdig plant capture --resume`
  // or the station goes on with it). Idempotent.
  void stop();
  // The operator's commands (devices only; the virtual technician decides its own): false when
  // no capture with devices is running.
  bool command(const acquisition::PlantCommand& c);
  // The foot pedal (the Accept key held down) as the stylus button; false without devices.
  bool setPedal(bool down);
  [[nodiscard]] bool pedal() const;
  // A retake in the words of `plant capture`'s standard input after "retake" ("landmark 2",
  // "collar", "point 4", "reading 4", "quick_point 5 2", "node 2 marker 1 3"): the words of what
  // is wrong, or empty when the command went to the capture (its decision comes as feedback).
  QString retake(const QString& words);
  // What the Retake… dialog offers first: the item selected in the tree, in those words.
  [[nodiscard]] QString retakeSuggestion() const;

  [[nodiscard]] std::int64_t sessionId() const { return session_; }
  [[nodiscard]] bool complete() const { return complete_; }
  [[nodiscard]] QString bannerText() const;
  [[nodiscard]] QString feedbackText() const;
  [[nodiscard]] QString summaryText() const;
  [[nodiscard]] QTreeWidget* tree() const { return tree_; }
  [[nodiscard]] QPushButton* reviewButton() const { return review_; }
  [[nodiscard]] QPushButton* undoButton() const { return undo_; }
  [[nodiscard]] QPushButton* endButton() const { return end_; }
  // Pause (the operator's: presses and readings change nothing until Resume) and back.
  [[nodiscard]] QPushButton* pauseButton() const { return pause_; }
  // The leaf of the node the prompt is at (or the next one): kind, state and type (the approved
  // leaves' types offered, any other typed), and Set.
  [[nodiscard]] QComboBox* leafKind() const { return leafKind_; }
  [[nodiscard]] QComboBox* leafState() const { return leafState_; }
  [[nodiscard]] QComboBox* leafType() const { return leafType_; }
  [[nodiscard]] QPushButton* setLeafButton() const { return setLeaf_; }
  [[nodiscard]] QPushButton* retakeButton() const { return retake_; }
  // The next node starts a branch from the stem's last node (shown for a protocol with branches).
  [[nodiscard]] QPushButton* branchButton() const { return branch_; }
  // The technician moved the transmitter: the landmarks are taken again and fitted (issue 29);
  // the tree's "Transmitter" line shows each position's residual.
  [[nodiscard]] QPushButton* moveButton() const { return move_; }
  [[nodiscard]] QString devicesText() const;
  [[nodiscard]] PreviewWidget* plantPreview() const { return plantPreview_; }
  [[nodiscard]] PreviewWidget* leafPreview() const { return leafPreview_; }
  // The plant as last shown (its engine state and its preview; empty before the first).
  [[nodiscard]] const std::optional<acquisition::PlantEngine>& engine() const { return engine_; }
  [[nodiscard]] const std::optional<acquisition::PlantPreview>& preview() const { return shown_; }
  // How many previews reached the view, and how many of them had the leaf view open.
  [[nodiscard]] int previewsShown() const { return previewsShown_; }
  [[nodiscard]] int leafPreviewsShown() const { return leafPreviewsShown_; }

 signals:
  void plantComplete();
  // After each committed decision (or a refusal): the prompt now, and whether it was refused.
  void stepChanged(const QString& prompt, bool rejected);
  // "Review this plant" was pressed (enabled once the plant is complete).
  void reviewRequested(std::int64_t session);

 private:
  struct State {
    acquisition::PlantEngine engine;
    QString feedback;
    bool rejected = false, complete = false;
    bool paused = false;
    QString pauseReason;
  };
  void applyState();    // GUI thread: the newest state to the tree and the banner
  void applyPreview();  // GUI thread: the newest preview to the views
  void fillTree(const acquisition::PlantEngine& engine);
  void previewLoop();
  void startThreads(const std::function<void()>& capture);
  void readSession(db::Store& store);  // session_'s library and engine, before the threads start
  // The capture thread's listener: the engine to the GUI thread and the preview thread.
  void committed(const acquisition::PlantFeedback& f, const acquisition::PlantCaptureSession& s);
  [[nodiscard]] int choiceNode() const;  // the node the leaf controls set

  QLabel *banner_, *feedback_, *summary_;
  QTreeWidget* tree_;
  QPushButton *review_, *undo_, *end_, *setLeaf_, *pause_, *retake_, *branch_, *move_;
  bool paused_ = false;  // as the last committed state said
  QComboBox *leafKind_, *leafState_, *leafType_;
  QLabel* devices_;
  QWidget* controls_;
  PreviewWidget *plantPreview_, *leafPreview_;
  QWidget* leafPane_;

  std::int64_t session_ = 0;
  std::string fieldCalibration_;                          // setFieldCalibration
  std::optional<acquisition::FieldSentinels> sentinels_;  // setSentinels
  double fieldCheckMaxAgeHours_ = acquisition::kFieldCheckMaxAgeHours;
  QLabel* field_ = nullptr;
  bool complete_ = false;
  std::optional<acquisition::PlantEngine> engine_;
  std::optional<acquisition::PlantPreview> shown_;
  int previewsShown_ = 0, leafPreviewsShown_ = 0;
  std::vector<model::LibraryLeaf> library_;  // read once at the start (the preview thread's)

  std::thread capture_, previewer_;
  std::atomic<bool> stop_{false};
  mutable std::mutex mutex_;  // guards everything below
  std::condition_variable wake_;
  std::optional<State> stateMailbox_;
  std::optional<acquisition::PlantEngine> previewWanted_;
  std::optional<acquisition::PlantPreview> previewMailbox_;
  bool quitPreview_ = false;
  QString failure_;                                  // the capture thread's error, if it stopped on one
  acquisition::PlantCaptureLoop* loop_ = nullptr;    // the devices' loop while it runs
  std::map<std::string, std::string> deviceStates_;  // device name -> its state in words
  bool devicesChanged_ = false;
  QTimer poll_;  // the GUI thread's look into the mailboxes while a capture runs
};

}  // namespace leafdig::station
