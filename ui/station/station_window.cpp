#include "station_window.hpp"

#include <QApplication>
#include <QPushButton>
#include <fstream>
#include <QHBoxLayout>
#include <QKeyEvent>
#include <QKeySequence>
#include <QMenu>
#include <QMessageBox>
#include <QShortcut>
#include <QSplitter>
#include <QStatusBar>
#include <QToolBar>
#include <QVBoxLayout>

#include "export_dialog.hpp"
#include "leafdig/devices/registry.hpp"
#include "leafdig/model/markers_json.hpp"
#include "leafdig/version.hpp"
#include "review_view.hpp"
#include "settings_dialog.hpp"
#include "setup_dialog.hpp"

namespace leafdig::station {
namespace acq = leafdig::acquisition;
using Role = acq::DeviceSet::Role;

namespace {

QString stateColour(devices::LinkState s) {
  switch (s) {
    case devices::LinkState::Streaming: return "background:#e8f5e9; color:#1b5e20; border:2px solid #2e7d32;";
    case devices::LinkState::Connecting: return "background:#fff8e1; color:#8d6e00; border:2px solid #f9a825;";
    case devices::LinkState::Warning: return "background:#fff3e0; color:#bf360c; border:2px solid #ef6c00;";
    case devices::LinkState::Error: return "background:#ffebee; color:#b71c1c; border:2px solid #c62828;";
    case devices::LinkState::Disconnected: break;
  }
  return "background:#eceff1; color:#37474f; border:2px solid #90a4ae;";
}

std::string defaultMarkers() {
  const std::string dir = samplesDir();
  return (dir.empty() ? std::string(kSourceDataDir) + "/samples" : dir) + "/lower-leaf-n10.markers.json";
}

}  // namespace

StationWindow::StationWindow(StationOptions options, QWidget* parent)
    : QMainWindow(parent), options_(std::move(options)) {
  if (options_.settingsFile.isEmpty()) options_.settingsFile = defaultSettingsFile();
  settings_ = StationSettings::load(options_.settingsFile);
  setWindowTitle(QStringLiteral("leafdig station %1").arg(QString::fromLatin1(kVersion)));
  sounds_ = new Sounds(this);

  tabs_ = new QTabWidget(this);
  tabs_->setFocusPolicy(Qt::NoFocus);
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
  outer->addWidget(chipRow_);
  auto* split = new QSplitter(capture);
  auto* left = new QSplitter(Qt::Vertical, split);
  schematic_ = new LeafSchematic(left);
  steps_ = new QListWidget(left);
  steps_->setObjectName("steps");
  steps_->setFocusPolicy(Qt::NoFocus);  // focus is never trapped: keys go to the window
  left->setMinimumWidth(260);
  preview_ = new PreviewWidget(split);
  split->addWidget(left);
  split->addWidget(preview_);
  split->setStretchFactor(1, 1);
  outer->addWidget(split, 1);
  tabs_->addTab(capture, tr("Capture"));
  review_ = new ReviewView(settings_, tabs_);
  tabs_->addTab(review_, tr("Review"));
  setCentralWidget(tabs_);
  resize(1280, 860);

  auto* bar = addToolBar(tr("Station"));
  bar->setMovable(false);
  bar->setFocusPolicy(Qt::NoFocus);
  bar->addAction(tr("New session…"), this, [this] { (void)newSessionDialog(); });
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
  deviceTimer_.start(100);
  cursorTimer_.start(33);  // the cursor follows the latest sample at ~30 Hz, never each one
  qApp->installEventFilter(this);
  applySettings(settings_);
}

StationWindow::~StationWindow() {
  qApp->removeEventFilter(this);
  stopCapture();
}

void StationWindow::applySettings(const StationSettings& s) {
  settings_ = s;
  sounds_->setMuted(!s.sounds);
  sounds_->setVolume(s.volume);
  if (auto* app = qobject_cast<QApplication*>(QApplication::instance())) applyTheme(*app, s);
  review_->setSettings(s);
  buildShortcuts();
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
  if ((event->type() == QEvent::KeyPress || event->type() == QEvent::KeyRelease) && loop_ &&
      tabs_->currentIndex() == 0 && watched->isWidgetType() && static_cast<QWidget*>(watched)->window() == this) {
    auto* k = static_cast<QKeyEvent*>(event);
    const QKeySequence accept = settings_.shortcuts[Action::Accept];
    if (!k->isAutoRepeat() && !accept.isEmpty() && QKeySequence(k->keyCombination()) == accept) {
      loop_->setPedal(event->type() == QEvent::KeyPress);
      return true;
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
  if (loop_) loop_->command(c);
}

QToolButton* StationWindow::chip(Role role) {
  QToolButton*& b = chips_[role];
  if (!b) {
    b = new QToolButton(chipRow_);
    b->setFocusPolicy(Qt::NoFocus);
    b->setToolButtonStyle(Qt::ToolButtonTextOnly);
    b->setPopupMode(QToolButton::InstantPopup);
    auto* menu = new QMenu(b);
    menu->addAction(tr("Connect / disconnect"), this, [this, role] { toggleDevice(role); });
    b->setMenu(menu);
    b->setText(role == Role::Digitizer ? tr("Digitizer · not started") : tr("Caliper · not started"));
    b->setStyleSheet("QToolButton { padding:6px 10px; border-radius:6px; " + stateColour(devices::LinkState::Disconnected) + "}");
    static_cast<QHBoxLayout*>(chipRow_->layout())->insertWidget(role == Role::Digitizer ? 0 : 1, b);
  }
  return b;
}

QString StationWindow::chipText(Role role) const { return chips_.at(role)->text(); }

void StationWindow::toggleDevice(Role role) {
  if (!devices_) return;
  if (devices_->connected(role)) devices_->disconnect(role);
  else devices_->connect(role);
  refreshDevices();
}

void StationWindow::refreshDevices() {
  if (!devices_) return;
  for (const Role role : {Role::Digitizer, Role::Caliper}) {
    const devices::DeviceStatus s = devices_->status(role);
    QString text = QString::fromStdString(s.device.empty() ? (role == Role::Digitizer ? "Digitizer" : "Caliper") : s.device);
    text += " · " + QString::fromLatin1(devices::toString(s.state));
    if (s.state == devices::LinkState::Streaming || s.state == devices::LinkState::Warning) {
      if (role == Role::Digitizer || s.rateHz > 0) text += QString(" · %1 Hz").arg(s.rateHz, 0, 'f', 0);
      if (s.lastSampleAgeS >= 0) text += QString(" · last %1 s ago").arg(s.lastSampleAgeS, 0, 'f', 1);
    }
    if (!s.remedy.empty() && s.state != devices::LinkState::Streaming)
      text += "\n" + QString::fromStdString(s.message) + " — " + QString::fromStdString(s.remedy);
    QToolButton* b = chip(role);
    b->setText(text);
    b->setToolTip(QString::fromStdString(s.where) + "\n" + QString::fromStdString(s.message) +
                  QString("\nreconnects: %1").arg(s.reconnects));
    b->setStyleSheet("QToolButton { padding:6px 10px; border-radius:6px; " + stateColour(s.state) + "}");
    const auto was = lastState_.find(role);
    if ((s.state == devices::LinkState::Error || (s.state == devices::LinkState::Disconnected && devices_->connected(role))) &&
        (was == lastState_.end() || was->second != s.state))
      sounds_->play(Cue::DeviceError);
    lastState_[role] = s.state;
  }
}

void StationWindow::refreshCursor() {
  if (!loop_ || tabs_->currentIndex() != 0) return;
  const auto s = loop_->latestStylus();
  if (s) preview_->setStylusCursor(acq::Vec3{s->positionMm[0], s->positionMm[1], s->positionMm[2]});
}

std::string StationWindow::dbPath() const { return options_.db.empty() ? db::Store::defaultPath() : options_.db; }

std::vector<db::SessionInfo> StationWindow::interruptedSessions() const {
  std::vector<db::SessionInfo> out;
  try {
    if (!std::ifstream(dbPath()).good()) return out;
    db::Store store(dbPath(), true);
    const std::string station = acq::thisStation();
    for (const auto& s : store.sessions())
      if (s.status == "open" && (station.empty() || s.station == station)) out.push_back(s);
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

bool StationWindow::start() {
  stopCapture();
  operator_.reset();
  devices_.reset();
  loop_.reset();
  session_.reset();
  rig_.reset();
  last_.reset();
  lastState_.clear();
  try {
    if (!store_ || store_->path() != dbPath()) store_ = std::make_unique<db::Store>(dbPath());
    acq::SessionSetup setup = options_.setup;
    if (options_.resume == 0) {
      acq::Settings e = settings_.engine;  // tolerances and stillness from the station's settings
      e.mode = setup.settings.mode;
      e.order = setup.settings.order;
      e.boardFrame = setup.settings.boardFrame;
      setup.settings = e;
    }
    setup.simulated = options_.simulate;
    setup.timeScale = options_.simulate ? options_.speed : 1.0;
    if (options_.simulate) {
      setup.digitizer = "fastrak:simulated";
      setup.caliper = "sylvac:simulated";
    }
    sessionId_ = options_.resume > 0 ? options_.resume : acq::CaptureSession::create(*store_, setup);
    session_ = std::make_unique<acq::CaptureSession>(*store_, sessionId_);
    const bool simulated = session_->setup().simulated;
    const double speed = simulated ? (options_.resume > 0 ? session_->setup().timeScale : options_.speed) : 1.0;
    acq::LoopListener listener;
    // Called on the capture thread: hand over to the UI thread.
    listener.onFeedback = [this](const acq::Feedback& f) {
      QMetaObject::invokeMethod(this, [this, f] { applyFeedback(f); }, Qt::QueuedConnection);
    };
    listener.onSnapshot = [this](const acq::Snapshot& s) {
      if (operator_) operator_->observe(s);
      QMetaObject::invokeMethod(this, [this, s] { applySnapshot(s); }, Qt::QueuedConnection);
    };
    loop_ = std::make_unique<acq::CaptureLoop>(*session_, listener, speed);
    std::string digitizer = session_->setup().digitizer, caliper = session_->setup().caliper;
    if (simulated) {
      acq::SimulationOptions so;
      so.speed = speed;
      so.seed = options_.seed;
      rig_ = std::make_unique<acq::SimulatedRig>(so);
      const std::string markers = options_.markers.empty() ? defaultMarkers() : options_.markers;
      operator_ = std::make_unique<acq::VirtualOperator>(*rig_, model::readMarkersFile(markers), so);
      digitizer = rig_->digitizerSpec();
      caliper = rig_->caliperSpec();
    }
    devices_ = std::make_unique<acq::DeviceSet>(digitizer, caliper, *loop_);
    if (session_->paused()) {
      acq::Command c;
      c.kind = acq::Command::Kind::Resume;
      loop_->command(c);
    }
    devices_->start();
    if (operator_) operator_->start();
    captureThread_ = std::thread([this] { (void)loop_->run(); });
    statusBar()->showMessage(QStringLiteral("session %1 · %2 · %3")
                                 .arg(sessionId_)
                                 .arg(QString::fromStdString(store_->path()))
                                 .arg(simulated ? tr("simulated devices") : tr("devices")));
    review_->setDatabase(store_->path());
    tabs_->setCurrentIndex(0);
    return true;
  } catch (const std::exception& e) {
    banner_->setText(tr("Cannot start: %1").arg(QString::fromStdString(e.what())));
    return false;
  }
}

void StationWindow::stopCapture() {
  if (operator_) operator_->stop();
  if (loop_) loop_->stop();
  if (captureThread_.joinable()) captureThread_.join();
  if (devices_) devices_->stop();
}

void StationWindow::applyFeedback(const acq::Feedback& f) {
  using K = acq::Feedback::Kind;
  QString text;
  QString colour = "#1b5e20";
  switch (f.kind) {
    case K::Accepted: {
      text = tr("✓ accepted %1").arg(QString::fromLatin1(acq::toString(f.item.what)));
      if (acq::isStylusItem(f.item.what)) {
        const auto& p = f.item.positionMm;
        lastPoint_->setText(tr("last point  x %1  y %2  z %3")
                                .arg(settings_.length(p[0], 1), settings_.length(p[1], 1), settings_.length(p[2], 1)));
      } else {
        lastPoint_->setText(tr("last reading  %1").arg(settings_.length(f.item.valueMm, 3)));
      }
      const bool rowDone = f.item.what == acq::What::Marker && f.item.col == 7;
      sounds_->play(rowDone ? Cue::StepDone : Cue::Accept);
      break;
    }
    case K::Rejected:
      text = tr("✗ not taken: %1").arg(QString::fromStdString(f.text));
      colour = "#b71c1c";
      sounds_->play(Cue::Reject);
      break;
    case K::Undone: text = tr("↶ undone"); break;
    case K::RowsEnded:
      text = tr("rows ended: now the thicknesses, on the back of the leaf");
      sounds_->play(Cue::StepDone);
      break;
    case K::Paused:
      text = tr("‖ paused: %1").arg(QString::fromStdString(f.text));
      colour = "#e65100";
      break;
    case K::Complete:
      text = tr("✓ leaf complete — session %1 is ready for review").arg(sessionId_);
      sounds_->play(Cue::StepDone);
      break;
    case K::Device: {
      statusBar()->showMessage(QString::fromStdString(f.text), 8000);
      refreshDevices();
      return;
    }
    default: text = QString::fromLatin1(acq::toString(f.kind)); break;
  }
  feedback_->setText(text);
  feedback_->setStyleSheet("color:" + colour);
  if (f.kind == K::Complete) emit captureComplete();
}

void StationWindow::fillSteps(const acq::Snapshot& s) {
  steps_->clear();
  const auto count = [&](acq::What w, int row) {
    int n = 0;
    for (const auto& i : s.items) n += i.what == w && (row < 0 || i.row == row);
    return n;
  };
  const auto add = [&](const QString& text, bool done, bool current) {
    auto* item = new QListWidgetItem((done ? "✓ " : current ? "▶ " : "· ") + text, steps_);
    if (current) {
      QFont f = item->font();
      f.setBold(true);
      item->setFont(f);
      item->setBackground(QColor("#fff59d"));
      item->setForeground(QColor("#000000"));
    } else if (done) {
      item->setForeground(QColor("#2e7d32"));
    }
  };
  add(tr("Tip"), count(acq::What::Tip, -1) > 0, s.step.what == acq::What::Tip);
  const int rows = std::max(s.completeRows + (s.rowsEnded ? 0 : 1), 1);
  for (int r = 1; r <= rows; ++r) {
    const int n = count(acq::What::Marker, r);
    add(tr("Row %1 · %2 of 7 points").arg(r).arg(n), n == 7, s.step.what == acq::What::Marker && s.step.row == r);
  }
  if (s.rowsEnded || s.complete) {
    for (int r = 1; r <= s.completeRows; ++r) {
      const int n = count(acq::What::MidribThickness, r) + count(acq::What::VeinOriginThickness, r) +
                    count(acq::What::PointThickness, r);
      const bool current = s.step.row == r && s.step.what != acq::What::Marker;
      add(tr("Row %1 · back side thickness (%2 taken)").arg(r).arg(n), !current && n > 0, current);
    }
    add(tr("Margin thickness (d)"), count(acq::What::EdgeThickness, -1) > 0, s.step.what == acq::What::EdgeThickness);
  }
  int doneSteps = 0;
  for (int i = 0; i < steps_->count(); ++i) {
    if (steps_->item(i)->text().startsWith("▶")) steps_->scrollToItem(steps_->item(i));
    doneSteps += steps_->item(i)->text().startsWith("✓");
  }
  statusBar()->showMessage(tr("session %1 · %2 of %3 steps · %4 items").arg(s.session).arg(doneSteps).arg(steps_->count()).arg(s.items.size()));
}

void StationWindow::applySnapshot(const acq::Snapshot& s) {
  last_ = s;
  banner_->setText(QString::fromStdString(s.prompt));
  fillSteps(s);
  schematic_->show(s);
  preview_->show(s);
}

}  // namespace leafdig::station
