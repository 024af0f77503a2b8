// The Plant view (issue 14, seed 003's interactive display): for curators and modellers. A
// plant from a plan file, or from the station's approved leaves (each at its leaf position,
// drawn from the organ library); sliders for the plan's divergence, jitter, inclination and
// seed; a growth-time scrubber when the plan has growth; the plant in 3D, updated as they
// move; area, silhouette and STAR from above; export by file extension (docs/plants.md).
// A plant captured in place (a plant session of the station's file) opens as measured: its
// stem, full leaves as digitized and quick leaves shaped from the library; the plan's sliders
// do not apply to it.
#pragma once

#include <QWidget>
#include <memory>
#include <optional>

#include "leafdig/acquisition/review/correction.hpp"
#include "leafdig/acquisition/review/review.hpp"
#include "leafdig/model/io/plant_export.hpp"
#include "leafdig/model/plant/plant.hpp"
#include "leafdig/model/plant/plant_survey.hpp"

class QChartView;
class QComboBox;
class QLabel;
class QLineEdit;
class QListWidget;
class QPushButton;
class QSlider;
class QSpinBox;

namespace leafdig::station {

class MeshChoice;
class PreviewWidget;

class PlantView : public QWidget {
  Q_OBJECT

 public:
  explicit PlantView(QWidget* parent = nullptr);
  ~PlantView() override;
  // The station's database: its approved leaves are listed (all ticked) for "From approved
  // leaves".
  void setDatabase(const std::string& path);
  // A correction moving a point further than this asks with a warning (the station's setting).
  void setConfirmMoveAboveMm(double mm) { confirmMoveAboveMm_ = mm; }
  void refreshLibrary();
  [[nodiscard]] QListWidget* libraryList() const { return libraryList_; }
  // Each returns an error text to show (empty when the plant was built).
  QString openPlan(const QString& path);
  QString planFromApprovedLeaves();
  // The plant sessions of the database (listed in capturedList(), with their data the session id).
  [[nodiscard]] QComboBox* capturedList() const { return captured_; }
  QString openCapturedPlant(std::int64_t session);
  // A curator's decision on the captured plant shown (a complete plant session): approved, or
  // rejected with what is wrong. Returns an error text (empty when recorded); the store's words
  // when it refuses (an open session, one already decided, a lab server role that may not).
  QString approveCaptured(const QString& who);
  // The captured plant's points and readings a curator may correct, as stored (the
  // digitizer's frame): the plant's own (landmarks, the collar and its diameter, each node's
  // points and stem diameters, quick leaves' points), then each full leaf's items with their
  // node.
  struct CorrectableItem {
    QString label;                 // "Node 3 · stem diameter (17.10 mm)"
    acquisition::Correction item;  // plantWhat, row, col, and the stored position or value
  };
  [[nodiscard]] std::vector<CorrectableItem> correctableItems() const;
  // Records a curator's correction of the shown complete plant (acquisition::correct) and
  // shows the plant again as corrected; the engine's words when it refuses (nothing written).
  QString correctCaptured(const acquisition::Correction& c);
  [[nodiscard]] QPushButton* correctButton() const { return correct_; }
  QString rejectCaptured(const QString& who, const QString& why);
  // Reopens the approved or rejected plant session, saying why: complete again (acquisition::reopen).
  QString reopenCaptured(const QString& who, const QString& why);
  // The shown captured plant's session status ("complete", "approved", …; empty for a plan).
  [[nodiscard]] QString capturedStatus() const { return capturedStatus_; }
  [[nodiscard]] QPushButton* approveButton() const { return approve_; }
  [[nodiscard]] QPushButton* reopenButton() const { return reopen_; }
  // A captured plant's divergences between successive leaves (counterclockwise, seen from
  // above), counted in 10° bins from 0° to 360°, drawn against the golden angle (137.5°);
  // empty and hidden for a planned plant.
  [[nodiscard]] const std::vector<int>& divergenceBins() const { return divergenceBins_; }
  [[nodiscard]] QChartView* divergenceChart() const { return divergenceChart_; }
  QString exportTo(const QString& path);

  [[nodiscard]] const model::Plant* plant() const { return plant_ ? &*plant_ : nullptr; }
  [[nodiscard]] const model::PlantMetrics* metrics() const { return metrics_ ? &*metrics_ : nullptr; }
  [[nodiscard]] PreviewWidget* preview() const { return preview_; }
  [[nodiscard]] QSlider* divergenceSlider() const { return divergence_; }
  [[nodiscard]] QSlider* jitterSlider() const { return jitter_; }
  [[nodiscard]] QSlider* inclinationSlider() const { return inclination_; }
  [[nodiscard]] QSlider* timeSlider() const { return time_; }
  [[nodiscard]] QSpinBox* seedBox() const { return seed_; }
  [[nodiscard]] MeshChoice* exportMesh() const { return exportMesh_; }
  [[nodiscard]] QString summaryText() const;
  [[nodiscard]] QString statusText() const;

 private:
  QString usePlan(model::PlantPlan plan, std::vector<model::LibraryLeaf> library);
  void slidersFromPlan();
  QString rebuild();  // plan + sliders -> plant -> preview and summary
  // plant_ -> mesh, metrics, preview and summary ("<id>, <what>: …", then the lines of `more`)
  void showPlant(const QString& what, const QString& more);
  void enableSliders(bool on);
  void scheduleRebuild();
  [[nodiscard]] std::optional<double> time() const;

  std::string db_;
  std::optional<model::PlantPlan> plan_;  // as loaded; the sliders override some keys
  std::vector<model::LibraryLeaf> library_;
  std::optional<model::Plant> plant_;
  std::optional<model::LeafMesh> mesh_;
  std::optional<model::PlantMetrics> metrics_;
  PreviewWidget* preview_;
  QSlider *divergence_, *jitter_, *inclination_, *time_;
  QSpinBox* seed_;
  QLabel *divergenceLabel_, *jitterLabel_, *inclinationLabel_, *timeLabel_, *summary_, *status_;
  QPushButton* export_;
  MeshChoice* exportMesh_;
  QListWidget* libraryList_;
  QComboBox* captured_;
  QChartView* divergenceChart_;
  std::vector<int> divergenceBins_;
  void showDivergences(const std::vector<double>& degrees);
  QString decide(const char* status, const QString& who, const QString& why);
  void showReviewState();
  std::int64_t capturedSession_ = 0;          // the captured plant shown, 0 for a plan
  std::optional<model::PlantSurvey> survey_;  // its survey (exports: the session's own MTG, CSV, GLB)
  model::SurveyDate surveyDate_{};
  QString capturedStatus_;
  QWidget* reviewRow_;
  QLineEdit* curator_;
  QPushButton *approve_, *reject_, *reopen_, *correct_;
  double confirmMoveAboveMm_ = acquisition::kConfirmMoveAboveMm;
  void correctDialog();
  std::vector<model::LibraryLeaf> approved_;  // as listed
  bool rebuildPending_ = false;
};

}  // namespace leafdig::station
