#include "station_window.hpp"

#include <QApplication>
#include <QHBoxLayout>
#include <QKeySequence>
#include <QShortcut>
#include <QSplitter>
#include <QStatusBar>
#include <QVBoxLayout>

#include "leafdig/model/markers_json.hpp"
#include "leafdig/version.hpp"

namespace leafdig::station {
namespace acq = leafdig::acquisition;

StationWindow::StationWindow(StationOptions options, QWidget* parent)
    : QMainWindow(parent), options_(std::move(options)) {
  setWindowTitle(QStringLiteral("leafdig station %1").arg(QString::fromLatin1(kVersion)));
  auto* central = new QWidget(this);
  auto* outer = new QVBoxLayout(central);
  banner_ = new QLabel(tr("Starting…"), central);
  QFont big = banner_->font();
  big.setPointSizeF(big.pointSizeF() * 2.2);
  big.setBold(true);
  banner_->setFont(big);
  banner_->setWordWrap(true);
  banner_->setObjectName("banner");
  banner_->setStyleSheet("QLabel#banner { background: #1f3b57; color: white; padding: 12px; border-radius: 6px; }");
  outer->addWidget(banner_);
  feedback_ = new QLabel(central);
  QFont mid = feedback_->font();
  mid.setPointSizeF(mid.pointSizeF() * 1.3);
  feedback_->setFont(mid);
  outer->addWidget(feedback_);
  chipRow_ = new QWidget(central);
  new QHBoxLayout(chipRow_);
  chipRow_->layout()->setContentsMargins(0, 0, 0, 0);
  outer->addWidget(chipRow_);
  auto* split = new QSplitter(central);
  steps_ = new QListWidget(split);
  steps_->setFocusPolicy(Qt::NoFocus);  // focus is never trapped: keys go to the window
  steps_->setMinimumWidth(240);
  preview_ = new PreviewWidget(split);
  split->addWidget(steps_);
  split->addWidget(preview_);
  split->setStretchFactor(1, 1);
  outer->addWidget(split, 1);
  setCentralWidget(central);
  resize(1200, 800);

  // Keyboard shortcuts (a foot pedal that types these keys works the same).
  const auto key = [this](const QKeySequence& k, acq::Command::Kind kind) {
    auto* s = new QShortcut(k, this);
    s->setContext(Qt::ApplicationShortcut);
    connect(s, &QShortcut::activated, this, [this, kind] { command(kind); });
  };
  key(QKeySequence(Qt::Key_U), acq::Command::Kind::Undo);
  key(QKeySequence(Qt::Key_Backspace), acq::Command::Kind::Undo);
  key(QKeySequence(Qt::Key_E), acq::Command::Kind::EndRows);
  key(QKeySequence(Qt::Key_P), acq::Command::Kind::Pause);
  key(QKeySequence(Qt::Key_Space), acq::Command::Kind::Resume);
}

StationWindow::~StationWindow() { stopCapture(); }

void StationWindow::command(acq::Command::Kind kind) {
  if (!loop_) return;
  acq::Command c;
  c.kind = kind;
  if (kind == acq::Command::Kind::Pause) c.text = "paused at the station";
  loop_->command(c);
}

bool StationWindow::start() {
  try {
    store_ = std::make_unique<db::Store>(options_.db.empty() ? db::Store::defaultPath() : options_.db);
    acq::SessionSetup setup;
    setup.project = options_.project;
    setup.plant = options_.plant;
    setup.leafPosition = options_.leafPosition;
    setup.operatorName = options_.operatorName;
    setup.simulated = options_.simulate;
    setup.timeScale = options_.simulate ? options_.speed : 1.0;
    setup.digitizer = options_.simulate ? "fastrak:simulated" : options_.digitizer;
    setup.caliper = options_.simulate ? "sylvac:simulated" : options_.caliper;
    sessionId_ = options_.resume > 0 ? options_.resume : acq::CaptureSession::create(*store_, setup);
    session_ = std::make_unique<acq::CaptureSession>(*store_, sessionId_);
    acq::LoopListener listener;
    // Called on the capture thread: hand over to the UI thread (latest snapshot wins).
    listener.onFeedback = [this](const acq::Feedback& f) {
      QMetaObject::invokeMethod(this, [this, f] { applyFeedback(f); }, Qt::QueuedConnection);
    };
    listener.onSnapshot = [this](const acq::Snapshot& s) {
      if (operator_) operator_->observe(s);
      QMetaObject::invokeMethod(this, [this, s] { applySnapshot(s); }, Qt::QueuedConnection);
    };
    loop_ = std::make_unique<acq::CaptureLoop>(*session_, listener, options_.simulate ? options_.speed : 1.0);
    std::string digitizer = options_.digitizer, caliper = options_.caliper;
    if (options_.simulate) {
      acq::SimulationOptions so;
      so.speed = options_.speed;
      so.seed = options_.seed;
      rig_ = std::make_unique<acq::SimulatedRig>(so);
      const std::string markers = options_.markers.empty() ? std::string(kSourceDataDir) + "/samples/lower-leaf-n10.markers.json"
                                                           : options_.markers;
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
                                 .arg(options_.simulate ? tr("simulated devices") : tr("devices")));
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
    case K::Accepted: text = tr("✓ accepted %1").arg(QString::fromLatin1(acq::toString(f.item.what))); break;
    case K::Rejected:
      text = tr("✗ not taken: %1").arg(QString::fromStdString(f.text));
      colour = "#b71c1c";
      QApplication::beep();
      break;
    case K::Undone: text = tr("↶ undone"); break;
    case K::Paused:
      text = tr("‖ paused: %1").arg(QString::fromStdString(f.text));
      colour = "#e65100";
      break;
    case K::Complete: text = tr("✓ leaf complete"); break;
    case K::Device: {
      const auto colon = f.text.find(':');
      const std::string device = f.text.substr(0, colon);
      QLabel*& chip = chips_[device];
      if (!chip) {
        chip = new QLabel(chipRow_);
        chip->setMargin(6);
        chipRow_->layout()->addWidget(chip);
      }
      const bool ok = f.text.find("ready") != std::string::npos || f.text.find("streaming") != std::string::npos;
      chip->setText(QString::fromStdString(f.text));
      chip->setStyleSheet(ok ? "background:#e8f5e9; border:1px solid #2e7d32; border-radius:4px"
                             : "background:#fff3e0; border:1px solid #e65100; border-radius:4px");
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
  for (int i = 0; i < steps_->count(); ++i)
    if (steps_->item(i)->text().startsWith("▶")) steps_->scrollToItem(steps_->item(i));
}

void StationWindow::applySnapshot(const acq::Snapshot& s) {
  last_ = s;
  banner_->setText(QString::fromStdString(s.prompt));
  fillSteps(s);
  preview_->show(s);
}

}  // namespace leafdig::station
