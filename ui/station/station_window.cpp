#include "station_window.hpp"

#include <QApplication>
#include <QHBoxLayout>
#include <QKeyEvent>
#include <QKeySequence>
#include <QMenu>
#include <QMessageBox>
#include <QPushButton>
#include <QScreen>
#include <QShortcut>
#include <QSplitter>
#include <QStatusBar>
#include <QTime>
#include <QToolBar>
#include <QVBoxLayout>
#include <filesystem>
#include <fstream>
#include <utility>

#include "capture/setup_dialog.hpp"
#include "dialogs/settings_dialog.hpp"
#include "field/field_view.hpp"
#include "leafdig/acquisition/field/field_applied.hpp"
#include "leafdig/acquisition/review/review.hpp"
#include "leafdig/db/lab.hpp"
#include "leafdig/devices/transports/registry.hpp"
#include "leafdig/model/leaf/markers_json.hpp"
#include "leafdig/version.hpp"
#include "plant/plant_capture_view.hpp"
#include "plant/plant_setup_dialog.hpp"
#include "plant/plant_view.hpp"
#include "review/export_dialog.hpp"
#include "review/review_view.hpp"

namespace leafdig::station {
namespace acq = leafdig::acquisition;
using Role = acq::DeviceSet::Role;

StationWindow::StationWindow(StationOptions options, QWidget* parent)
    : QMainWindow(parent), options_(std::move(options)) {
  if (options_.settingsFile.isEmpty()) options_.settingsFile = defaultSettingsFile();
  settings_ = StationSettings::load(options_.settingsFile);
  setWindowTitle(QStringLiteral("leafdig station %1").arg(QString::fromLatin1(kVersion)));
  sounds_ = new Sounds(this, options_.audio);
  tabs_ = new QTabWidget(this);
  tabs_->setFocusPolicy(Qt::NoFocus);
  tabs_->addTab(buildCaptureTab(), tr("Capture"));
  review_ = new ReviewView(settings_, tabs_);
  tabs_->addTab(review_, tr("Review"));
  plant_ = new PlantView(tabs_);
  plant_->setDatabase(dbPath());
  // A curator reviews a station's file without starting a capture (issue 49): the Review tab
  // opens it at once when it is there (the lab server is opened by reviewLabServer).
  if (!db::isServerUrl(dbPath()) && std::filesystem::exists(dbPath())) review_->setDatabase(dbPath());
  tabs_->addTab(plant_, tr("Plant"));
  fieldView_ = new FieldView(tabs_);
  tabs_->addTab(fieldView_, tr("Field"));
  updateFieldSource();
  connect(tabs_, &QTabWidget::currentChanged, this, [this](int index) {
    if (tabs_->widget(index) == plant_) plant_->refreshLibrary();  // leaves approved since
  });
  setCentralWidget(tabs_);
  // As large as the screen allows, up to 1440 × 900: a 1366 × 768 laptop gets all of it.
  const QSize room = screen() ? screen()->availableGeometry().size() : QSize(1280, 860);
  resize(std::min(1440, room.width()), std::min(900, room.height()));
  buildToolBar();
  connectPreviewAndTimers();
  qApp->installEventFilter(this);
  applySettings(settings_);
}

// The Capture tab: the banner, the feedback line, the device chips, the steps beside the
// leaf's schematic, and the live preview.
QWidget* StationWindow::buildCaptureTab() {
  auto* capture = new QWidget(tabs_);
  auto* outer = new QVBoxLayout(capture);
  banner_ = new QLabel(tr("Starting…"), capture);
  QFont big = banner_->font();
  big.setPointSizeF(big.pointSizeF() * 2.2);
  big.setBold(true);
  banner_->setFont(big);
  banner_->setWordWrap(true);
  banner_->setObjectName("banner");
  banner_->setStyleSheet("QLabel#banner { background: #1f3b57; color: white; padding: 12px; border-radius: 6px; }");
  outer->addWidget(banner_);
  auto* info = new QHBoxLayout;
  feedback_ = new QLabel(capture);
  feedback_->setWordWrap(true);  // a long reason wraps; it never widens the window
  QFont mid = feedback_->font();
  mid.setPointSizeF(mid.pointSizeF() * 1.3);
  feedback_->setFont(mid);
  lastPoint_ = new QLabel(capture);
  lastPoint_->setFont(mid);
  lastPoint_->setAlignment(Qt::AlignRight | Qt::AlignVCenter);
  info->addWidget(feedback_, 1);
  info->addWidget(lastPoint_);
  outer->addLayout(info);
  chipRow_ = new QWidget(capture);
  auto* chipLayout = new QHBoxLayout(chipRow_);
  chipLayout->setContentsMargins(0, 0, 0, 0);
  chip(Role::Digitizer);
  chip(Role::Caliper);
  chipLayout->addStretch(1);
  // The field the capture goes through (acquisition::fieldBanner): corrected by which check, or
  // not, and whether the field was checked within the settings' age.
  field_ = new QLabel(chipRow_);
  field_->setObjectName("field");
  field_->setWordWrap(true);
  chipLayout->addWidget(field_, 2);
  outer->addWidget(chipRow_);
  auto* split = new QSplitter(capture);
  auto* left = new QSplitter(Qt::Vertical, split);
  schematic_ = new LeafSchematic(left);
  steps_ = new QListWidget(left);
  steps_->setObjectName("steps");
  steps_->setFocusPolicy(Qt::NoFocus);  // focus is never trapped: keys go to the window
  // A long step wraps onto a second line instead of being cut off.
  steps_->setWordWrap(true);
  steps_->setTextElideMode(Qt::ElideNone);
  steps_->setHorizontalScrollBarPolicy(Qt::ScrollBarAlwaysOff);
  steps_->setResizeMode(QListView::Adjust);
  left->setMinimumWidth(260);
  preview_ = new PreviewWidget(split);
  split->addWidget(left);
  split->addWidget(preview_);
  split->setStretchFactor(1, 1);
  outer->addWidget(split, 1);
  return capture;
}

// New session, Export, Settings, Sync with lab and Sound; none takes the keyboard's focus.
void StationWindow::buildToolBar() {
  auto* bar = addToolBar(tr("Station"));
  bar->setMovable(false);
  bar->setFocusPolicy(Qt::NoFocus);
  bar->addAction(tr("New session…"), this, [this] { (void)newSessionDialog(); });
  bar->addAction(tr("New plant…"), this, [this] { (void)newPlantDialog(); });
  bar->addAction(tr("Export…"), this, [this] {
    ExportDialog d(settings_, this);
    if (sessionId_ > 0) d.setSessions({sessionId_});
    if (d.exec() == QDialog::Accepted) d.run(dbPath());
  });
  bar->addAction(tr("Settings…"), this, [this] {
    SettingsDialog d(settings_, this);
    if (d.exec() == QDialog::Accepted) {
      applySettings(d.result());
      settings_.save(options_.settingsFile);
    }
  });
  syncAction_ = bar->addAction(tr("Sync with lab"), this, [this] { syncWithLab(); });
  syncAction_->setToolTip(tr("Send this station's sessions to the lab server and take the curators' decisions in"));
  connect(&syncTimer_, &QTimer::timeout, this, [this] { syncWithLab(); });
  QAction* mute = bar->addAction(tr("Sound"));
  mute->setCheckable(true);
  mute->setChecked(settings_.sounds);
  connect(mute, &QAction::toggled, this, [this](bool on) {
    settings_.sounds = on;
    sounds_->setMuted(!on);
    settings_.save(options_.settingsFile);
  });
  for (QAction* a : bar->actions())
    if (QWidget* w = bar->widgetForAction(a)) w->setFocusPolicy(Qt::NoFocus);
}

// Picking an item in the preview selects it for a retake; the device chips refresh at 10 Hz
// and the stylus cursor at 30 Hz.
void StationWindow::connectPreviewAndTimers() {
  preview_->setFocusPolicy(Qt::NoFocus);
  connect(preview_, &PreviewWidget::itemPicked, this, [this](const acq::Item& item) {
    retakeTarget_ = item;
    preview_->setHighlight(item);
    feedback_->setText(tr("Selected %1 (row %2, point %3): %4 retakes it")
                           .arg(QString::fromLatin1(acq::toString(item.what)))
                           .arg(item.row)
                           .arg(item.col)
                           .arg(settings_.shortcuts[Action::Retake].toString(QKeySequence::NativeText)));
  });
  connect(&deviceTimer_, &QTimer::timeout, this, &StationWindow::refreshDevices);
  connect(&cursorTimer_, &QTimer::timeout, this, &StationWindow::refreshCursor);
  connect(&mailboxTimer_, &QTimer::timeout, this, &StationWindow::takeSnapshot);
  mailboxTimer_.start(5);
  deviceTimer_.start(100);
  cursorTimer_.start(33);  // the cursor follows the latest sample at ~30 Hz, never each one
}

StationWindow::~StationWindow() {
  qApp->removeEventFilter(this);
  stopCapture();
  if (syncThread_.joinable()) syncThread_.join();  // its result is posted to this window: wait for it
}

void StationWindow::syncWithLab() {
  const std::string url = settings_.labUrl.toStdString();
  if (url.empty() || syncing_ || db::isServerUrl(dbPath())) return;
  if (syncThread_.joinable()) syncThread_.join();
  syncing_ = true;
  syncAction_->setEnabled(false);
  statusBar()->showMessage(tr("Lab: syncing with %1…").arg(QString::fromStdString(db::redactUrl(url))));
  // The thread has its own connections to the file (SQLite lets it read beside the capture,
  // and its few writes wait for the capture's) and to the server; it touches nothing of the
  // window and hands its words back through the event loop.
  syncThread_ = std::thread([this, url, path = dbPath()] {
    QString text;
    try {
      db::PushReport pushed;
      {
        db::Store local(path, true);
        pushed = db::push(local, url);
      }
      db::Store local(path);
      db::SyncOptions options;
      options.replays = acq::requireReplays;
      const db::PullReport pulled = db::pull(local, url, options);
      text = tr("Lab: sent %1 event(s) of %2 session(s), took in %3 decision event(s)")
                 .arg(pushed.eventsSent)
                 .arg(pushed.sessionsSeen)
                 .arg(pulled.eventsTaken);
      std::vector<db::SyncProblem> problems = pushed.problems;
      problems.insert(problems.end(), pulled.problems.begin(), pulled.problems.end());
      if (!problems.empty())
        text += tr("; %1 session(s) not synced, e.g. %2:%3: %4")
                    .arg(problems.size())
                    .arg(QString::fromStdString(problems.front().station))
                    .arg(problems.front().stationSessionId)
                    .arg(QString::fromStdString(problems.front().problem));
    } catch (const db::StoreError& e) {
      text = tr("Lab: not synced: %1 (%2)").arg(QString::fromStdString(e.what()), QString::fromStdString(e.remedy()));
    } catch (const std::exception& e) {
      text = tr("Lab: not synced: %1").arg(QString::fromStdString(e.what()));
    }
    QMetaObject::invokeMethod(
        this,
        [this, text] {
          labStatus_ = text + QStringLiteral(" · ") + QTime::currentTime().toString("HH:mm");
          statusBar()->showMessage(labStatus_);
          syncAction_->setEnabled(!settings_.labUrl.isEmpty());
          review_->setDatabase(dbPath());  // (opens it if the review had not yet)
          review_->refreshSessions();      // decisions taken in show at once
          syncing_ = false;
        },
        Qt::QueuedConnection);
  });
}

void StationWindow::applySettings(const StationSettings& s) {
  settings_ = s;
  sounds_->setMuted(!s.sounds);
  sounds_->setVolume(s.volume);
  if (auto* app = qobject_cast<QApplication*>(QApplication::instance())) applyTheme(*app, s);
  review_->setSettings(s);
  plant_->setConfirmMoveAboveMm(s.confirmMoveAboveMm);
  buildShortcuts();
  syncAction_->setEnabled(!s.labUrl.isEmpty() && !syncing_);
  if (!s.labUrl.isEmpty() && s.labSyncMinutes > 0)
    syncTimer_.start(s.labSyncMinutes * 60 * 1000);
  else
    syncTimer_.stop();
}

void StationWindow::buildShortcuts() {
  for (QObject* o : shortcutObjects_) delete o;
  shortcutObjects_.clear();
  for (const auto& [action, key] : settings_.shortcuts) {
    if (action == Action::Accept || key.isEmpty()) continue;  // Accept is held: see eventFilter
    auto* s = new QShortcut(key, this);
    s->setContext(Qt::WindowShortcut);
    const Action a = action;
    connect(s, &QShortcut::activated, this, [this, a] { runAction(a); });
    shortcutObjects_.push_back(s);
  }
  // U undoes too (the key printed on the station's label), unless it is assigned elsewhere.
  bool uTaken = false;
  for (const auto& [action, key] : settings_.shortcuts) uTaken = uTaken || key == QKeySequence(Qt::Key_U);
  if (!uTaken) {
    auto* s = new QShortcut(QKeySequence(Qt::Key_U), this);
    connect(s, &QShortcut::activated, this, [this] { runAction(Action::Undo); });
    shortcutObjects_.push_back(s);
  }
}

bool StationWindow::eventFilter(QObject* watched, QEvent* event) {
  // The Accept key (a foot pedal) held down is the stylus button: press → button down,
  // release → up, and the engine decides on release as it does for the stylus.
  // Only keys meant for this window count (not a dialog's Enter): their widget is in it.
  // The same on the plant capture tab, for a plant taken with the devices.
  const bool leafTab = run_ && tabs_->currentIndex() == 0;
  const bool plantTab = plantCapture_ && tabs_->currentWidget() == plantCapture_;
  if ((event->type() == QEvent::KeyPress || event->type() == QEvent::KeyRelease) && (leafTab || plantTab) &&
      watched->isWidgetType() && static_cast<QWidget*>(watched)->window() == this) {
    auto* k = static_cast<QKeyEvent*>(event);
    const QKeySequence accept = settings_.shortcuts[Action::Accept];
    if (!k->isAutoRepeat() && !accept.isEmpty() && QKeySequence(k->keyCombination()) == accept) {
      const bool down = event->type() == QEvent::KeyPress;
      if (leafTab) {
        run_->setPedal(down);
        return true;
      }
      if (plantCapture_->setPedal(down)) return true;
    }
  }
  return QMainWindow::eventFilter(watched, event);
}

void StationWindow::runAction(Action a) {
  if (tabs_->currentIndex() != 0) return;  // capture keys act on the capture only
  acq::Command c;
  switch (a) {
    case Action::Accept: return;
    case Action::Undo: c.kind = acq::Command::Kind::Undo; break;
    case Action::EndRows: c.kind = acq::Command::Kind::EndRows; break;
    case Action::Pause:
      c.kind = acq::Command::Kind::Pause;
      c.text = "paused at the station";
      break;
    case Action::Resume: c.kind = acq::Command::Kind::Resume; break;
    case Action::MoveTransmitter: c.kind = acq::Command::Kind::MoveTransmitter; break;
    case Action::Retake:
      if (!retakeTarget_) {
        feedback_->setText(tr("Click the marker to retake in the 3D view first"));
        return;
      }
      c.kind = acq::Command::Kind::Retake;
      c.what = retakeTarget_->what;
      c.row = retakeTarget_->row;
      c.col = retakeTarget_->col;
      retakeTarget_.reset();
      preview_->setHighlight(std::nullopt);
      break;
  }
  command(c);
}

void StationWindow::command(acq::Command c) {
  if (run_) run_->command(c);
}

std::string StationWindow::dbPath() const {
  return options_.db.empty() ? db::Store::defaultPath() : options_.db;
}

std::vector<db::SessionInfo> StationWindow::interruptedSessions() const {
  std::vector<db::SessionInfo> out;
  try {
    if (!std::ifstream(dbPath()).good()) return out;
    db::Store store(dbPath(), true);
    const std::string station = options_.setup.station.empty() ? acq::thisStation() : options_.setup.station;
    for (const auto& s : store.sessions())
      if (s.kind == "leaf" && s.status == "open" && (station.empty() || s.station == station)) out.push_back(s);
  } catch (const std::exception&) {
    // An unreadable store is reported by start().
  }
  return out;
}

void StationWindow::offerResume() {
  const auto open = interruptedSessions();
  if (open.empty() || options_.resume > 0) return;
  const db::SessionInfo& s = open.back();
  QMessageBox box(QMessageBox::Question, tr("leafdig · interrupted session"),
                  tr("Session %1 (%2 / %3 / leaf %4, operator %5, %6 events) was not finished.\n\nResume it at the "
                     "step where it stopped?")
                      .arg(s.id)
                      .arg(QString::fromStdString(s.project), QString::fromStdString(s.plant))
                      .arg(s.leafPosition)
                      .arg(QString::fromStdString(s.operatorName))
                      .arg(s.headSeq),
                  QMessageBox::NoButton, this);
  QPushButton* resume = box.addButton(tr("Resume session %1").arg(s.id), QMessageBox::AcceptRole);
  box.addButton(tr("Start a new session"), QMessageBox::RejectRole);
  box.setDefaultButton(resume);
  box.setObjectName("resumePrompt");
  box.exec();
  if (box.clickedButton() == resume) options_.resume = s.id;
}

bool StationWindow::newPlantDialog() {
  std::vector<db::SessionInfo> known;
  try {
    if (std::ifstream(dbPath()).good()) known = db::Store(dbPath(), true).sessions();
  } catch (const std::exception&) {
  }
  acq::PlantSessionSetup defaults;
  defaults.project = options_.setup.project;
  defaults.operatorName = options_.setup.operatorName;
  defaults.plant = options_.setup.plant;
  // The sample plant beside the sample leaves (the source tree, or where the package put them).
  const std::string samples = leafdig::samplesDir();
  const std::string data =
      samples.empty() ? leafdig::sourceDataDir() : std::filesystem::path(samples).parent_path().string();
  const QString sample = QString::fromStdString(data + "/plants/sample.plant-markers.json");
  PlantSetupDialog d(defaults, known, devices::takeInventory(), sample, this);
  if (d.exec() != QDialog::Accepted) return false;
  const auto c = d.choice();
  if (!c) return false;
  stopCapture();
  options_.setup.project = c->setup.project;
  options_.setup.operatorName = c->setup.operatorName;
  if (c->simulated) options_.referenceReceiver = c->referenceReceiver;  // the pot stays as --pot-turn says
  return c->simulated ? startPlantCapture(c->plantMarkers, c->setup.protocol) : startPlantCaptureWithDevices(c->setup);
}

bool StationWindow::newSessionDialog() {
  std::vector<db::SessionInfo> known;
  try {
    if (std::ifstream(dbPath()).good()) known = db::Store(dbPath(), true).sessions();
  } catch (const std::exception&) {
  }
  acq::SessionSetup defaults = options_.setup;
  defaults.settings = settings_.engine;
  defaults.settings.mode = options_.setup.settings.mode;
  defaults.settings.order = options_.setup.settings.order;
  defaults.simulated = options_.simulate;
  if (sessionId_ > 0) defaults.leafPosition = options_.setup.leafPosition + 1;  // the next leaf up
  SetupDialog d(defaults, known, devices::takeInventory(), this);
  if (d.exec() != QDialog::Accepted) return false;
  const auto c = d.choice();
  if (!c) return false;
  stopCapture();
  options_.setup = c->setup;
  options_.simulate = c->simulatedDigitizer;
  options_.resume = 0;
  return start();
}

void StationWindow::reviewLabServer() {
  const QString where = QString::fromStdString(db::redactUrl(options_.db));
  banner_->setText(tr("Reviewing the lab server %1. Capture writes this station's own file: start the station "
                      "without --db postgresql://… to capture.")
                       .arg(where));
  review_->setDatabase(options_.db);
  tabs_->setCurrentWidget(review_);
  statusBar()->showMessage(tr("lab server %1").arg(where));
}

bool StationWindow::capturesIntoStationFile() {
  if (!db::isServerUrl(dbPath())) return true;
  banner_->setText(
      tr("Cannot capture into the lab server: capture writes this station's own file, and "
         "'leafdig sync push' sends it. Leave out --db postgresql://… to capture."));
  return false;
}

void StationWindow::updateFieldSource() {
  FieldSource f;
  f.db = dbPath();
  f.station = options_.setup.station;
  if (!options_.setup.operatorName.empty()) f.operatorName = options_.setup.operatorName;
  f.simulate = options_.simulate;
  f.simulation.speed = options_.speed;
  f.simulation.seed = options_.seed;
  f.simulation.distortion = options_.distortion;
  f.digitizer = options_.setup.digitizer;
  fieldView_->setSource(f);
}

bool StationWindow::sentinelsFirst(const std::function<void()>& then) {
  if (settings_.sentinels == 0 || options_.fieldCalibration.empty() || options_.fieldCalibration == "none")
    return false;
  updateFieldSource();
  QString error;
  try {
    const auto resolved = acq::resolveFieldCheck(db::Store(dbPath(), true), options_.fieldCalibration);
    if (resolved) {
      const std::int64_t id = resolved->check.id;
      error = fieldView_->startSentinels(resolved->check, settings_.sentinels, [this, then, id](auto held) {
        if (!held) {
          banner_->setText(tr("The sentinel divots were stopped: no capture began."));
        } else if (held->moved()) {
          banner_->setText(
              tr("Not started: %1. The Field tab checks the field again.").arg(QString::fromStdString(held->words())));
          sounds_->play(Cue::Reject);
        } else {
          sentinels_ = std::move(held);
          statusBar()->showMessage(tr("sentinel divots of field check %1 held").arg(id));
          then();
        }
      });
    }
  } catch (const std::exception& e) {
    error = QString::fromStdString(e.what());
  }
  if (!error.isEmpty()) {
    banner_->setText(tr("Cannot start: %1").arg(error));
    return true;
  }
  banner_->setText(
      tr("Before the first leaf: touch the sentinel divots the Field tab asks for (the jig where it lay "
         "for the check)."));
  tabs_->setCurrentWidget(fieldView_);
  return true;
}

bool StationWindow::start() {
  if (!capturesIntoStationFile()) return false;
  stopCapture();
  run_.reset();
  {
    const std::lock_guard lock(mailboxMutex_);
    mailbox_.reset();  // a snapshot of the previous run not yet applied
  }
  last_.reset();
  lastState_.clear();
  try {
    acq::RunRequest r;
    r.db = dbPath();
    r.resume = options_.resume;
    r.setup = options_.setup;
    if (options_.resume == 0) {
      acq::Settings e = settings_.engine;  // tolerances and stillness from the station's settings
      e.mode = r.setup.settings.mode;
      e.order = r.setup.settings.order;
      e.boardFrame = r.setup.settings.boardFrame;
      r.setup.settings = e;
    }
    r.setup.simulated = options_.simulate;
    r.simulation.speed = options_.speed;
    r.simulation.seed = options_.seed;
    r.simulation.distortion = options_.distortion;
    if (options_.resume == 0 && options_.fieldCalibration != "none") r.fieldCalibration = options_.fieldCalibration;
    if (options_.resume == 0 && sentinels_) {
      r.sentinels = std::exchange(sentinels_, std::nullopt);
      r.fieldCalibration = std::to_string(r.sentinels->checkId);
    } else if (options_.resume == 0 && sentinelsFirst([this] { (void)start(); })) {
      return true;
    }
    r.leafFile = options_.markers;
    acq::RunObserver observer;
    // Called on the capture thread: hand over to the UI thread.
    observer.onFeedback = [this](const acq::Feedback& f) {
      QMetaObject::invokeMethod(
          this, [this, f] { applyFeedback(f); }, Qt::QueuedConnection);
    };
    observer.onSnapshot = [this](const acq::Snapshot& s) { postSnapshot(s); };
    run_ = std::make_unique<acq::CaptureRun>(r, observer);
    sessionId_ = run_->sessionId();
    run_->start();
    statusBar()->showMessage(QStringLiteral("session %1 · %2 · %3")
                                 .arg(sessionId_)
                                 .arg(QString::fromStdString(run_->dbPath()))
                                 .arg(run_->simulated() ? tr("simulated devices") : tr("devices")));
    review_->setDatabase(run_->dbPath());
    plant_->setDatabase(run_->dbPath());
    field_->setText(QString::fromStdString(
        acq::fieldBanner(db::Store(run_->dbPath(), true), run_->setup().field, settings_.fieldCheckMaxAgeHours)));
    tabs_->setCurrentIndex(0);
    return true;
  } catch (const std::exception& e) {
    run_.reset();
    banner_->setText(tr("Cannot start: %1").arg(QString::fromStdString(e.what())));
    return false;
  }
}

void StationWindow::stopCapture() {
  if (run_) (void)run_->shutdown("capture stopped at the station");
  if (plantCapture_) plantCapture_->stop();
}

PlantCaptureView* StationWindow::plantCaptureTab() {
  if (!plantCapture_) {
    plantCapture_ = new PlantCaptureView(tabs_);
    tabs_->insertTab(1, plantCapture_, tr("Plant capture"));
    connect(plantCapture_, &PlantCaptureView::stepChanged, this,
            [this](const QString&, bool rejected) { sounds_->play(rejected ? Cue::Reject : Cue::Accept); });
    connect(plantCapture_, &PlantCaptureView::reviewRequested, this, [this](std::int64_t id) {
      tabs_->setCurrentWidget(plant_);  // lists the plant sessions again
      const QString error = plant_->openCapturedPlant(id);
      if (!error.isEmpty()) statusBar()->showMessage(error);
    });
  }
  tabs_->setCurrentWidget(plantCapture_);
  return plantCapture_;
}

bool StationWindow::startPlantCapture(const std::string& plantMarkers, const model::PlantProtocol& protocol) {
  if (!capturesIntoStationFile()) return false;
  if (!sentinels_ &&
      sentinelsFirst([this, plantMarkers, protocol] { (void)startPlantCapture(plantMarkers, protocol); }))
    return true;
  plantCaptureTab()->setFieldCalibration(sentinels_ ? std::to_string(sentinels_->checkId) : options_.fieldCalibration);
  plantCapture_->setSentinels(std::exchange(sentinels_, std::nullopt));
  plantCaptureTab()->setFieldCheckMaxAgeHours(settings_.fieldCheckMaxAgeHours);
  acq::SimulationOptions sim;
  sim.speed = options_.speed;
  sim.seed = options_.seed;
  sim.mistakes = false;
  sim.referenceReceiver = options_.referenceReceiver;
  sim.potTurnDeg = options_.potTurnDeg;
  sim.distortion = options_.distortion;
  const QString error = plantCapture_->startSimulated(dbPath(), plantMarkers, sim, options_.setup.operatorName,
                                                      options_.setup.station, 0, protocol);
  if (!error.isEmpty()) {
    banner_->setText(tr("Cannot start the plant capture: %1").arg(error));
    return false;
  }
  sessionId_ = plantCapture_->sessionId();
  return true;
}

bool StationWindow::startPlantCaptureWithDevices(acq::PlantSessionSetup setup) {
  if (!capturesIntoStationFile()) return false;
  if (setup.station.empty()) setup.station = options_.setup.station;
  if (!sentinels_ && sentinelsFirst([this, setup] { (void)startPlantCaptureWithDevices(setup); })) return true;
  plantCaptureTab()->setFieldCalibration(sentinels_ ? std::to_string(sentinels_->checkId) : options_.fieldCalibration);
  plantCapture_->setSentinels(std::exchange(sentinels_, std::nullopt));
  plantCaptureTab()->setFieldCheckMaxAgeHours(settings_.fieldCheckMaxAgeHours);
  const QString error = plantCaptureTab()->startWithDevices(dbPath(), setup);
  if (!error.isEmpty()) {
    banner_->setText(tr("Cannot start the plant capture: %1").arg(error));
    return false;
  }
  sessionId_ = plantCapture_->sessionId();
  return true;
}

}  // namespace leafdig::station
