// StationWindow's Capture tab as it changes (station_window.hpp): the device chips and their
// states, the feedback line, the steps and the snapshots the capture thread posts.
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

#include "station_window.hpp"

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

}  // namespace

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
    b->setStyleSheet("QToolButton { padding:6px 10px; border-radius:6px; " +
                     stateColour(devices::LinkState::Disconnected) + "}");
    static_cast<QHBoxLayout*>(chipRow_->layout())->insertWidget(role == Role::Digitizer ? 0 : 1, b);
  }
  return b;
}

QString StationWindow::chipText(Role role) const {
  return chips_.at(role)->text();
}

QString StationWindow::chipLabel(const devices::DeviceStatus& s, Role role, double simulationSpeed) {
  QString text =
      QString::fromStdString(s.device.empty() ? (role == Role::Digitizer ? "Digitizer" : "Caliper") : s.device);
  text += " · " + QString::fromLatin1(devices::toString(s.state));
  if (s.state == devices::LinkState::Streaming || s.state == devices::LinkState::Warning) {
    if (role == Role::Digitizer || s.rateHz > 0) {
      const bool scaled = simulationSpeed > 0 && simulationSpeed != 1.0;
      text += QString(" · %1 Hz").arg(scaled ? s.rateHz / simulationSpeed : s.rateHz, 0, 'f', 0);
      if (scaled) text += QString(" (simulated ×%1)").arg(simulationSpeed, 0, 'g', 3);
    }
    if (s.lastSampleAgeS >= 0) text += QString(" · last %1 s ago").arg(s.lastSampleAgeS, 0, 'f', 1);
  }
  if (!s.remedy.empty() && s.state != devices::LinkState::Streaming) {
    // Message and remedy on lines of at most kChipLineChars: a chip never widens the window.
    constexpr int kChipLineChars = 56;
    QString line;
    for (const QString& word : (QString::fromStdString(s.message) + " — " + QString::fromStdString(s.remedy))
                                   .split(' ', Qt::SkipEmptyParts)) {
      if (!line.isEmpty() && line.size() + 1 + word.size() > kChipLineChars) {
        text += "\n" + line;
        line.clear();
      }
      line += (line.isEmpty() ? "" : " ") + word;
    }
    if (!line.isEmpty()) text += "\n" + line;
  }
  return text;
}

void StationWindow::toggleDevice(Role role) {
  if (!run_) return;
  acq::DeviceSet& devices = run_->devices();
  if (devices.connected(role))
    devices.disconnect(role);
  else
    devices.connect(role);
  refreshDevices();
}

void StationWindow::refreshDevices() {
  if (!run_) return;
  for (const Role role : {Role::Digitizer, Role::Caliper}) {
    const devices::DeviceStatus s = run_->devices().status(role);
    const QString text = chipLabel(s, role, options_.simulate ? options_.speed : 1.0);
    QToolButton* b = chip(role);
    b->setText(text);
    b->setToolTip(QString::fromStdString(s.where) + "\n" + QString::fromStdString(s.message) +
                  QString("\nreconnects: %1").arg(s.reconnects));
    b->setStyleSheet("QToolButton { padding:6px 10px; border-radius:6px; " + stateColour(s.state) + "}");
    const auto was = lastState_.find(role);
    if ((s.state == devices::LinkState::Error ||
         (s.state == devices::LinkState::Disconnected && run_->devices().connected(role))) &&
        (was == lastState_.end() || was->second != s.state))
      sounds_->play(Cue::DeviceError);
    lastState_[role] = s.state;
  }
}

void StationWindow::refreshCursor() {
  if (!run_ || tabs_->currentIndex() != 0) return;
  const auto s = run_->latestStylus();
  if (s) preview_->setStylusCursor(acq::Vec3{s->positionMm[0], s->positionMm[1], s->positionMm[2]});
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
      const bool rowDone = f.item.what == acq::What::Marker && f.item.col == acq::kMarkersPerRow;
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
    case K::Relocation:
      if (f.text == "started")
        text = tr("⇄ transmitter moved: take the three board points again, then hold the button");
      else if (f.text == "fitted")
        text = tr("✓ transmitter position %1 fitted: RMS %2, worst board point %3")
                   .arg(f.relocation + 1)
                   .arg(settings_.length(f.fitRmsMm, 2), QString::number(f.fitWorstPoint));
      else
        text = tr("↶ move of the transmitter %1").arg(QString::fromStdString(f.text));
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
  // One line per group of the engine's plan: the board, the tip, a row's points, a row's
  // thickness readings, the margin reading.
  using State = acq::PlannedStep::State;
  struct Group {
    acq::What what;
    int row = 0, done = 0, total = 0;
    bool current = false;
  };
  std::vector<Group> groups;
  const auto groupOf = [](acq::What w) {
    const bool thickness =
        w == acq::What::MidribThickness || w == acq::What::VeinOriginThickness || w == acq::What::PointThickness;
    return thickness ? acq::What::MidribThickness : w;
  };
  for (const acq::PlannedStep& p : s.plan) {
    const acq::What g = groupOf(p.step.what);
    if (groups.empty() || groups.back().what != g || groups.back().row != p.step.row) groups.push_back({g, p.step.row});
    Group& group = groups.back();
    ++group.total;
    group.done += p.state == State::Done;
    group.current = group.current || p.state == State::Current;
  }
  int doneSteps = 0, totalSteps = 0;
  for (const Group& g : groups) {
    QString text;
    switch (g.what) {
      case acq::What::Board: text = tr("Board frame · %1 of %2 points").arg(g.done).arg(g.total); break;
      case acq::What::Tip: text = tr("Tip"); break;
      case acq::What::Marker: text = tr("Row %1 · %2 of %3 points").arg(g.row).arg(g.done).arg(g.total); break;
      case acq::What::EdgeThickness: text = tr("Margin thickness (d)"); break;
      case acq::What::BoardAgain:
        text = tr("Transmitter moved · board points again · %1 of %2").arg(g.done).arg(g.total);
        break;
      default: text = tr("Row %1 · back side thickness (%2 of %3)").arg(g.row).arg(g.done).arg(g.total); break;
    }
    const bool done = g.done == g.total;
    auto* item = new QListWidgetItem((done ? "✓ " : g.current ? "▶ " : "· ") + text, steps_);
    if (g.current) {
      QFont f = item->font();
      f.setBold(true);
      item->setFont(f);
      item->setBackground(QColor("#fff59d"));
      item->setForeground(QColor("#000000"));
      steps_->scrollToItem(item);
    } else if (done) {
      item->setForeground(QColor("#2e7d32"));
    }
    item->setToolTip(text);
    doneSteps += g.done;
    totalSteps += g.total;
  }
  statusBar()->showMessage(
      tr("session %1 · %2 of %3 steps · %4 items").arg(s.session).arg(doneSteps).arg(totalSteps).arg(s.items.size()));
}

void StationWindow::postSnapshot(const acq::Snapshot& s) {
  // The newest wins; the GUI thread's mailbox timer takes it (takeSnapshot), so nothing the
  // capture thread allocates is read by the GUI thread without this lock between them.
  const std::lock_guard lock(mailboxMutex_);
  mailbox_ = s;
}

void StationWindow::takeSnapshot() {
  std::optional<acq::Snapshot> s;
  {
    const std::lock_guard lock(mailboxMutex_);
    s.swap(mailbox_);
  }
  if (s) applySnapshot(*s);
}

void StationWindow::applySnapshot(const acq::Snapshot& s) {
  last_ = s;
  banner_->setText(QString::fromStdString(s.prompt));
  fillSteps(s);
  schematic_->show(s);
  preview_->show(s);
}

}  // namespace leafdig::station
