#include "plant/plant_capture_view.hpp"

#include <QComboBox>
#include <QHBoxLayout>
#include <QInputDialog>
#include <QLabel>
#include <QLineEdit>
#include <QPushButton>
#include <QSplitter>
#include <QTimer>
#include <QTreeWidget>
#include <QVBoxLayout>
#include <exception>
#include <set>

#include "leafdig/acquisition/live/device_set.hpp"
#include "leafdig/acquisition/review/review.hpp"
#include "leafdig/acquisition/sim/plant_simulation.hpp"
#include "leafdig/db/store.hpp"
#include "leafdig/model/plant/plant_markers.hpp"
#include "preview/preview_widget.hpp"

namespace leafdig::station {

namespace acq = leafdig::acquisition;
namespace m = leafdig::model;
using Kind = acq::PlantDecision::Kind;

namespace {

QString mm(double v) {
  return QString::number(v, 'f', 1) + " mm";
}

// What a committed decision did, in the words of the plant (the prompt says what comes next).
QString said(const acq::PlantDecision& d) {
  const auto item = [](const acq::PlantItem& i) -> QString {
    switch (i.what) {
      case acq::PlantWhat::Landmark: return QObject::tr("landmark %1").arg(i.index);
      case acq::PlantWhat::Collar: return QObject::tr("the collar");
      case acq::PlantWhat::CollarDiameter: return QObject::tr("the collar's diameter %1").arg(mm(i.valueMm));
      case acq::PlantWhat::Point: return QObject::tr("node %1, point %2").arg(i.index).arg(i.part);
      case acq::PlantWhat::Reading: return QObject::tr("node %1, stem diameter %2").arg(i.index).arg(mm(i.valueMm));
      case acq::PlantWhat::QuickPoint: return QObject::tr("node %1's leaf, point %2 of 3").arg(i.index).arg(i.part);
      case acq::PlantWhat::LandmarkAgain: return QObject::tr("landmark %1 again").arg(i.index);
      case acq::PlantWhat::Leaf:
      case acq::PlantWhat::Done: break;
    }
    return {};
  };
  switch (d.kind) {
    case Kind::Accepted: return QObject::tr("✓ %1").arg(item(d.item));
    case Kind::Undone: return QObject::tr("↶ undone: %1").arg(item(d.item));
    case Kind::RetakeStarted: return QObject::tr("↻ retake: %1 is taken out; take it again").arg(item(d.item));
    case Kind::RetakeCancelled: return QObject::tr("↶ retake cancelled: %1 is back").arg(item(d.item));
    case Kind::Rejected: return QObject::tr("✗ %1").arg(QString::fromStdString(d.reason));
    case Kind::LandmarksEnded: return QObject::tr("✓ landmarks ended");
    case Kind::LandmarksReopened: return QObject::tr("↶ landmarks reopened");
    case Kind::PlantEnded: return QObject::tr("✓ plant ended");
    case Kind::PlantReopened: return QObject::tr("↶ plant reopened");
    case Kind::LeafChosen:
      return QObject::tr("node %1's leaf: %2").arg(d.node).arg(QString::fromStdString(m::toString(d.choice.kind)));
    case Kind::ChoiceUndone: return QObject::tr("↶ node %1's leaf choice undone").arg(d.node);
    case Kind::NodePlaced:
      return d.place.relation == '+'
                 ? QObject::tr("✓ node %1 starts a branch from node %2").arg(d.node).arg(d.place.parent)
                 : QObject::tr("✓ branch ended: node %1 follows node %2 on the stem").arg(d.node).arg(d.place.parent);
    case Kind::PlacementUndone: return QObject::tr("↶ node %1 is placed as before").arg(d.node);
    case Kind::RelocationStarted: return QObject::tr("↻ transmitter moved (%1): take the landmarks again").arg(d.node);
    case Kind::RelocationFitted:
      return QObject::tr("✓ transmitter's new position fitted: RMS %1 mm, worst %2 mm")
          .arg(d.fit.rmsMm, 0, 'f', 2)
          .arg(d.fit.worstMm, 0, 'f', 2);
    case Kind::RelocationReopened: return QObject::tr("↶ the fit is undone: the landmarks again");
    case Kind::RelocationCancelled: return QObject::tr("↶ the move of the transmitter is undone");
    case Kind::Leaf:
      switch (d.leaf.kind) {
        case acq::Decision::Kind::Accepted:
          return QObject::tr("✓ node %1's leaf: %2 %3 %4")
              .arg(d.node)
              .arg(QString::fromLatin1(acq::toString(d.leaf.item.what)))
              .arg(d.leaf.item.row)
              .arg(d.leaf.item.col);
        case acq::Decision::Kind::Undone: return QObject::tr("↶ node %1's leaf: undone").arg(d.node);
        case acq::Decision::Kind::RowsEnded: return QObject::tr("✓ node %1's leaf: rows ended").arg(d.node);
        case acq::Decision::Kind::RetakeStarted:
          return QObject::tr("↻ node %1's leaf: %2 %3 %4 taken out; take it again")
              .arg(d.node)
              .arg(QString::fromLatin1(acq::toString(d.leaf.item.what)))
              .arg(d.leaf.item.row)
              .arg(d.leaf.item.col);
        case acq::Decision::Kind::RetakeCancelled: return QObject::tr("↶ node %1's leaf: retake cancelled").arg(d.node);
        default: return QObject::tr("node %1's leaf").arg(d.node);
      }
    case Kind::Ignored: break;
  }
  return {};
}

// A node's leaf as the tree shows it: its kind, how far it is, its state.
QString leafText(const acq::PlantEngine& e, int node) {
  const acq::LeafChoice c = e.choiceFor(node);
  QString text;
  switch (c.kind) {
    case m::LeafKind::Full: {
      const acq::Engine* leaf = e.leaf(node);
      const int rows = leaf ? acq::completeRows(leaf->items()) : 0;
      text = leaf && leaf->complete() ? QObject::tr("full leaf, %1 rows").arg(rows)
                                      : QObject::tr("full leaf, %1 row(s) so far").arg(rows);
      break;
    }
    case m::LeafKind::Quick: {
      int points = 0;
      for (const acq::PlantItem& i : e.items())
        points += i.what == acq::PlantWhat::QuickPoint && i.index == node ? 1 : 0;
      text = QObject::tr("quick leaf, %1 of 3 points").arg(points);
      break;
    }
    case m::LeafKind::None: text = QObject::tr("no leaf"); break;
  }
  if (c.state != m::LeafState::Alive) text += " · " + QString::fromStdString(m::toString(c.state));
  if (!c.type.empty()) text += " · " + QString::fromStdString(c.type);
  return text;
}

}  // namespace

PlantCaptureView::PlantCaptureView(QWidget* parent) : QWidget(parent) {
  banner_ = new QLabel(tr("No plant is being captured."), this);
  QFont big = banner_->font();
  big.setPointSizeF(big.pointSizeF() * 2.2);
  big.setBold(true);
  banner_->setFont(big);
  banner_->setWordWrap(true);
  banner_->setObjectName("plantBanner");
  banner_->setStyleSheet(
      "QLabel#plantBanner { background: #24502f; color: white; padding: 12px; border-radius: 6px; }");
  feedback_ = new QLabel(this);
  QFont mid = feedback_->font();
  mid.setPointSizeF(mid.pointSizeF() * 1.3);
  feedback_->setFont(mid);
  feedback_->setWordWrap(true);
  tree_ = new QTreeWidget;
  tree_->setHeaderLabels({tr("Plant"), tr("Measured")});
  tree_->setFocusPolicy(Qt::NoFocus);  // keys go to the window, never trapped here
  tree_->setColumnWidth(0, 110);
  summary_ = new QLabel;
  summary_->setWordWrap(true);
  auto* left = new QWidget;
  auto* leftLayout = new QVBoxLayout(left);
  leftLayout->setContentsMargins(0, 0, 0, 0);
  leftLayout->addWidget(tree_, 1);
  leftLayout->addWidget(summary_);
  field_ = new QLabel;
  field_->setWordWrap(true);
  leftLayout->addWidget(field_);
  review_ = new QPushButton(tr("Review this plant"));
  review_->setToolTip(tr("Open the plant in the Plant view: as measured, its divergences, approve or reject"));
  review_->setEnabled(false);
  review_->setFocusPolicy(Qt::NoFocus);
  leftLayout->addWidget(review_);
  connect(review_, &QPushButton::clicked, this, [this] { emit reviewRequested(session_); });
  left->setMinimumWidth(340);
  left->setMaximumWidth(420);
  plantPreview_ = new PreviewWidget;
  leafPane_ = new QWidget;
  auto* leafLayout = new QVBoxLayout(leafPane_);
  leafLayout->setContentsMargins(0, 0, 0, 0);
  auto* leafTitle = new QLabel(tr("The full leaf being taken"));
  leafTitle->setObjectName("leafTitle");
  leafLayout->addWidget(leafTitle);
  leafPreview_ = new PreviewWidget;
  leafLayout->addWidget(leafPreview_, 1);
  leafPane_->setMaximumWidth(480);
  leafPane_->hide();
  auto* split = new QSplitter;
  split->addWidget(left);
  split->addWidget(plantPreview_);
  split->addWidget(leafPane_);
  split->setStretchFactor(1, 3);
  split->setStretchFactor(2, 2);
  // What a press cannot say, for a person with the devices: undo, end, a node's leaf.
  controls_ = new QWidget;
  auto* row = new QHBoxLayout(controls_);
  row->setContentsMargins(0, 0, 0, 0);
  undo_ = new QPushButton(tr("Undo"));
  end_ = new QPushButton(tr("End"));
  end_->setToolTip(tr("Ends the landmarks, a full leaf's rows or the plant (as the long press)"));
  branch_ = new QPushButton(tr("Branch"));
  branch_->setToolTip(
      tr("The next node starts a branch from the stem's last node; End at a branch node's first point ends "
         "the branch (the protocol must have one)"));
  move_ = new QPushButton(tr("Move transmitter"));
  move_->setToolTip(
      tr("You move the transmitter (a tall plant, the far side): take at least three landmarks again where "
         "they are, then End; the new position is fitted to them and every later point joins the first frame"));
  retake_ = new QPushButton(tr("Retake…"));
  retake_->setToolTip(
      tr("Takes a point or reading out to take it again (the item selected in the tree, or "
         "any: landmark 2, collar, point 4, reading 4, quick_point 5 2, node 2 marker 1 3)"));
  pause_ = new QPushButton(tr("Pause"));
  pause_->setToolTip(tr("Presses and readings change nothing until Resume (the pause is kept in the log)"));
  leafKind_ = new QComboBox;
  leafKind_->addItems({"full", "quick", "none"});
  leafState_ = new QComboBox;
  leafState_->addItems({"alive", "dead", "broken", "yellow", "pruned"});
  leafType_ = new QComboBox;
  leafType_->setEditable(true);
  leafType_->lineEdit()->setPlaceholderText(tr("type (lower, upper…)"));
  leafType_->lineEdit()->setMaxLength(64);
  leafType_->setMinimumWidth(140);
  setLeaf_ = new QPushButton(tr("Set node 1's leaf"));
  devices_ = new QLabel;
  for (QWidget* w :
       std::initializer_list<QWidget*>{undo_, end_, branch_, move_, retake_, pause_, leafKind_, leafState_, setLeaf_})
    w->setFocusPolicy(Qt::NoFocus);
  row->addWidget(undo_);
  row->addWidget(end_);
  row->addWidget(branch_);
  row->addWidget(move_);
  row->addWidget(retake_);
  row->addWidget(pause_);
  row->addSpacing(16);
  row->addWidget(leafKind_);
  row->addWidget(leafState_);
  row->addWidget(leafType_);
  row->addWidget(setLeaf_);
  row->addSpacing(16);
  row->addWidget(devices_, 1);
  controls_->hide();
  connect(undo_, &QPushButton::clicked, this, [this] { (void)command({.kind = acq::PlantCommand::Kind::Undo}); });
  connect(end_, &QPushButton::clicked, this, [this] { (void)command({.kind = acq::PlantCommand::Kind::End}); });
  connect(branch_, &QPushButton::clicked, this, [this] { (void)command({.kind = acq::PlantCommand::Kind::Branch}); });
  connect(move_, &QPushButton::clicked, this,
          [this] { (void)command({.kind = acq::PlantCommand::Kind::MoveTransmitter}); });
  connect(pause_, &QPushButton::clicked, this, [this] {
    (void)command({paused_ ? acq::PlantCommand::Kind::Resume : acq::PlantCommand::Kind::Pause,
                   0,
                   {},
                   tr("paused at the station").toStdString()});
  });
  connect(retake_, &QPushButton::clicked, this, [this] {
    bool ok = false;
    const QString words = QInputDialog::getText(
        this, tr("Retake"),
        tr("Which point or reading? (landmark 2, collar, collar_diameter, point 4, reading 4, quick_point 5 2, "
           "node 2 marker 1 3, node 2 midrib_thickness 3)"),
        QLineEdit::Normal, retakeSuggestion(), &ok);
    if (!ok) return;
    if (const QString why = retake(words); !why.isEmpty()) feedback_->setText(tr("✗ %1").arg(why));
  });
  connect(setLeaf_, &QPushButton::clicked, this, [this] {
    acq::LeafChoice c;
    c.kind = m::leafKindFromString(leafKind_->currentText().toStdString());
    c.state = m::leafStateFromString(leafState_->currentText().toStdString());
    c.type = leafType_->currentText().trimmed().toStdString();
    (void)command({.kind = acq::PlantCommand::Kind::Choose, .node = choiceNode(), .choice = c});
  });
  // The GUI thread takes what the capture and preview threads left in their mailboxes at 60 Hz:
  // nothing crosses threads through Qt's event queue (whose lock ThreadSanitizer cannot see).
  poll_.setInterval(15);
  connect(&poll_, &QTimer::timeout, this, [this] {
    applyState();
    applyPreview();
  });
  auto* layout = new QVBoxLayout(this);
  layout->addWidget(banner_);
  layout->addWidget(feedback_);
  layout->addWidget(controls_);
  layout->addWidget(split, 1);
}

QString PlantCaptureView::devicesText() const {
  return devices_->text();
}

int PlantCaptureView::choiceNode() const {
  if (!engine_) return 1;
  const acq::PlantStep step = engine_->step();
  switch (step.what) {
    case acq::PlantWhat::Point:
    case acq::PlantWhat::Reading:
    case acq::PlantWhat::QuickPoint:
    case acq::PlantWhat::Leaf: return step.index;
    case acq::PlantWhat::Done: return std::max(1, engine_->nodes());
    default: return 1;
  }
}

QString PlantCaptureView::retake(const QString& words) {
  acq::PlantCommand c;
  try {
    c = acq::parsePlantCommand("retake " + words.simplified().toStdString());
  } catch (const std::invalid_argument& e) {
    return QString::fromStdString(e.what());
  }
  return command(c) ? QString() : tr("no plant is being captured with the devices");
}

QString PlantCaptureView::retakeSuggestion() const {
  const QTreeWidgetItem* item = tree_->currentItem();
  if (!item) return {};
  const QString text = item->text(0);
  const QTreeWidgetItem* parent = item->parent();
  if (text.startsWith(tr("Landmark ")) && parent) return "landmark " + text.section(' ', 1, 1);
  if (text == tr("Collar")) return "collar";
  if (text.startsWith(tr("Node "))) return "point " + text.section(' ', 1, 1);
  if (text == tr("Leaf") && parent && parent->text(0).startsWith(tr("Node ")))
    return "node " + parent->text(0).section(' ', 1, 1) + " marker 1 1";
  return {};
}

bool PlantCaptureView::setPedal(bool down) {
  std::lock_guard lock(mutex_);
  if (!loop_) return false;
  loop_->setPedal(down);
  return true;
}

bool PlantCaptureView::pedal() const {
  std::lock_guard lock(mutex_);
  return loop_ && loop_->pedal();
}

bool PlantCaptureView::command(const acq::PlantCommand& c) {
  std::lock_guard lock(mutex_);
  if (!loop_) return false;
  loop_->command(c);
  return true;
}

void PlantCaptureView::committed(const acq::PlantFeedback& f, const acq::PlantCaptureSession& s) {
  State state{s.engine(),
              said(f.decision),
              f.decision.kind == Kind::Rejected,
              f.completeSeq.has_value() || s.status() == "complete",
              s.paused(),
              QString::fromStdString(s.pauseReason())};
  if (f.storeRefused) state.feedback = tr("✗ not saved: %1").arg(QString::fromStdString(*f.storeRefused));
  if (f.control == acq::PlantFeedback::Control::Paused)
    state.feedback = tr("⏸ paused: %1").arg(QString::fromStdString(f.paused));
  if (f.control == acq::PlantFeedback::Control::Resumed) state.feedback = tr("▶ resumed");
  {
    std::lock_guard lock(mutex_);
    previewWanted_ = state.engine;
    stateMailbox_ = std::move(state);
  }
  wake_.notify_all();
}

void PlantCaptureView::startThreads(const std::function<void()>& capture) {
  banner_->setText(QString::fromStdString(engine_->prompt()));
  fillTree(*engine_);
  stop_ = false;
  quitPreview_ = false;
  previewer_ = std::thread([this] { previewLoop(); });
  {
    std::lock_guard lock(mutex_);
    previewWanted_ = *engine_;
  }
  wake_.notify_all();
  capture_ = std::thread([this, capture] {
    try {
      capture();
    } catch (const std::exception& e) {
      std::lock_guard lock(mutex_);
      failure_ = QString::fromStdString(e.what());
    }
  });
  poll_.start();
}

void PlantCaptureView::readSession(db::Store& store) {
  // The organ library (approved leaves) shapes the quick leaves; read once, here.
  library_ = acq::organLibrary(store).leaves;
  acq::PlantCaptureSession opened(store, session_);  // refuses what is not an open plant session
  engine_ = opened.engine();
  field_->setText(QString::fromStdString(acq::fieldBanner(store, opened.setup().field, fieldCheckMaxAgeHours_)));
}

QString PlantCaptureView::startWithDevices(const std::string& db, const acq::PlantSessionSetup& setup) {
  if (capture_.joinable()) return tr("A plant is being captured already.");
  std::optional<acq::TipApplied> tip;
  try {
    (void)acq::parseDigitizerSpec(setup.digitizer);  // nothing is written for a spec that does not parse
    (void)acq::parseCaliperSpec(setup.caliper);
    db::Store store(db);
    acq::PlantSessionSetup withField = setup;
    withField.field = acq::resolveFieldCalibration(store, fieldCalibration_);
    acq::attachSentinels(withField.field, std::exchange(sentinels_, std::nullopt));
    // The newest passing tip calibration of this digitizer, as every capture takes it.
    withField.tip = acq::resolveTipCalibration(store, "latest", acq::tipDevice(setup.digitizer, false));
    tip = withField.tip;
    session_ = acq::PlantCaptureSession::create(store, withField);
    readSession(store);
  } catch (const std::exception& e) {
    return QString::fromStdString(e.what());
  }
  // The approved leaves' types, for a quick leaf to take its shape from one of them.
  std::set<QString> types;
  for (const m::LibraryLeaf& l : library_)
    if (!l.markers.leaf.type.empty()) types.insert(QString::fromStdString(l.markers.leaf.type));
  leafType_->clear();
  leafType_->addItem(QString());
  for (const QString& t : types) leafType_->addItem(t);
  controls_->show();
  // The stylus' tip the session keeps: the link turns every sample to it.
  const std::string digitizer = acq::withTip(setup.digitizer, tip);
  const std::string caliper = setup.caliper;
  startThreads([this, db, digitizer, caliper] {
    db::Store store(db);
    acq::PlantCaptureLoop loop(store, session_);
    {
      std::lock_guard lock(mutex_);
      loop_ = &loop;
    }
    if (stop_) loop.stop();
    try {
      acq::DeviceSet ports(digitizer, caliper, loop.sinks([this](const devices::DeviceStatus& st) {
        std::lock_guard lock(mutex_);
        deviceStates_[st.device] = std::string(devices::toString(st.state)) +
                                   (st.message.empty() ? "" : ": " + st.message) +
                                   (st.remedy.empty() ? "" : " (" + st.remedy + ")");
        devicesChanged_ = true;
      }));
      ports.start();
      (void)loop.run({[this](const acq::PlantFeedback& f, const acq::PlantCaptureSession& s) { committed(f, s); }});
      ports.stop();
    } catch (...) {
      std::lock_guard lock(mutex_);
      loop_ = nullptr;
      throw;
    }
    std::lock_guard lock(mutex_);
    loop_ = nullptr;
  });
  return {};
}

PlantCaptureView::~PlantCaptureView() {
  stop();
}

QString PlantCaptureView::bannerText() const {
  return banner_->text();
}
QString PlantCaptureView::feedbackText() const {
  return feedback_->text();
}
QString PlantCaptureView::fieldText() const {
  return field_->text();
}

QString PlantCaptureView::summaryText() const {
  return summary_->text();
}

QString PlantCaptureView::startSimulated(const std::string& db, const std::string& plantMarkersFile,
                                         const acq::SimulationOptions& simulation, const std::string& operatorName,
                                         const std::string& station, std::int64_t resume,
                                         const m::PlantProtocol& protocol) {
  if (capture_.joinable()) return tr("A plant is being captured already.");
  try {
    db::Store store(db);
    if (resume == 0) {
      acq::PlantSessionSetup setup = acq::simulatedPlantSetup(m::readPlantMarkersFile(plantMarkersFile));
      if (simulation.referenceReceiver) setup.digitizer += ",reference=2";  // kept with the session
      setup.protocol = protocol;
      setup.project = "default";
      setup.operatorName = operatorName;
      setup.station = station;
      setup.field = acq::resolveFieldCalibration(store, fieldCalibration_);
      acq::attachSentinels(setup.field, std::exchange(sentinels_, std::nullopt));
      setup.tip = acq::resolveTipCalibration(store, "latest", acq::tipDevice(setup.digitizer, true));
      session_ = acq::PlantCaptureSession::create(store, setup);
    } else {
      session_ = resume;
    }
    readSession(store);
  } catch (const std::exception& e) {
    return QString::fromStdString(e.what());
  }
  controls_->hide();  // the virtual technician decides for itself
  startThreads([this, db, simulation] {
    db::Store store(db);
    (void)acq::runSimulatedPlant(
        store, session_, simulation,
        [this](const acq::PlantFeedback& f, const acq::PlantCaptureSession& s) { committed(f, s); }, stop_);
  });
  return {};
}

void PlantCaptureView::stop() {
  stop_ = true;
  {
    std::lock_guard lock(mutex_);
    if (loop_) loop_->stop();
  }
  if (capture_.joinable()) capture_.join();
  {
    std::lock_guard lock(mutex_);
    quitPreview_ = true;
  }
  wake_.notify_all();
  if (previewer_.joinable()) previewer_.join();
  poll_.stop();
  // What the threads left in the mailboxes is shown (the last decision, the last preview).
  applyState();
  applyPreview();
}

void PlantCaptureView::previewLoop() {
  acq::PlantPreviewer previewer(library_);  // a finished leaf is meshed once
  for (;;) {
    std::optional<acq::PlantEngine> engine;
    {
      std::unique_lock lock(mutex_);
      wake_.wait(lock, [this] { return quitPreview_ || previewWanted_.has_value(); });
      if (quitPreview_) return;
      engine.swap(previewWanted_);
    }
    acq::PlantPreview built = previewer.build(*engine);
    {
      std::lock_guard lock(mutex_);
      previewMailbox_ = std::move(built);
    }
  }
}

void PlantCaptureView::applyState() {
  std::optional<State> state;
  QString failure;
  {
    std::lock_guard lock(mutex_);
    state.swap(stateMailbox_);
    failure = failure_;
  }
  if (!failure.isEmpty()) feedback_->setText(tr("The capture stopped: %1").arg(failure));
  {
    std::lock_guard lock(mutex_);
    if (devicesChanged_) {
      QStringList lines;
      for (const auto& [device, words] : deviceStates_)
        lines << QString::fromStdString(device) + ": " + QString::fromStdString(words);
      devices_->setText(lines.join("\n"));
      devicesChanged_ = false;
    }
  }
  if (!state) return;
  engine_ = std::move(state->engine);
  paused_ = state->paused;
  pause_->setText(paused_ ? tr("Resume") : tr("Pause"));
  banner_->setText(paused_ ? tr("PAUSED · %1 · Resume to go on at: %2")
                                 .arg(state->pauseReason, QString::fromStdString(engine_->prompt()))
                           : QString::fromStdString(engine_->prompt()));
  if (!state->feedback.isEmpty()) {
    feedback_->setText(state->feedback);
    feedback_->setStyleSheet(state->rejected ? "color: #b00020" : "color: #1b5e20");
  }
  fillTree(*engine_);
  setLeaf_->setText(tr("Set node %1's leaf").arg(choiceNode()));
  emit stepChanged(banner_->text(), state->rejected);
  if (state->complete && !complete_) {
    complete_ = true;
    review_->setEnabled(true);
    emit plantComplete();
  }
}

void PlantCaptureView::applyPreview() {
  std::optional<acq::PlantPreview> p;
  {
    std::lock_guard lock(mutex_);
    p.swap(previewMailbox_);
  }
  if (!p) return;
  acq::Snapshot plant;
  plant.session = session_;
  plant.items = p->points;
  auto mesh = std::make_shared<acq::Preview>();
  mesh->mesh = p->mesh;
  plant.preview = std::move(mesh);
  plantPreview_->show(plant);
  if (p->leaf) {
    acq::Snapshot leaf;
    leaf.session = session_;
    leaf.items = p->leafItems;
    leaf.preview = p->leaf;
    leafPreview_->show(leaf);
    leafPane_->findChild<QLabel*>("leafTitle")->setText(tr("Node %1 · the full leaf being taken").arg(p->leafNode));
    leafPane_->show();
    ++leafPreviewsShown_;
  } else {
    leafPane_->setMaximumWidth(480);
    leafPane_->hide();
  }
  ++previewsShown_;
  QString text = tr("Plant session %1 · %2 node(s) · %3 leaf/leaves drawn%4")
                     .arg(session_)
                     .arg(engine_ ? engine_->nodes() : 0)
                     .arg(p->leaves)
                     .arg(p->inPlantFrame ? tr(" · in the plant frame (collar at the origin, +Z up)")
                                          : tr(" · in the digitizer's frame"));
  for (const std::string& note : p->notes) text += "\n" + QString::fromStdString(note);
  summary_->setText(text);
  shown_ = std::move(p);
}

void PlantCaptureView::fillTree(const acq::PlantEngine& e) {
  tree_->clear();
  const acq::PlantStep step = e.step();
  QTreeWidgetItem* current = nullptr;
  auto* landmarks = new QTreeWidgetItem(tree_, {tr("Landmarks")});
  int taken = 0;
  for (const acq::PlantItem& i : e.items())
    if (i.what == acq::PlantWhat::Landmark) {
      auto* l = new QTreeWidgetItem(landmarks, {tr("Landmark %1").arg(i.index), tr("taken")});
      ++taken;
      if (step.what == acq::PlantWhat::Landmark && step.index == i.index) current = l;
    }
  landmarks->setText(1, tr("%1 taken").arg(taken));
  if (step.what == acq::PlantWhat::Landmark && !current) current = landmarks;
  // The transmitter's positions once it was moved: each fitted one's residual, and the one
  // whose landmarks are being taken again.
  const int positions = static_cast<int>(e.toFirst().size());
  if (positions > 1 || e.relocating() > 0) {
    auto* transmitter = new QTreeWidgetItem(tree_, {tr("Transmitter")});
    for (int r = 1; r < positions; ++r) {
      const acq::RelocationFit fit = e.fitOf(r);
      (void)new QTreeWidgetItem(transmitter,
                                {tr("Position %1").arg(r + 1),
                                 tr("RMS %1 mm, worst %2 mm").arg(fit.rmsMm, 0, 'f', 2).arg(fit.worstMm, 0, 'f', 2)});
    }
    if (e.relocating() > 0) {
      int again = 0;
      for (const acq::PlantItem& i : e.items())
        again += i.what == acq::PlantWhat::LandmarkAgain && i.frame == e.relocating();
      current = new QTreeWidgetItem(
          transmitter, {tr("Position %1").arg(e.relocating() + 1), tr("moved: %1 landmarks taken again").arg(again)});
    }
    transmitter->setText(1, e.relocating() > 0 ? tr("moved: landmarks again") : tr("position %1").arg(positions));
    transmitter->setExpanded(true);
  }
  auto* collar = new QTreeWidgetItem(tree_, {tr("Collar")});
  for (const acq::PlantItem& i : e.items()) {
    if (i.what == acq::PlantWhat::Collar && collar->text(1).isEmpty()) collar->setText(1, tr("taken"));
    if (i.what == acq::PlantWhat::CollarDiameter) collar->setText(1, "Ø " + mm(i.valueMm));
  }
  if (step.what == acq::PlantWhat::Collar || step.what == acq::PlantWhat::CollarDiameter) current = collar;
  const int next = step.what == acq::PlantWhat::Point && step.part == 1 ? step.index : 0;
  const int nodes = std::max(e.nodes(), next);
  // A branch's nodes hang under the stem node that bears it, in the order taken.
  bool branched = false;
  for (const m::ProtocolEntity& entity : e.protocol().entities)
    branched = branched || (!entity.leaf && entity.order == 2);
  branch_->setVisible(branched);
  std::map<int, QTreeWidgetItem*> nodeItems;
  for (int node = 1; node <= nodes; ++node) {
    const m::NodeLink where = e.link(node);
    QTreeWidgetItem* bearer = where.order > 1 ? nodeItems[e.link(where.axis).parent] : nullptr;
    auto* n = bearer ? new QTreeWidgetItem(bearer, {tr("Node %1").arg(node)})
                     : new QTreeWidgetItem(tree_, {tr("Node %1").arg(node)});
    nodeItems[node] = n;
    if (where.order > 1) {
      n->setToolTip(0, tr("on the branch from node %1").arg(e.link(where.axis).parent));
      if (bearer) bearer->setExpanded(true);
    }
    QString measured = node > e.nodes() ? tr("next") : tr("point taken");
    for (const acq::PlantItem& i : e.items())
      if (i.what == acq::PlantWhat::Reading && i.index == node) measured = "Ø " + mm(i.valueMm);
    n->setText(1, measured);
    auto* leaf = new QTreeWidgetItem(n, {tr("Leaf"), leafText(e, node)});
    leaf->setToolTip(1, leaf->text(1));  // whole, where the column cuts it
    const bool here = step.what != acq::PlantWhat::Done && step.what != acq::PlantWhat::Landmark &&
                      step.what != acq::PlantWhat::Collar && step.what != acq::PlantWhat::CollarDiameter &&
                      step.index == node;
    if (here) {
      const bool onLeaf = step.what == acq::PlantWhat::Leaf || step.what == acq::PlantWhat::QuickPoint;
      current = onLeaf ? leaf : n;
      n->setExpanded(true);
    }
  }
  if (current) {
    QFont bold = current->font(0);
    bold.setBold(true);
    current->setFont(0, bold);
    current->setFont(1, bold);
    current->setSelected(true);
    tree_->setCurrentItem(current);
    tree_->scrollToItem(current);
  }
  if (step.what == acq::PlantWhat::Done) tree_->expandAll();
  tree_->resizeColumnToContents(0);  // "Landmarks", bold when current, is never cut
}

}  // namespace leafdig::station
