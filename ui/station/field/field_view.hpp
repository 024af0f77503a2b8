// The station's Field tab (issue 50; docs/devices.md, "The field"): the technician checks the
// field with the jig — each divot prompted in large words, every press answered, the last taken
// back with Undo — and sees the check's verdict, its numbers and the error map the CLI's --map
// draws (model::fieldErrorMapLayout); calibrates the stylus' tip by pivoting it in a divot; and,
// before a capture through a check, takes its sentinel divots again (acquisition/field/sentinels).
// What it does is acquisition's FieldCheckRun and TipCalibrationRun, as `leafdig field check` and
// `leafdig field tip` do it: stored in the station's file the same way.
//
// Threads: a run (its store, the digitizer or the simulated one with its virtual technician) goes
// on a thread of its own; its prompts, decisions and result wait in a mailbox under a std::mutex
// that the GUI thread empties at 30 Hz (a timer, no cross-thread Qt call).
#pragma once

#include <QTimer>
#include <QWidget>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "leafdig/acquisition/field/sentinels.hpp"
#include "leafdig/acquisition/field/tip_calibration.hpp"
#include "leafdig/acquisition/run/field_check_run.hpp"
#include "leafdig/acquisition/sim/simulation.hpp"
#include "leafdig/model/field/correction.hpp"

class QDoubleSpinBox;
class QLabel;
class QLineEdit;
class QListWidget;
class QPushButton;

namespace leafdig::station {

// The error map painted: the same figure as the SVG of `leafdig field check --map`.
class FieldMapWidget : public QWidget {
  Q_OBJECT

 public:
  explicit FieldMapWidget(QWidget* parent = nullptr);
  void setMap(std::optional<model::FieldMapLayout> map);
  [[nodiscard]] const std::optional<model::FieldMapLayout>& map() const { return map_; }

 protected:
  void paintEvent(QPaintEvent* event) override;

 private:
  std::optional<model::FieldMapLayout> map_;
};

// Where the Field tab's runs read the stylus: the simulated FASTRAK (in its bent field, the jig at
// `jigPose`) or the digitizer on its port; signed by `operatorName` into `db`.
struct FieldSource {
  std::string db, station, operatorName = "technician";
  bool simulate = false;
  acquisition::SimulationOptions simulation;  // speed, seed, distortion
  std::string jigPose = "200,-620,0,90";      // a simulation: x,y,z,yaw_deg
  std::string digitizer;                      // "fastrak:/dev/ttyUSB0" with devices
};

class FieldView : public QWidget {
  Q_OBJECT

 public:
  explicit FieldView(QWidget* parent = nullptr);
  ~FieldView() override;  // stop()
  void setSource(FieldSource source) { source_ = std::move(source); }
  [[nodiscard]] const FieldSource& source() const { return source_; }

  // A check of the field with the jig file in the tab's box (empty: the shipped sample) against the
  // tab's tolerance. Returns what went wrong in words (empty: started).
  QString startCheck();
  // A tip calibration of the stylus (the simulated stylus' sensor `simTipMm` from its tip).
  QString startTipCalibration(const devices::Vec3& simTipMm = {0, 0, 0});
  // Sentinels: `count` divots of `check` taken again; `done` is called on the GUI thread with
  // them (held or moved), or nothing when stopped.
  QString startSentinels(const acquisition::FieldCalibration& check, int count,
                         std::function<void(std::optional<acquisition::FieldSentinels>)> done);
  void undo();
  void stop();  // the run ends with nothing stored; idempotent
  [[nodiscard]] bool running() const { return worker_.joinable() && !finished_; }

  [[nodiscard]] QString promptText() const;
  [[nodiscard]] QString resultText() const;
  [[nodiscard]] QStringList decisions() const;
  [[nodiscard]] FieldMapWidget* map() const { return map_; }
  [[nodiscard]] QLineEdit* jigFile() const { return jig_; }
  [[nodiscard]] QDoubleSpinBox* tolerance() const { return tolerance_; }
  [[nodiscard]] QPushButton* checkButton() const { return check_; }

 signals:
  void finished();  // a run ended (stored, stopped or refused)

 private:
  struct Mail {
    std::vector<QString> prompts, decisions;
    std::optional<acquisition::FieldCalibration> check;
    std::optional<acquisition::TipCalibration> tip;
    std::optional<acquisition::FieldSentinels> sentinels;
    std::optional<QString> failure;
    bool ended = false;
  };
  void launch(const QString& what, std::function<void()> body);
  // A run of divots (a check, sentinels) through the tab's source: the request, and on the worker
  // its prompts and decisions posted, Stop and Undo wired to it, `go` run and its result posted.
  [[nodiscard]] acquisition::FieldCheckRequest divotRequest(model::Jig jig, double toleranceMm) const;
  void launchDivots(const QString& what, acquisition::FieldCheckRequest r,
                    std::function<void(acquisition::FieldCheckRun&, Mail&)> go);
  void drain();
  void showCheck(const acquisition::FieldCalibration& c);
  void post(const std::function<void(Mail&)>& write);

  FieldSource source_;
  QLineEdit* jig_ = nullptr;
  QDoubleSpinBox* tolerance_ = nullptr;
  QPushButton *check_ = nullptr, *tip_ = nullptr, *undo_ = nullptr, *stop_ = nullptr;
  QLabel *prompt_ = nullptr, *result_ = nullptr;
  QListWidget* decisions_ = nullptr;
  FieldMapWidget* map_ = nullptr;
  QTimer poll_;
  std::mutex mutex_;
  Mail mail_;
  std::function<void()> stopRun_, undoRun_;  // set on the worker before it runs, under mutex_
  std::function<void(std::optional<acquisition::FieldSentinels>)> sentinelsDone_;
  bool stopAsked_ = false;  // under mutex_
  std::thread worker_;
  bool finished_ = true;
};

}  // namespace leafdig::station
