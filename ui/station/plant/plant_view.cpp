#include "plant/plant_view.hpp"

#include <QChart>
#include <QChartView>
#include <QComboBox>
#include <QDialog>
#include <QDialogButtonBox>
#include <QDoubleSpinBox>
#include <QFileDialog>
#include <QFileInfo>
#include <QFormLayout>
#include <QHBoxLayout>
#include <QInputDialog>
#include <QLabel>
#include <QLineEdit>
#include <QLineSeries>
#include <QListWidget>
#include <QPushButton>
#include <QSlider>
#include <QSpinBox>
#include <QTimer>
#include <QVBoxLayout>
#include <QValueAxis>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <tuple>

#include "leafdig/acquisition/review/correction.hpp"
#include "leafdig/acquisition/review/plant_export.hpp"
#include "leafdig/acquisition/review/review.hpp"
#include "leafdig/acquisition/session/plant_session.hpp"
#include "leafdig/db/lab.hpp"
#include "leafdig/db/store.hpp"
#include "leafdig/model/errors.hpp"
#include "leafdig/model/files.hpp"
#include "leafdig/model/io/survey_export.hpp"
#include "leafdig/version.hpp"
#include "preview/compact_chart.hpp"
#include "preview/mesh_choice.hpp"
#include "preview/preview_widget.hpp"
#include "review/correction_dialog.hpp"

namespace leafdig::station {

namespace m = leafdig::model;

namespace {

constexpr int kTimeSteps = 100;  // the scrubber's last step is the full-grown plant

QSlider* slider(int lo, int hi) {
  auto* s = new QSlider(Qt::Horizontal);
  s->setRange(lo, hi);
  return s;
}

}  // namespace

PlantView::PlantView(QWidget* parent) : QWidget(parent) {
  auto* controls = new QWidget;
  controls->setMaximumWidth(380);
  auto* form = new QFormLayout;
  auto* open = new QPushButton(tr("Open plan…"));
  auto* fromStore = new QPushButton(tr("From approved leaves"));
  fromStore->setToolTip(tr("A plant of the ticked approved leaves, each at its leaf position"));
  libraryList_ = new QListWidget;
  libraryList_->setMaximumHeight(140);
  captured_ = new QComboBox;
  captured_->setToolTip(tr("Plants digitized where they stand (plant sessions of this station)"));
  auto* openCaptured = new QPushButton(tr("Open captured plant"));
  export_ = new QPushButton(tr("Export…"));
  export_->setEnabled(false);
  divergence_ = slider(900, 1800);  // tenths of a degree
  jitter_ = slider(0, 30);
  inclination_ = slider(0, 120);
  time_ = slider(0, kTimeSteps);
  time_->setEnabled(false);
  seed_ = new QSpinBox;
  seed_->setRange(0, 999999);
  divergenceLabel_ = new QLabel;
  jitterLabel_ = new QLabel;
  inclinationLabel_ = new QLabel(tr("as planned"));
  timeLabel_ = new QLabel(tr("full grown"));
  summary_ = new QLabel(tr("Open a plan (leafdig.plant/1) or build one from the approved leaves."));
  summary_->setWordWrap(true);
  status_ = new QLabel;
  status_->setWordWrap(true);
  status_->setStyleSheet("color: #b00020");
  const auto row = [form](const QString& name, QSlider* s, QLabel* value) {
    auto* box = new QWidget;
    auto* h = new QHBoxLayout(box);
    h->setContentsMargins(0, 0, 0, 0);
    h->addWidget(s, 1);
    value->setMinimumWidth(80);
    h->addWidget(value);
    form->addRow(name, box);
  };
  auto* buttons = new QHBoxLayout;
  buttons->addWidget(open);
  buttons->addWidget(fromStore);
  form->addRow(buttons);
  form->addRow(libraryList_);
  auto* capturedRow = new QHBoxLayout;
  capturedRow->addWidget(captured_, 1);
  capturedRow->addWidget(openCaptured);
  form->addRow(capturedRow);
  row(tr("Divergence"), divergence_, divergenceLabel_);
  row(tr("Jitter"), jitter_, jitterLabel_);
  row(tr("Inclination"), inclination_, inclinationLabel_);
  form->addRow(tr("Seed"), seed_);
  row(tr("Growth time"), time_, timeLabel_);
  form->addRow(summary_);
  form->addRow(status_);
  divergenceChart_ = new QChartView;
  divergenceChart_->setMinimumHeight(170);
  divergenceChart_->setRenderHint(QPainter::Antialiasing);
  divergenceChart_->hide();
  form->addRow(divergenceChart_);
  // A captured plant's review: the curator approves it or rejects it with what is wrong.
  reviewRow_ = new QWidget;
  auto* reviewLayout = new QHBoxLayout(reviewRow_);
  reviewLayout->setContentsMargins(0, 0, 0, 0);
  curator_ = new QLineEdit(QString::fromLocal8Bit(qgetenv("USER")));
  curator_->setPlaceholderText(tr("curator's name"));
  approve_ = new QPushButton(tr("Approve"));
  reject_ = new QPushButton(tr("Reject…"));
  reopen_ = new QPushButton(tr("Reopen…"));
  correct_ = new QPushButton(tr("Correct…"));
  reviewLayout->addWidget(curator_, 1);
  reviewLayout->addWidget(correct_);
  reviewLayout->addWidget(approve_);
  reviewLayout->addWidget(reject_);
  reviewLayout->addWidget(reopen_);
  reviewRow_->hide();
  form->addRow(reviewRow_);
  exportMesh_ = new MeshChoice;
  form->addRow(tr("Export mesh"), exportMesh_);
  form->addRow(export_);
  controls->setLayout(form);

  preview_ = new PreviewWidget(this);
  auto* layout = new QHBoxLayout(this);
  layout->addWidget(controls);
  layout->addWidget(preview_, 1);

  connect(open, &QPushButton::clicked, this, [this] {
    const QString path = QFileDialog::getOpenFileName(this, tr("Open a plant plan"), {}, tr("Plant plans (*.json)"));
    if (!path.isEmpty()) status_->setText(openPlan(path));
  });
  connect(fromStore, &QPushButton::clicked, this, [this] { status_->setText(planFromApprovedLeaves()); });
  connect(openCaptured, &QPushButton::clicked, this, [this] {
    const QVariant id = captured_->currentData();
    status_->setText(id.isValid() ? openCapturedPlant(id.toLongLong()) : tr("No plant captured in this database yet."));
  });
  connect(export_, &QPushButton::clicked, this, [this] {
    const QString path = QFileDialog::getSaveFileName(
        this, tr("Export the plant"), {}, tr("Any plant format (*.glb *.obj *.ply *.stl *.can *.mtg *.csv *.json)"));
    if (path.isEmpty()) return;
    const QString error = exportTo(path);
    status_->setText(error);
    if (error.isEmpty()) summary_->setText(summary_->text() + "\n" + tr("Wrote %1").arg(path));
  });
  connect(approve_, &QPushButton::clicked, this, [this] { status_->setText(approveCaptured(curator_->text())); });
  connect(correct_, &QPushButton::clicked, this, [this] { correctDialog(); });
  connect(reject_, &QPushButton::clicked, this, [this] {
    bool ok = false;
    const QString why =
        QInputDialog::getText(this, tr("Reject"), tr("What is wrong with this plant?"), QLineEdit::Normal, {}, &ok);
    if (ok) status_->setText(rejectCaptured(curator_->text(), why));
  });
  connect(reopen_, &QPushButton::clicked, this, [this] {
    bool ok = false;
    const QString why = QInputDialog::getText(this, tr("Reopen"), tr("Why does the decision no longer stand?"),
                                              QLineEdit::Normal, {}, &ok);
    if (ok) status_->setText(reopenCaptured(curator_->text(), why));
  });
  for (QSlider* s : {divergence_, jitter_, time_})
    connect(s, &QSlider::valueChanged, this, [this] { scheduleRebuild(); });
  connect(inclination_, &QSlider::valueChanged, this, [this] {
    inclination_->setProperty("override", true);
    scheduleRebuild();
  });
  connect(seed_, qOverload<int>(&QSpinBox::valueChanged), this, [this] { scheduleRebuild(); });
}

PlantView::~PlantView() = default;

QString PlantView::summaryText() const {
  return summary_->text();
}
QString PlantView::statusText() const {
  return status_->text();
}

QString PlantView::openPlan(const QString& path) {
  try {
    m::PlantPlan plan = m::readPlantPlan(path.toStdString());
    std::vector<m::LibraryLeaf> library;
    if (plan.libraryDb) {
      if (!db::isServerUrl(*plan.libraryDb) && !std::filesystem::exists(*plan.libraryDb))
        return tr("The plan's library %1 does not exist.").arg(QString::fromStdString(*plan.libraryDb));
      library = acquisition::organLibrary(*db::openEventStore(*plan.libraryDb, true)).leaves;
    }
    return usePlan(std::move(plan), std::move(library));
  } catch (const std::exception& e) {
    return QString::fromStdString(e.what());
  }
}

void PlantView::setDatabase(const std::string& path) {
  db_ = path;
  refreshLibrary();
}

void PlantView::refreshLibrary() {
  libraryList_->clear();
  approved_.clear();
  captured_->clear();
  if (db_.empty() || (!db::isServerUrl(db_) && !std::filesystem::exists(db_))) return;
  try {
    const auto store = db::openEventStore(db_, true);
    approved_ = acquisition::organLibrary(*store).leaves;
    for (const db::SessionInfo& s : store->sessions())
      if (s.kind == "plant")
        captured_->addItem(tr("%1 · session %2 · %3 · %4")
                               .arg(QString::fromStdString(s.plant))
                               .arg(s.id)
                               .arg(QString::fromStdString(s.createdUtc.substr(0, 10)))
                               .arg(QString::fromStdString(s.status)),
                           QVariant::fromValue<qlonglong>(s.id));
  } catch (const std::exception& e) {
    status_->setText(QString::fromStdString(e.what()));
    return;
  }
  if (approved_.empty()) {
    // Say why the list is empty rather than show an empty box (not a leaf: not checkable).
    auto* none = new QListWidgetItem(tr("No approved leaf in this database yet: approve sessions in Review"));
    none->setFlags(Qt::NoItemFlags);
    libraryList_->addItem(none);
    return;
  }
  std::stable_sort(approved_.begin(), approved_.end(), [](const auto& a, const auto& b) {
    return a.markers.leaf.position.value_or(0) < b.markers.leaf.position.value_or(0);
  });
  for (const auto& leaf : approved_) {
    const auto& info = leaf.markers.leaf;
    auto* item =
        new QListWidgetItem(tr("%1 · leaf %2%3 · %4")
                                .arg(QString::fromStdString(info.plant))
                                .arg(info.position.value_or(0))
                                .arg(info.type.empty() ? QString() : " (" + QString::fromStdString(info.type) + ")")
                                .arg(QString::fromStdString(leaf.source)));
    item->setFlags(item->flags() | Qt::ItemIsUserCheckable);
    item->setCheckState(Qt::Checked);
    libraryList_->addItem(item);
  }
}

QString PlantView::planFromApprovedLeaves() {
  if (db_.empty() || !std::filesystem::exists(db_)) return tr("This station has no database yet.");
  if (approved_.empty()) refreshLibrary();  // (keeps the operator's ticks otherwise)
  // The ticked leaves, in leaf-position order, each one placed as itself.
  std::vector<m::LibraryLeaf> picked;
  for (std::size_t i = 0; i < approved_.size() && i < static_cast<std::size_t>(libraryList_->count()); ++i)
    if (libraryList_->item(static_cast<int>(i))->checkState() == Qt::Checked) picked.push_back(approved_[i]);
  if (approved_.empty()) return tr("No approved leaf yet: approve sessions in the Review view first.");
  if (picked.empty()) return tr("Tick at least one approved leaf.");
  m::PlantPlan plan;
  plan.id = picked.front().markers.leaf.plant.empty() ? "plant" : picked.front().markers.leaf.plant;
  plan.stem = {900.0, 24.0, 8.0, {}};
  plan.libraryDb = db_;
  std::vector<m::LibraryLeaf> library;
  int rank = 0;
  for (auto& leaf : picked) {
    m::LeafPlan l;
    l.rank = ++rank;
    // A request only this leaf answers: its own id as the type of a one-leaf library.
    leaf.markers.leaf.type = leaf.source;
    l.library = m::LibraryRequest{leaf.source, std::nullopt};
    l.insertionHeightMm = std::min(860.0, 60.0 + 70.0 * (rank - 1));
    plan.leaves.push_back(l);
    library.push_back(leaf);
  }
  return usePlan(std::move(plan), std::move(library));
}

QString PlantView::openCapturedPlant(std::int64_t session) {
  if (db_.empty()) return tr("This station has no database yet.");
  try {
    const auto store = db::openEventStore(db_, true);
    const acquisition::CapturedSurvey captured = acquisition::capturedSurvey(*store, session);
    acquisition::CapturedModel made = acquisition::capturedModel(captured);
    plan_.reset();
    library_.clear();
    plant_ = std::move(made.plant);
    enableSliders(false);
    const QString what = tr("captured %1 (session %2)")
                             .arg(QString::fromStdString(captured.markers.date ? m::toIso(*captured.markers.date) : ""))
                             .arg(session);
    QString more;
    for (const std::string& note : made.notes) more += "\n" + QString::fromStdString(note);
    std::vector<double> divergences;
    for (const m::SurveyedLeaf& l : captured.survey.leaves)
      if (l.divergenceDeg) divergences.push_back(*l.divergenceDeg);
    if (!divergences.empty()) {
      double sum = 0.0;
      for (double d : divergences) sum += d;
      more += "\n" + tr("divergence: mean %1° over %2 pair(s) of successive leaves (golden angle 137.5°)")
                         .arg(sum / static_cast<double>(divergences.size()), 0, 'f', 1)
                         .arg(divergences.size());
    }
    showPlant(what, more);
    showDivergences(divergences);
    export_->setEnabled(true);
    capturedSession_ = session;
    capturedStatus_ = QString::fromStdString(captured.status);
    survey_ = captured.survey;
    surveyDate_ = captured.markers.date.value_or(m::SurveyDate{2000, 1, 1});
    showReviewState();
    return {};
  } catch (const std::exception& e) {
    return QString::fromStdString(e.what());
  }
}

void PlantView::enableSliders(bool on) {
  for (QWidget* w : std::initializer_list<QWidget*>{divergence_, jitter_, inclination_, seed_}) w->setEnabled(on);
  if (!on) time_->setEnabled(false);
}

void PlantView::showDivergences(const std::vector<double>& degrees) {
  divergenceBins_.assign(36, 0);
  for (double d : degrees) ++divergenceBins_[static_cast<std::size_t>(std::clamp(static_cast<int>(d / 10.0), 0, 35))];
  QFont small;
  QChart* chart = compactChart(tr("Divergence, ° (green line: 137.5°)"), small);
  chart->legend()->hide();       // the title says what the line is: room for the labels at 1366 × 768
  auto* bars = new QLineSeries;  // the histogram's outline, bin by bin
  bars->setName(tr("leaves"));
  int most = 1;
  bars->append(0, 0);
  for (std::size_t b = 0; b < divergenceBins_.size(); ++b) {
    const double x0 = 10.0 * static_cast<double>(b);
    bars->append(x0, divergenceBins_[b]);
    bars->append(x0 + 10.0, divergenceBins_[b]);
    most = std::max(most, divergenceBins_[b]);
  }
  bars->append(360, 0);
  auto* golden = new QLineSeries;
  golden->setName(tr("137.5°"));
  golden->append(m::kGoldenAngleDeg, 0);
  golden->append(m::kGoldenAngleDeg, most + 0.5);
  chart->addSeries(bars);
  chart->addSeries(golden);
  auto* x = new QValueAxis;
  x->setRange(0, 360);
  x->setTickType(QValueAxis::TicksDynamic);
  x->setTickAnchor(0);
  x->setTickInterval(90);
  x->setLabelFormat("%d");  // degrees (a ° in the format is not taken as UTF-8 by Qt Charts)
  x->setLabelsFont(small);
  auto* y = new QValueAxis;
  y->setRange(0, most + 0.5);
  y->setLabelFormat("%d");
  y->setLabelsFont(small);
  y->setTickType(QValueAxis::TicksDynamic);
  y->setTickAnchor(0);
  y->setTickInterval(most > 6 ? 2 : 1);
  showChart(divergenceChart_, chart, x, y);
  divergenceChart_->setVisible(!degrees.empty());
}

QString PlantView::usePlan(m::PlantPlan plan, std::vector<m::LibraryLeaf> library) {
  enableSliders(true);
  capturedSession_ = 0;
  capturedStatus_.clear();
  survey_.reset();
  showReviewState();
  divergenceBins_.clear();
  divergenceChart_->hide();
  plan_ = std::move(plan);
  library_ = std::move(library);
  slidersFromPlan();
  const QString error = rebuild();
  if (!error.isEmpty()) {
    plan_.reset();
    plant_.reset();
  }
  export_->setEnabled(error.isEmpty());
  return error;
}

void PlantView::slidersFromPlan() {
  const QSignalBlocker a(divergence_), b(jitter_), c(inclination_), d(time_), e(seed_);
  divergence_->setValue(static_cast<int>(std::lround(plan_->divergenceDeg * 10)));
  jitter_->setValue(static_cast<int>(std::lround(plan_->jitterDeg)));
  inclination_->setValue(static_cast<int>(m::kDefaultInclinationDeg));
  inclination_->setProperty("override", false);
  time_->setValue(kTimeSteps);
  time_->setEnabled(plan_->growth.has_value());
  seed_->setValue(static_cast<int>(plan_->seed % 1000000));
}

std::optional<double> PlantView::time() const {
  if (!plan_ || !plan_->growth || time_->value() >= kTimeSteps) return std::nullopt;
  const m::GrowthPlan& g = *plan_->growth;
  // The scrubber spans from the first leaf's appearance to the last leaf's near-full size.
  const double end = (static_cast<double>(plan_->leaves.size()) - 1) * g.plastochron + g.leafMidpoint + 6 / g.leafRate;
  return end * time_->value() / kTimeSteps;
}

void PlantView::scheduleRebuild() {
  if (rebuildPending_ || !plan_) return;
  rebuildPending_ = true;  // slider moves coalesce into one rebuild per event-loop turn
  QTimer::singleShot(0, this, [this] {
    rebuildPending_ = false;
    status_->setText(rebuild());
  });
}

QString PlantView::rebuild() {
  if (!plan_) return {};
  m::PlantPlan plan = *plan_;
  plan.divergenceDeg = divergence_->value() / 10.0;
  plan.jitterDeg = jitter_->value();
  plan.seed = static_cast<std::uint64_t>(seed_->value());
  const bool inclined = inclination_->property("override").toBool();
  if (inclined) {
    for (auto& l : plan.leaves) l.inclinationDeg = inclination_->value();
  }
  divergenceLabel_->setText(QString::number(plan.divergenceDeg, 'f', 1) + "°");
  jitterLabel_->setText("± " + QString::number(plan.jitterDeg, 'f', 0) + "°");
  inclinationLabel_->setText(inclined ? QString::number(inclination_->value()) + "°" : tr("as planned"));
  const std::optional<double> t = time();
  timeLabel_->setText(t ? QString::number(*t, 'f', 1) + " " + QString::fromStdString(plan.growth->timeUnit)
                        : tr("full grown"));
  try {
    const m::PlantBuilder builder(plan, library_);
    plant_ = builder.build(t);
    showPlant(tr("planned"), {});
  } catch (const std::exception& e) {
    return QString::fromStdString(e.what());
  }
  return {};
}

void PlantView::showPlant(const QString& what, const QString& more) {
  mesh_ = m::meshPlant(*plant_, m::MeshResolution::preset("preview"));
  metrics_ = m::computePlantMetrics(*plant_, *mesh_, Eigen::Vector3d::UnitZ());
  auto preview = std::make_shared<acquisition::Preview>();
  preview->mesh = *mesh_;
  acquisition::Snapshot snapshot;
  snapshot.preview = preview;
  preview_->show(snapshot);
  summary_->setText(tr("%1, %7: %2 leaves, stem %3 mm · leaf area %4 cm² · silhouette from above %5 cm² · STAR %6")
                        .arg(QString::fromStdString(plant_->id))
                        .arg(plant_->leaves.size())
                        .arg(plant_->stemHeightMm, 0, 'f', 0)
                        .arg(metrics_->areaMm2 / 100, 0, 'f', 0)
                        .arg(metrics_->silhouetteMm2 / 100, 0, 'f', 0)
                        .arg(metrics_->star, 0, 'f', 2)
                        .arg(what) +
                    more);
}

QString PlantView::exportTo(const QString& path) {
  if (!plant_) return tr("Nothing to export: open a plan first.");
  try {
    // Exports at the export resolution or as chosen (the view draws the preview's).
    const m::LeafMesh mesh = m::meshPlant(*plant_, exportMesh_->options("export"));
    const m::PlantMetrics metrics = m::computePlantMetrics(*plant_, mesh, Eigen::Vector3d::UnitZ());
    const std::string generator = std::string("leafdig ") + kVersion;
    // A captured plant's MTG, CSV and GLB are its session's (`sessions export`): the survey's
    // entities, its measured features, its day.
    const std::string extension = std::filesystem::path(path.toStdString()).extension().string();
    if (survey_ && (extension == ".glb" || extension == ".mtg" || extension == ".csv")) {
      const std::string bytes = extension == ".glb"   ? m::encodeSurveyGlb(*survey_, surveyDate_, mesh, generator)
                                : extension == ".mtg" ? m::encodeSurveyMtg(*survey_, surveyDate_)
                                                      : m::encodeSurveyCsv(*survey_, surveyDate_);
      m::writeFileAtomically(path.toStdString(), bytes);
      return {};
    }
    for (const auto& f : m::encodePlant(path.toStdString(), *plant_, mesh, metrics, {m::CanUnit::Metre, generator}))
      m::writeFileAtomically(f.path, f.bytes);
    return {};
  } catch (const std::exception& e) {
    return QString::fromStdString(e.what());
  }
}

void PlantView::showReviewState() {
  reviewRow_->setVisible(capturedSession_ != 0);
  const bool open = capturedStatus_ == "complete";
  approve_->setEnabled(open);
  reject_->setEnabled(open);
  correct_->setEnabled(open);
  approve_->setToolTip(
      open ? tr("Approve plant session %1").arg(capturedSession_)
           : tr("This plant session is %1: only a complete one is approved or rejected").arg(capturedStatus_));
  const bool decided = capturedStatus_ == "approved" || capturedStatus_ == "rejected";
  reopen_->setEnabled(decided);
  reopen_->setToolTip(
      decided ? tr("Make this %1 plant session complete again, to correct and decide anew").arg(capturedStatus_)
              : tr("Only an approved or rejected session is reopened"));
}

QString PlantView::approveCaptured(const QString& who) {
  return decide("approved", who, {});
}

QString PlantView::rejectCaptured(const QString& who, const QString& why) {
  return decide("rejected", who, why);
}

QString PlantView::reopenCaptured(const QString& who, const QString& why) {
  return decide("reopened", who, why);
}

QString PlantView::decide(const char* status, const QString& who, const QString& why) {
  if (capturedSession_ == 0) return tr("Open a captured plant first: a plan is not reviewed.");
  try {
    const auto store = db::openEventStore(db_, false);
    if (std::string(status) == "reopened")
      (void)acquisition::reopen(*store, capturedSession_, who.toStdString(), why.toStdString());
    else
      (void)acquisition::review(*store, capturedSession_, status, who.toStdString(), why.toStdString());
    capturedStatus_ = QString::fromStdString(store->session(capturedSession_)->status);
  } catch (const std::exception& e) {
    return QString::fromStdString(e.what());
  }
  showReviewState();
  summary_->setText(summary_->text() + "\n" + tr("Session %1 %2 by %3").arg(capturedSession_).arg(status, who));
  return {};
}

std::vector<PlantView::CorrectableItem> PlantView::correctableItems() const {
  // The item's stored position or value, into the correction and its label after `where`.
  const auto stored = [](CorrectableItem& c, const QString& where, bool stylus, const acquisition::Vec3& p,
                         double value) {
    if (stylus) {
      c.item.positionMm = p;
      c.label = tr("%1 (%2, %3, %4 mm)").arg(where).arg(p[0], 0, 'f', 1).arg(p[1], 0, 'f', 1).arg(p[2], 0, 'f', 1);
    } else {
      c.item.valueMm = value;
      c.label = tr("%1 (%2 mm)").arg(where).arg(value, 0, 'f', 2);
    }
  };
  std::vector<CorrectableItem> out;
  if (capturedSession_ == 0) return out;
  try {
    const auto store = db::openEventStore(db_, true);
    const auto info = store->session(capturedSession_);
    if (!info) return out;
    const acquisition::PlantEngine engine = acquisition::PlantCaptureSession::replay(
        acquisition::PlantCaptureSession::setupFromJson(info->settingsJson), store->events(capturedSession_));
    for (const acquisition::PlantItem& i : engine.items()) {
      CorrectableItem c;
      c.item.plantWhat = i.what;
      c.item.row = i.index;
      c.item.col = i.part;
      QString where;
      switch (i.what) {
        case acquisition::PlantWhat::Landmark: where = tr("Landmark %1").arg(i.index); break;
        case acquisition::PlantWhat::LandmarkAgain:  // as pressed after move `part`, in its own frame
          where = tr("Landmark %1 again · move %2").arg(i.index).arg(i.part);
          break;
        case acquisition::PlantWhat::Collar: where = tr("Collar"); break;
        case acquisition::PlantWhat::CollarDiameter: where = tr("Collar · stem diameter"); break;
        case acquisition::PlantWhat::Point: where = tr("Node %1 · point %2").arg(i.index).arg(i.part); break;
        case acquisition::PlantWhat::Reading: where = tr("Node %1 · stem diameter %2").arg(i.index).arg(i.part); break;
        case acquisition::PlantWhat::QuickPoint:
          where = tr("Node %1 · quick leaf %2")
                      .arg(i.index)
                      .arg(i.part == 1   ? tr("base")
                           : i.part == 2 ? tr("tip")
                                         : tr("margin point"));
          break;
        default: continue;
      }
      stored(c, where, acquisition::isStylusItem(i.what), i.positionMm, i.valueMm);
      out.push_back(std::move(c));
    }
    // Each full leaf's items, with their node (the leaf's own words, rows from the tip).
    for (int node = 1; node <= engine.nodes(); ++node) {
      const acquisition::Engine* leaf = engine.leaf(node);
      if (!leaf) continue;
      std::vector<acquisition::Item> items = leaf->items();
      std::sort(items.begin(), items.end(), [](const acquisition::Item& a, const acquisition::Item& b) {
        return std::tie(a.row, a.col, a.what) < std::tie(b.row, b.col, b.what);
      });
      for (const acquisition::Item& i : items) {
        CorrectableItem c;
        c.item.node = node;
        c.item.what = i.what;
        c.item.row = i.row;
        c.item.col = i.col;
        const QString where = tr("Node %1 · leaf %2%3%4")
                                  .arg(node)
                                  .arg(QString::fromLatin1(acquisition::toString(i.what)).replace('_', ' '))
                                  .arg(i.row > 0 ? tr(" · row %1").arg(i.row) : QString())
                                  .arg(i.col > 0 ? tr(" · point %1").arg(i.col) : QString());
        stored(c, where, acquisition::isStylusItem(i.what), i.positionMm, i.valueMm);
        out.push_back(std::move(c));
      }
    }
  } catch (const std::exception&) {
    return {};  // openCapturedPlant said what is wrong with the session
  }
  return out;
}

QString PlantView::correctCaptured(const acquisition::Correction& c) {
  if (capturedSession_ == 0) return tr("Open a captured plant first: a plan is not corrected.");
  try {
    const auto store = db::openEventStore(db_, false);
    (void)acquisition::correct(*store, capturedSession_, c);
  } catch (const std::exception& e) {
    return QString::fromStdString(e.what());
  }
  const std::int64_t session = capturedSession_;
  const QString error = openCapturedPlant(session);
  if (!error.isEmpty()) return error;
  summary_->setText(summary_->text() + "\n" +
                    tr("Corrected by %1: %2").arg(QString::fromStdString(c.who), QString::fromStdString(c.reason)));
  return {};
}

void PlantView::correctDialog() {
  const std::vector<CorrectableItem> items = correctableItems();
  if (items.empty()) {
    status_->setText(tr("This plant has no point or reading to correct."));
    return;
  }
  std::vector<CorrectionChoice> choices;
  for (const CorrectableItem& i : items) choices.push_back({i.label, i.item});
  std::optional<acquisition::Correction> asked = askCorrection(
      this, tr("Correct a point or reading of plant session %1").arg(capturedSession_), choices, tr("diameter"));
  if (!asked) return;
  acquisition::Correction c = *asked;
  c.who = curator_->text().toStdString();
  // The effect shown before anything is written; the curator writes it or not.
  try {
    const auto store = db::openEventStore(db_, false);
    const acquisition::CorrectionEffect effect = acquisition::previewCorrection(*store, capturedSession_, c);
    if (!confirmCorrection(this, effect, confirmMoveAboveMm_)) {
      status_->setText(tr("The correction was not written."));
      return;
    }
    c.seenHead = effect.head;  // what the curator confirmed: refused if the session moved on since
  } catch (const std::exception& e) {
    status_->setText(QString::fromStdString(e.what()));
    return;
  }
  const QString error = correctCaptured(c);
  status_->setText(error.isEmpty() ? tr("Corrected; the plant is shown as corrected.") : error);
}

}  // namespace leafdig::station
