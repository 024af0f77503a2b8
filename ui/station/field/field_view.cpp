#include "field/field_view.hpp"

#include <QDoubleSpinBox>
#include <QFormLayout>
#include <QHBoxLayout>
#include <QLabel>
#include <QLineEdit>
#include <QListWidget>
#include <QPainter>
#include <QPainterPath>
#include <QPushButton>
#include <QVBoxLayout>
#include <cmath>
#include <filesystem>
#include <utility>

#include "leafdig/acquisition/run/field_check_run.hpp"
#include "leafdig/acquisition/run/tip_calibration_run.hpp"
#include "leafdig/model/field/jig.hpp"
#include "leafdig/version.hpp"

namespace leafdig::station {

namespace acq = leafdig::acquisition;

namespace {

// The shipped sample jig (data/fields/ in the source tree or beside the package's samples).
std::string sampleJig() {
  const std::string samples = samplesDir();
  const std::string data = samples.empty() ? sourceDataDir() : std::filesystem::path(samples).parent_path().string();
  return data + "/fields/three-level.jig.json";
}

QString decisionText(const acq::JigCapture::Decision& d) {
  using K = acq::JigCapture::Decision::Kind;
  const char* kind = d.kind == K::Accepted ? "accepted" : d.kind == K::Undone ? "undone" : "rejected";
  return QStringLiteral("%1: %2").arg(QString::fromLatin1(kind), QString::fromStdString(d.words));
}

}  // namespace

FieldMapWidget::FieldMapWidget(QWidget* parent) : QWidget(parent) {
  setMinimumSize(380, 260);
}

void FieldMapWidget::setMap(std::optional<model::FieldMapLayout> map) {
  map_ = std::move(map);
  update();
}

void FieldMapWidget::paintEvent(QPaintEvent* /*event*/) {
  QPainter p(this);
  p.fillRect(rect(), Qt::white);
  if (!map_) {
    p.setPen(QColor("#777"));
    p.drawText(rect(), Qt::AlignCenter | Qt::TextWordWrap, tr("The error map appears when every divot is taken."));
    return;
  }
  const model::FieldMapLayout& m = *map_;
  // The figure's own pixels scaled to the widget, kept in proportion.
  const double k = std::min(width() / m.width, height() / m.height);
  p.setRenderHint(QPainter::Antialiasing);
  p.scale(k, k);
  p.setPen(Qt::black);
  QFont bold = font();
  bold.setBold(true);
  p.setFont(bold);
  p.drawText(QPointF(10, 20), QString::fromStdString(m.title));
  p.setFont(font());
  p.drawText(QPointF(10, 40), QString::fromStdString(m.summary));
  for (const model::FieldMapPanel& panel : m.panels) {
    p.setPen(QColor("#999"));
    p.setBrush(Qt::NoBrush);
    p.drawRect(QRectF(panel.x0, panel.y0, panel.size, panel.size));
    p.setPen(Qt::black);
    p.drawText(QPointF(panel.x0 + 6, panel.y0 + 16), QString::fromStdString(panel.title));
    for (const model::FieldMapArrow& a : panel.arrows) {
      const QColor colour(QString::fromStdString(a.colour));
      p.setPen(QPen(colour, 1.6));
      p.setBrush(colour);
      p.drawEllipse(QPointF(a.x, a.y), 2.5, 2.5);
      p.drawLine(QPointF(a.x, a.y), QPointF(a.tipX, a.tipY));
      const double angle = std::atan2(a.tipY - a.y, a.tipX - a.x);
      if (std::hypot(a.tipX - a.x, a.tipY - a.y) > 1.0) {
        QPainterPath head;
        head.moveTo(a.tipX, a.tipY);
        head.lineTo(a.tipX - 7 * std::cos(angle - 0.45), a.tipY - 7 * std::sin(angle - 0.45));
        head.lineTo(a.tipX - 7 * std::cos(angle + 0.45), a.tipY - 7 * std::sin(angle + 0.45));
        head.closeSubpath();
        p.drawPath(head);
      }
      if (!a.label.empty()) {
        p.setPen(QColor("#555"));
        p.drawText(QPointF(a.x + 4, a.y - 4), QString::fromStdString(a.label));
      }
    }
  }
  double lx = 10;
  for (const auto& [colour, words] : m.legend) {
    p.fillRect(QRectF(lx, m.legendY - 9, 12, 12), QColor(QString::fromStdString(colour)));
    p.setPen(Qt::black);
    p.drawText(QPointF(lx + 16, m.legendY + 1), QString::fromStdString(words));
    lx += 110;
  }
  p.setPen(QPen(Qt::black, 2));
  p.drawLine(QPointF(lx + 10, m.legendY - 3), QPointF(lx + 10 + m.scaleBarPx, m.legendY - 3));
  p.drawText(QPointF(lx + 16 + m.scaleBarPx, m.legendY + 1), tr("100 mm (positions)"));
}

FieldView::FieldView(QWidget* parent) : QWidget(parent) {
  jig_ = new QLineEdit;
  jig_->setPlaceholderText(tr("the sample jig (data/fields/three-level.jig.json)"));
  tolerance_ = new QDoubleSpinBox;
  tolerance_->setRange(0.1, 50);
  tolerance_->setDecimals(2);
  tolerance_->setSingleStep(0.1);
  tolerance_->setSuffix(tr(" mm RMS"));
  tolerance_->setValue(acq::kDefaultFieldToleranceMm);
  auto* form = new QFormLayout;
  form->addRow(tr("Jig file"), jig_);
  form->addRow(tr("Tolerance"), tolerance_);
  check_ = new QPushButton(tr("Check the field"));
  tip_ = new QPushButton(tr("Calibrate the stylus tip"));
  undo_ = new QPushButton(tr("Undo the last divot"));
  stop_ = new QPushButton(tr("Stop"));
  undo_->setEnabled(false);
  stop_->setEnabled(false);
  auto* buttons = new QHBoxLayout;
  for (QPushButton* b : {check_, tip_, undo_, stop_}) buttons->addWidget(b);
  buttons->addStretch();
  prompt_ =
      new QLabel(tr("Check the field before the day's captures: lay the jig where the leaves and plants will "
                    "be, and press Check the field."));
  prompt_->setWordWrap(true);
  QFont big = prompt_->font();
  big.setPointSizeF(big.pointSizeF() * 1.6);
  big.setBold(true);
  prompt_->setFont(big);
  result_ = new QLabel;
  result_->setWordWrap(true);
  result_->setTextInteractionFlags(Qt::TextSelectableByMouse);
  decisions_ = new QListWidget;
  decisions_->setMaximumWidth(420);
  map_ = new FieldMapWidget;
  auto* body = new QHBoxLayout;
  body->addWidget(decisions_, 1);
  body->addWidget(map_, 2);
  auto* outer = new QVBoxLayout(this);
  outer->addLayout(form);
  outer->addLayout(buttons);
  outer->addWidget(prompt_);
  outer->addWidget(result_);
  outer->addLayout(body, 1);
  connect(check_, &QPushButton::clicked, this, [this] {
    const QString error = startCheck();
    if (!error.isEmpty()) result_->setText(error);
  });
  connect(tip_, &QPushButton::clicked, this, [this] {
    const QString error = startTipCalibration();
    if (!error.isEmpty()) result_->setText(error);
  });
  connect(undo_, &QPushButton::clicked, this, &FieldView::undo);
  connect(stop_, &QPushButton::clicked, this, &FieldView::stop);
  connect(&poll_, &QTimer::timeout, this, &FieldView::drain);
  poll_.start(33);
}

FieldView::~FieldView() {
  sentinelsDone_ = nullptr;  // what it would call is going too
  stop();
}

void FieldView::post(const std::function<void(Mail&)>& write) {
  const std::lock_guard lock(mutex_);
  write(mail_);
}

void FieldView::launch(const QString& what, std::function<void()> body) {
  stop();
  {
    const std::lock_guard lock(mutex_);
    mail_ = Mail{};
  }
  decisions_->clear();
  result_->setText(what);
  finished_ = false;
  stopAsked_ = false;
  for (QPushButton* b : {check_, tip_}) b->setEnabled(false);
  for (QPushButton* b : {undo_, stop_}) b->setEnabled(true);
  worker_ = std::thread([this, body = std::move(body)] {
    try {
      body();
    } catch (const std::exception& e) {
      post([&](Mail& m) { m.failure = QString::fromStdString(e.what()); });
    }
    post([](Mail& m) { m.ended = true; });
  });
}

acq::FieldCheckRequest FieldView::divotRequest(model::Jig jig, double toleranceMm) const {
  acq::FieldCheckRequest r;
  r.jig = std::move(jig);
  r.jigPose = acq::parseJigPose(source_.jigPose);
  r.db = source_.db;
  r.station = source_.station;
  r.who = source_.operatorName;
  r.toleranceMm = toleranceMm;
  r.digitizer = source_.digitizer;
  r.simulated = source_.simulate;
  r.simulation = source_.simulation;
  r.simulation.mistakes = false;
  return r;
}

void FieldView::launchDivots(const QString& what, acq::FieldCheckRequest r,
                             std::function<void(acq::FieldCheckRun&, Mail&)> go) {
  launch(what, [this, r = std::move(r), go = std::move(go)]() mutable {
    acq::FieldCheckListener l;
    l.onPrompt = [this](const std::string& text) {
      post([&](Mail& m) { m.prompts.push_back(QString::fromStdString(text)); });
    };
    l.onDecision = [this](const acq::JigCapture::Decision& d) {
      post([&](Mail& m) { m.decisions.push_back(decisionText(d)); });
    };
    acq::FieldCheckRun run(std::move(r), l);
    post([&](Mail&) {
      stopRun_ = [&run] { run.stop(); };
      undoRun_ = [&run] { run.undo(); };
      if (stopAsked_) run.stop();
    });
    Mail result;
    go(run, result);
    post([&](Mail& m) {
      stopRun_ = nullptr;
      undoRun_ = nullptr;
      m.check = std::move(result.check);
      m.sentinels = std::move(result.sentinels);
    });
  });
}

QString FieldView::startCheck() {
  acq::FieldCheckRequest r;
  try {
    r = divotRequest(
        model::readJigFile(jig_->text().trimmed().isEmpty() ? sampleJig() : jig_->text().trimmed().toStdString()),
        tolerance_->value());
  } catch (const std::exception& e) {
    return tr("Cannot check the field: %1").arg(QString::fromStdString(e.what()));
  }
  if (!r.simulated && r.digitizer.empty())
    return tr(
        "Cannot check the field: no digitizer — choose one in the capture's set-up, or start the station "
        "with --simulate");
  map_->setMap(std::nullopt);
  const QString what = tr("Checking the field with %1 divots…").arg(r.jig.points.size());
  launchDivots(what, std::move(r), [](acq::FieldCheckRun& run, Mail& result) { result.check = run.run(); });
  return {};
}

QString FieldView::startTipCalibration(const devices::Vec3& simTipMm) {
  acq::TipCalibrationRequest r;
  r.db = source_.db;
  r.station = source_.station;
  r.who = source_.operatorName;
  r.digitizer = source_.digitizer;
  r.simulated = source_.simulate;
  r.simulation = source_.simulation;
  r.simulation.mistakes = false;
  r.simulation.stylusTipMm = simTipMm;
  if (!r.simulated && r.digitizer.empty())
    return tr(
        "Cannot calibrate the tip: no digitizer — choose one in the capture's set-up, or start the station "
        "with --simulate");
  map_->setMap(std::nullopt);
  launch(tr("Calibrating the stylus tip…"), [this, r = std::move(r)]() mutable {
    acq::TipCalibrationListener l;
    l.onPrompt = [this](const std::string& text) {
      post([&](Mail& m) { m.prompts.push_back(QString::fromStdString(text)); });
    };
    l.onRefused = [this](const std::string& text) {
      post([&](Mail& m) { m.decisions.push_back(tr("rejected: %1").arg(QString::fromStdString(text))); });
    };
    acq::TipCalibrationRun run(std::move(r), l);
    post([&](Mail&) {
      stopRun_ = [&run] { run.stop(); };
      if (stopAsked_) run.stop();
    });
    std::optional<acq::TipCalibration> result = run.run();
    post([&](Mail& m) {
      stopRun_ = nullptr;
      m.tip = std::move(result);
    });
  });
  return {};
}

QString FieldView::startSentinels(const acq::FieldCalibration& check, int count,
                                  std::function<void(std::optional<acq::FieldSentinels>)> done) {
  acq::FieldCheckRequest r;
  try {
    r = divotRequest(acq::sentinelJig(check.jig, count), check.result.toleranceMm);
  } catch (const std::exception& e) {
    return QString::fromStdString(e.what());
  }
  sentinelsDone_ = std::move(done);
  launchDivots(tr("Sentinel divots of field check %1, before the capture…").arg(check.id), std::move(r),
               [check](acq::FieldCheckRun& run, Mail& result) { result.sentinels = run.runSentinels(check); });
  return {};
}

void FieldView::undo() {
  const std::lock_guard lock(mutex_);
  if (undoRun_) undoRun_();
}

void FieldView::stop() {
  {
    const std::lock_guard lock(mutex_);
    stopAsked_ = true;  // a run still being set up stops as soon as it can be
    if (stopRun_) stopRun_();
  }
  if (worker_.joinable()) worker_.join();
  drain();
}

void FieldView::drain() {
  Mail m;
  {
    // The prompts and decisions so far; the result only with the end (posted after it), so a
    // result is never taken apart from the end that acts on it.
    const std::lock_guard lock(mutex_);
    if (mail_.ended) {
      m = std::move(mail_);
      mail_ = Mail{};
    } else {
      m.prompts = std::exchange(mail_.prompts, {});
      m.decisions = std::exchange(mail_.decisions, {});
    }
  }
  if (!m.prompts.empty()) prompt_->setText(m.prompts.back());
  for (const QString& d : m.decisions) decisions_->addItem(d);
  if (!m.decisions.empty()) decisions_->scrollToBottom();
  if (!m.ended) return;
  if (worker_.joinable()) worker_.join();
  finished_ = true;
  for (QPushButton* b : {check_, tip_}) b->setEnabled(true);
  for (QPushButton* b : {undo_, stop_}) b->setEnabled(false);
  auto done = std::move(sentinelsDone_);
  sentinelsDone_ = nullptr;
  if (m.failure) {
    prompt_->setText(tr("Stopped."));
    result_->setText(*m.failure);
  } else if (m.check) {
    showCheck(*m.check);
  } else if (m.tip) {
    prompt_->setText(m.tip->result.verdict == "pass" ? tr("The stylus tip is calibrated.")
                                                     : tr("The pivot was too loose: calibrate again."));
    result_->setText(QString::fromStdString(acq::tipCalibrationSummaryText(*m.tip)));
  } else if (m.sentinels) {
    prompt_->setText(m.sentinels->moved() ? tr("The field moved since the check: check it again.")
                                          : tr("The sentinel divots held."));
    result_->setText(QString::fromStdString(m.sentinels->words()));
  } else {
    prompt_->setText(tr("Stopped: nothing was stored."));
  }
  if (done) done(m.failure ? std::nullopt : m.sentinels);
  emit finished();
}

void FieldView::showCheck(const acq::FieldCalibration& c) {
  const std::string title = "Field check " + std::to_string(c.id) + " · " + c.device + " · " + c.createdUtc;
  map_->setMap(model::fieldErrorMapLayout({&c.jig, &c.result.fit, c.result.toleranceMm, c.result.verdict, title}));
  prompt_->setText(c.result.verdict == "pass"          ? tr("The field passes.")
                   : c.result.verdict == "correctable" ? tr("The field is bent, and the correction brings it within "
                                                            "tolerance: capture through this check.")
                                                       : tr("The field fails: move the metal away and check again."));
  result_->setText(QString::fromStdString(acq::fieldCheckSummaryText(c)));
}

QString FieldView::promptText() const {
  return prompt_->text();
}

QString FieldView::resultText() const {
  return result_->text();
}

QStringList FieldView::decisions() const {
  QStringList all;
  for (int i = 0; i < decisions_->count(); ++i) all << decisions_->item(i)->text();
  return all;
}

}  // namespace leafdig::station
