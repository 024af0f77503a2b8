#include "review/review_view.hpp"

#include <QChart>
#include <QChartView>
#include <QDialog>
#include <QDialogButtonBox>
#include <QDoubleSpinBox>
#include <QFormLayout>
#include <QHBoxLayout>
#include <QHeaderView>
#include <QInputDialog>
#include <QLineSeries>
#include <QPushButton>
#include <QScatterSeries>
#include <QScrollArea>
#include <QScrollBar>
#include <QSplitter>
#include <QVBoxLayout>
#include <QValueAxis>
#include <algorithm>
#include <set>

#include "leafdig/db/history.hpp"
#include "leafdig/db/lab.hpp"
#include "leafdig/model/errors.hpp"
#include "preview/compact_chart.hpp"
#include "review/correction_dialog.hpp"
#include "review/export_dialog.hpp"

namespace leafdig::station {
namespace acq = leafdig::acquisition;

namespace {

// A short name for the markers table (the full name is the cell's tooltip and data).
QString shortName(acq::What w) {
  switch (w) {
    case acq::What::MidribThickness: return QStringLiteral("midrib");
    case acq::What::VeinOriginThickness: return QStringLiteral("vein origin");
    case acq::What::EdgeThickness: return QStringLiteral("margin (d)");
    case acq::What::PointThickness: return QStringLiteral("at point");
    default: return QString::fromLatin1(acq::toString(w));
  }
}

QTableWidgetItem* cell(const QString& text) {
  auto* c = new QTableWidgetItem(text);
  c->setFlags(c->flags() & ~Qt::ItemIsEditable);
  return c;
}

const char* kBanner = "QLabel { background:#4a148c; color:white; padding:10px; border-radius:6px; font-weight:bold; }";

}  // namespace

ReviewView::ReviewView(const StationSettings& settings, QWidget* parent) : QWidget(parent), settings_(settings) {
  auto* outer = new QVBoxLayout(this);
  banner_ = new QLabel(tr("REVIEW · choose a session"), this);
  banner_->setStyleSheet(kBanner);
  banner_->setWordWrap(true);
  outer->addWidget(banner_);

  auto* filters = new QHBoxLayout;
  project_ = new QComboBox;
  plant_ = new QComboBox;
  status_ = new QComboBox;
  operator_ = new QComboBox;
  date_ = new QLineEdit;
  date_->setPlaceholderText(tr("date, e.g. 2026-11"));
  curator_ = new QLineEdit(QString::fromLocal8Bit(qgetenv("USER")));
  curator_->setPlaceholderText(tr("curator's name"));
  for (auto* c : {project_, plant_, status_, operator_})
    connect(c, &QComboBox::currentTextChanged, this, [this] { applyFilters(); });
  connect(date_, &QLineEdit::textChanged, this, [this] { applyFilters(); });
  auto* refresh = new QPushButton(tr("Refresh"));
  connect(refresh, &QPushButton::clicked, this, &ReviewView::refreshSessions);
  filters->addWidget(new QLabel(tr("Project")));
  filters->addWidget(project_);
  filters->addWidget(new QLabel(tr("Plant")));
  filters->addWidget(plant_);
  filters->addWidget(new QLabel(tr("Status")));
  filters->addWidget(status_);
  filters->addWidget(new QLabel(tr("Operator")));
  filters->addWidget(operator_);
  filters->addWidget(date_);
  filters->addWidget(refresh);
  filters->addStretch(1);
  filters->addWidget(new QLabel(tr("Curator")));
  filters->addWidget(curator_);
  outer->addLayout(filters);

  // Plant sessions are reviewed in the Plant tab: say how many there are, and where.
  plantNote_ = new QLabel;
  plantNote_->setVisible(false);
  outer->addWidget(plantNote_);

  auto* split = new QSplitter(Qt::Vertical, this);
  sessions_ = new QTableWidget(0, 9, split);
  sessions_->setHorizontalHeaderLabels({tr("id"), tr("project"), tr("plant"), tr("leaf"), tr("status"), tr("operator"),
                                        tr("created (UTC)"), tr("events"), tr("station")});
  sessions_->setSelectionBehavior(QAbstractItemView::SelectRows);
  sessions_->horizontalHeader()->setStretchLastSection(true);
  sessions_->verticalHeader()->hide();
  connect(sessions_, &QTableWidget::itemSelectionChanged, this, [this] {
    if (filling_) return;
    const auto rows = sessions_->selectionModel()->selectedRows();
    if (rows.size() == 1) (void)openSession(sessions_->item(rows[0].row(), 0)->text().toLongLong());
  });

  auto* detail = new QSplitter(split);
  markers_ = new QTableWidget(0, 6, detail);
  markers_->setHorizontalHeaderLabels({tr("item"), tr("row"), tr("point"), tr("value"), tr("event"), tr("flag")});
  markers_->setSelectionBehavior(QAbstractItemView::SelectRows);
  markers_->setSelectionMode(QAbstractItemView::SingleSelection);
  markers_->verticalHeader()->hide();
  markers_->horizontalHeader()->setStretchLastSection(true);
  connect(markers_, &QTableWidget::itemSelectionChanged, this, [this] {
    if (filling_) return;
    const auto rows = markers_->selectionModel()->selectedRows();
    if (rows.size() == 1) preview_->setHighlight(itemOfRow(rows[0].row()));
  });
  auto* middle = new QWidget(detail);
  auto* mid = new QVBoxLayout(middle);
  mid->setContentsMargins(0, 0, 0, 0);
  preview_ = new PreviewWidget(middle);
  preview_->setLive(false);
  connect(preview_, &PreviewWidget::itemPicked, this, [this](const acq::Item& i) { selectItem(i); });
  mid->addWidget(preview_, 1);
  auto* replay = new QHBoxLayout;
  auto* back = new QPushButton(QStringLiteral("◀"));
  auto* forward = new QPushButton(QStringLiteral("▶"));
  for (auto* b : {back, forward}) b->setMaximumWidth(44);  // the slider keeps the room
  slider_ = new QSlider(Qt::Horizontal);
  slider_->setMinimumWidth(120);
  slider_->setEnabled(false);
  replayLabel_ = new QLabel;
  connect(back, &QPushButton::clicked, this, [this] { slider_->setValue(slider_->value() - 1); });
  connect(forward, &QPushButton::clicked, this, [this] { slider_->setValue(slider_->value() + 1); });
  connect(slider_, &QSlider::valueChanged, this, [this](int v) {
    if (!filling_) replayTo(v);
  });
  replay->addWidget(new QLabel(tr("Replay")));
  replay->addWidget(back);
  replay->addWidget(slider_, 1);
  replay->addWidget(forward);
  replay->addWidget(replayLabel_);
  mid->addLayout(replay);

  auto* right = new QWidget(detail);
  auto* rl = new QVBoxLayout(right);
  rl->setContentsMargins(0, 0, 0, 0);
  chart_ = new QChartView(right);
  chart_->setRenderHint(QPainter::Antialiasing);
  chart_->setMinimumHeight(240);
  metrics_ = new QLabel;
  metrics_->setTextFormat(Qt::PlainText);  // it shows curators' reasons from the file or the server
  metrics_->setWordWrap(true);
  metrics_->setAlignment(Qt::AlignLeft | Qt::AlignTop);
  metrics_->setTextInteractionFlags(Qt::TextSelectableByMouse);
  // The metrics grow (interval, constraint, warnings): they scroll rather than push the
  // chart and the flags under each other on a 768-pixel screen.
  auto* metricsScroll = new QScrollArea(right);
  metricsScroll->setWidget(metrics_);
  metricsScroll->setWidgetResizable(true);
  metricsScroll->setFrameShape(QFrame::NoFrame);
  metricsScroll->setMinimumHeight(70);
  flags_ = new QListWidget(right);
  connect(flags_, &QListWidget::itemClicked, this, [this](QListWidgetItem* it) {
    const auto what = acq::whatFromString(it->data(Qt::UserRole).toString().toStdString());
    if (const auto* i = current_ ? acq::findItem(current_->engine.items(), what, it->data(Qt::UserRole + 1).toInt(),
                                                 it->data(Qt::UserRole + 2).toInt())
                                 : nullptr)
      selectItem(*i);
  });
  auto* actions = new QHBoxLayout;
  auto* correctB = correctB_ = new QPushButton(tr("Correct…"));
  auto* approveB = approveB_ = new QPushButton(tr("Approve"));
  auto* rejectB = rejectB_ = new QPushButton(tr("Reject…"));
  auto* reopenB = reopenB_ = new QPushButton(tr("Reopen…"));
  for (auto* b : {correctB, approveB, rejectB, reopenB}) b->setEnabled(false);  // until a session is open
  auto* exportB = new QPushButton(tr("Export…"));
  connect(correctB, &QPushButton::clicked, this, &ReviewView::correctSelected);
  connect(approveB, &QPushButton::clicked, this, [this] { (void)approve(curator_->text()); });
  connect(rejectB, &QPushButton::clicked, this, [this] {
    bool ok = false;
    const QString why =
        QInputDialog::getText(this, tr("Reject"), tr("What is wrong with this session?"), QLineEdit::Normal, {}, &ok);
    if (ok) (void)reject(curator_->text(), why);
  });
  connect(reopenB, &QPushButton::clicked, this, [this] {
    bool ok = false;
    const QString why = QInputDialog::getText(this, tr("Reopen"), tr("Why does the decision no longer stand?"),
                                              QLineEdit::Normal, {}, &ok);
    if (ok) (void)reopen(curator_->text(), why);
  });
  connect(exportB, &QPushButton::clicked, this, [this] {
    std::vector<std::int64_t> ids;
    for (const auto& r : sessions_->selectionModel()->selectedRows())
      ids.push_back(sessions_->item(r.row(), 0)->text().toLongLong());
    ExportDialog d(settings_, this);
    d.setSessions(ids);
    if (d.exec() == QDialog::Accepted) d.run(dbPath_);
  });
  for (auto* b : {correctB, approveB, rejectB, reopenB, exportB}) actions->addWidget(b);
  flags_->setMinimumHeight(40);
  rl->addWidget(chart_, 3);
  rl->addWidget(metricsScroll, 2);
  rl->addWidget(new QLabel(tr("Flags")));
  rl->addWidget(flags_, 1);
  rl->addLayout(actions);
  detail->setStretchFactor(1, 1);
  detail->setSizes({330, 640, 560});
  split->setSizes({140, 620});
  outer->addWidget(split, 1);
}

ReviewView::~ReviewView() = default;

void ReviewView::setSettings(const StationSettings& s) {
  settings_ = s;
  if (current_) fill();
}

void ReviewView::setDatabase(const std::string& path) {
  if (path == dbPath_ && store_) return;
  dbPath_ = path;
  store_.reset();
  current_.reset();
  refreshSessions();
}

void ReviewView::refreshSessions() {
  all_.clear();
  try {
    if (!store_ && !dbPath_.empty()) store_ = db::openEventStore(dbPath_, false);
    // On the lab server a review is signed by the login that writes it (lab schema 10).
    if (const auto login = store_ ? store_->login() : std::nullopt) curator_->setText(QString::fromStdString(*login));
    if (store_) all_ = store_->sessions();
    // Plant sessions are reviewed as plants (docs/plants.md); this view reviews leaves and says
    // where the plants are.
    const auto plants =
        std::count_if(all_.begin(), all_.end(), [](const db::SessionInfo& s) { return s.kind != "leaf"; });
    all_.erase(std::remove_if(all_.begin(), all_.end(), [](const db::SessionInfo& s) { return s.kind != "leaf"; }),
               all_.end());
    plantNote_->setText(
        plants == 0 ? QString()
        : plants == 1
            ? tr("1 plant session in this database: review it in the Plant tab.")
            : tr("%1 plant sessions in this database: review them in the Plant tab.").arg(static_cast<int>(plants)));
    plantNote_->setVisible(plants > 0);
  } catch (const std::exception& e) {
    banner_->setText(tr("REVIEW · cannot open %1: %2")
                         .arg(QString::fromStdString(db::redactUrl(dbPath_)), QString::fromStdString(e.what())));
    return;
  }
  filling_ = true;
  const auto refill = [](QComboBox* c, const std::set<QString>& values) {
    const QString keep = c->currentText();
    c->clear();
    c->addItem(tr("all"));
    for (const auto& v : values) c->addItem(v);
    c->setCurrentText(keep.isEmpty() ? tr("all") : keep);
  };
  std::set<QString> projects, plants, statuses, operators;
  for (const auto& s : all_) {
    projects.insert(QString::fromStdString(s.project));
    plants.insert(QString::fromStdString(s.plant));
    statuses.insert(QString::fromStdString(s.status));
    operators.insert(QString::fromStdString(s.operatorName));
  }
  refill(project_, projects);
  refill(plant_, plants);
  refill(status_, statuses);
  refill(operator_, operators);
  filling_ = false;
  applyFilters();
}

void ReviewView::applyFilters() {
  if (filling_) return;
  filling_ = true;
  const auto pass = [](const QComboBox* c, const std::string& v) {
    return c->currentIndex() <= 0 || c->currentText() == QString::fromStdString(v);
  };
  sessions_->setRowCount(0);
  for (auto it = all_.rbegin(); it != all_.rend(); ++it) {
    const auto& s = *it;
    if (!pass(project_, s.project) || !pass(plant_, s.plant) || !pass(status_, s.status) ||
        !pass(operator_, s.operatorName))
      continue;
    if (!date_->text().isEmpty() && !QString::fromStdString(s.createdUtc).startsWith(date_->text().trimmed())) continue;
    const int r = sessions_->rowCount();
    sessions_->insertRow(r);
    const QStringList values{QString::number(s.id), QString::fromStdString(s.project), QString::fromStdString(s.plant),
                             QString::number(s.leafPosition), QString::fromStdString(s.status),
                             QString::fromStdString(s.operatorName), QString::fromStdString(s.createdUtc),
                             QString::number(s.headSeq),
                             // the station that captured it, and its id there (the lab server's ids are its own)
                             QString::fromStdString(s.station + ":" + std::to_string(s.stationSessionId))};
    for (int c = 0; c < values.size(); ++c) sessions_->setItem(r, c, cell(values[c]));
  }
  sessions_->resizeColumnsToContents();
  filling_ = false;
}

bool ReviewView::openSession(std::int64_t id, std::int64_t upToSeq) {
  try {
    if (!store_) refreshSessions();
    if (!store_) return false;
    current_ = acq::openForReview(*store_, id, upToSeq);
  } catch (const std::exception& e) {
    current_.reset();
    banner_->setText(tr("REVIEW · session %1 cannot be opened: %2").arg(id).arg(QString::fromStdString(e.what())));
    return false;
  }
  fill();
  return true;
}

void ReviewView::replayTo(std::int64_t seq) {
  if (!current_) return;
  (void)openSession(current_->info.id, seq >= current_->totalEvents ? 0 : std::max<std::int64_t>(1, seq));
}

std::optional<acq::Item> ReviewView::itemOfRow(int row) const {
  if (!current_ || row < 0) return std::nullopt;
  const auto* w = markers_->item(row, 0);
  if (!w) return std::nullopt;
  const auto* i =
      acq::findItem(current_->engine.items(), acq::whatFromString(w->data(Qt::UserRole).toString().toStdString()),
                    markers_->item(row, 1)->text().toInt(), markers_->item(row, 2)->text().toInt());
  return i ? std::optional<acq::Item>(*i) : std::nullopt;
}

void ReviewView::selectItem(const acq::Item& item) {
  for (int r = 0; r < markers_->rowCount(); ++r) {
    if (markers_->item(r, 0)->data(Qt::UserRole).toString() == QString::fromLatin1(acq::toString(item.what)) &&
        markers_->item(r, 1)->text().toInt() == item.row && markers_->item(r, 2)->text().toInt() == item.col) {
      markers_->selectRow(r);
      markers_->scrollToItem(markers_->item(r, 0));
      break;
    }
  }
  preview_->setHighlight(item);
}

void ReviewView::fill() {
  const auto& r = *current_;
  filling_ = true;
  // The chain is recomputed when the session or its head changed, not at every replay step.
  if (chainOf_ != std::make_pair(r.info.id, r.info.headSeq)) {
    chain_ = store_->verify(r.info.id);
    chainOf_ = {r.info.id, r.info.headSeq};
  }
  const db::ChainReport& chain = chain_;
  const bool partial = r.replayedEvents < r.totalEvents;
  banner_->setText(
      tr("REVIEW · session %1 · %2 / %3 / leaf %4 · %5 · operator %6 · chain %7%8")
          .arg(r.info.id)
          .arg(QString::fromStdString(r.info.project), QString::fromStdString(r.info.plant))
          .arg(r.info.leafPosition)
          .arg(QString::fromStdString(r.info.status), QString::fromStdString(r.info.operatorName))
          .arg(chain.ok ? tr("OK (%1 events)").arg(chain.events)
                        : tr("BROKEN at event %1: %2")
                              .arg(chain.firstBadSeq.value_or(0))
                              .arg(QString::fromStdString(chain.problem)))
          .arg(partial ? tr(" · replay at event %1 of %2").arg(r.replayedEvents).arg(r.totalEvents) : QString()));
  const auto& items = r.engine.items();
  const auto flags = acq::reviewFlags(items);
  markers_->setRowCount(0);
  for (const auto& i : items) {
    const int row = markers_->rowCount();
    markers_->insertRow(row);
    QString value;
    if (acq::isStylusItem(i.what))
      value = QString("%1, %2, %3")
                  .arg(settings_.number(i.positionMm[0], 1), settings_.number(i.positionMm[1], 1),
                       settings_.number(i.positionMm[2], 1));
    else
      value = settings_.number(i.valueMm, 3);
    const auto seq = r.seqs.find({static_cast<int>(i.what), i.row, i.col});
    QString flag = QString::fromStdString(i.flag);
    for (const auto& f : flags)
      if (f.what == i.what && f.row == i.row && (f.col == i.col || f.col == 0) && f.text != i.flag)
        flag += (flag.isEmpty() ? "" : "; ") + QString::fromStdString(f.text);
    const QStringList values{shortName(i.what),
                             QString::number(i.row),
                             QString::number(i.col),
                             value,
                             seq != r.seqs.end() ? QString::number(seq->second) : QString(),
                             flag};
    for (int c = 0; c < values.size(); ++c) {
      auto* w = cell(values[c]);
      if (!flag.isEmpty()) w->setBackground(QColor(255, 224, 178));
      if (c == values.size() - 1 && !flag.isEmpty()) w->setToolTip(flag);
      if (c == 0) {
        w->setData(Qt::UserRole, QString::fromLatin1(acq::toString(i.what)));  // what the table's rows mean
        w->setToolTip(QString::fromLatin1(acq::toString(i.what)));
      }
      markers_->setItem(row, c, w);
    }
  }
  markers_->setHorizontalHeaderLabels(
      {tr("item"), tr("row"), tr("point"), tr("value (%1)").arg(settings_.units), tr("event"), tr("flag")});
  // Every column at its content's width (a long flag is capped; its cell's tooltip has it
  // whole), and the table at least that wide: no value is cut off.
  QHeaderView* header = markers_->horizontalHeader();
  header->setStretchLastSection(false);
  markers_->resizeColumnsToContents();
  const int last = markers_->columnCount() - 1;
  markers_->setColumnWidth(last, std::min(markers_->columnWidth(last), 220));
  const int contentWidth = header->length();
  header->setStretchLastSection(true);
  markers_->setMinimumWidth(contentWidth + markers_->frameWidth() * 2 +
                            markers_->verticalScrollBar()->sizeHint().width() + 2);
  flags_->clear();
  for (const auto& f : flags) {
    auto* it = new QListWidgetItem(QString("%1 row %2 point %3: %4")
                                       .arg(QString::fromLatin1(acq::toString(f.what)))
                                       .arg(f.row)
                                       .arg(f.col)
                                       .arg(QString::fromStdString(f.text)),
                                   flags_);
    it->setData(Qt::UserRole, QString::fromLatin1(acq::toString(f.what)));
    it->setData(Qt::UserRole + 1, f.row);
    it->setData(Qt::UserRole + 2, f.what == acq::What::MidribThickness && f.col == 0 ? 4 : f.col);
  }
  if (flags.empty()) flags_->addItem(tr("no flags"));
  // Metrics need the whole leaf; a replay in progress or an unfinished capture has none.
  try {
    const acq::LeafSummary s = acq::summarize(r);
    QString text = tr("Blade area %1 mm² (%2 cm²) · marker-grid Heron area %3 mm²")
                       .arg(s.metrics.blade.areaMm2, 0, 'f', 0)
                       .arg(s.metrics.blade.areaMm2 / 100.0, 0, 'f', 1)
                       .arg(s.metrics.markerGridHeronAreaMm2, 0, 'f', 0);
    if (s.metrics.areaInterval) {
      const auto& u = *s.metrics.areaInterval;
      text += "\n" + tr("95 % interval %1 – %2 mm² (digitizer accuracy %3 mm, the rows' interpolation, margin: %4)")
                         .arg(u.low95Mm2, 0, 'f', 0)
                         .arg(u.high95Mm2, 0, 'f', 0)
                         .arg(u.sigmaMm, 0, 'f', 2)
                         .arg(QString::fromStdString(u.margin));
      if (!u.note.empty()) text += "\n" + tr("Note: %1").arg(QString::fromStdString(u.note));
    }
    if (s.metrics.silhouette)
      text += "\n" + tr("Silhouette from above %1 mm² · STAR %2 (silhouette / the mesh's %3 mm²)")
                         .arg(s.metrics.silhouette->silhouetteMm2, 0, 'f', 0)
                         .arg(s.metrics.silhouette->star, 0, 'f', 3)
                         .arg(s.metrics.silhouette->meshAreaMm2, 0, 'f', 0);
    if (s.metrics.areaConstraint) {
      const auto& a = *s.metrics.areaConstraint;
      text += "\n" + tr("Measured area %1 mm² · model differs by %2 % · %3")
                         .arg(a.measuredMm2, 0, 'f', 0)
                         .arg(a.differencePercent, 0, 'f', 1)
                         .arg(a.exceeded ? tr("OUTSIDE the %1 % constraint").arg(a.thresholdPercent)
                                         : tr("within the %1 % constraint").arg(a.thresholdPercent));
    } else {
      text += "\n" + tr("No measured leaf area: the area constraint is not checked.");
    }
    for (const auto& w : s.metrics.warnings) text += "\n" + tr("Warning: %1").arg(QString::fromStdString(w.message));
    metrics_->setText(text);
  } catch (const std::exception& e) {
    metrics_->setText(tr("No metrics yet: %1").arg(QString::fromStdString(e.what())));
  }
  // Who decided what (issue 49): every decision and correction, under the metrics.
  const auto history = db::reviewHistory(store_->events(r.info.id));
  if (!history.empty()) {
    QString text = metrics_->text() + "\n\n" + tr("Review:");
    for (const auto& h : history) {
      QString line = QString::fromStdString(h.action);
      if (h.action == "reopened") line += tr(" (was %1)").arg(QString::fromStdString(h.reopens));
      if (h.action == "corrected") {
        line += " " + QString::fromStdString(h.what);
        if (h.row) line += tr(" row %1").arg(*h.row);
        if (h.col) line += tr(" point %1").arg(*h.col);
        if (const auto moved = h.movedMm()) line += tr(", moved %1 mm").arg(*moved, 0, 'f', 1);
        if (h.fromValueMm && h.toValueMm)
          line += tr(": %1 → %2 mm").arg(*h.fromValueMm, 0, 'f', 3).arg(*h.toValueMm, 0, 'f', 3);
      }
      line += tr(" by %1 at %2").arg(QString::fromStdString(h.who), QString::fromStdString(h.utc));
      if (!h.why.empty()) line += ": " + QString::fromStdString(h.why);
      text += "\n" + line;
    }
    metrics_->setText(text);
  }
  const bool decidable = decisionsEnabled();
  for (auto* b : {correctB_, approveB_, rejectB_}) {
    b->setEnabled(decidable);
    b->setToolTip(decidable ? QString()
                  : partial ? tr("the replay shows an earlier state: move the slider to the end")
                            : tr("only a complete session is corrected, approved or rejected; this one is %1")
                                  .arg(QString::fromStdString(r.info.status)));
  }
  // A decision stands until a curator reopens it, saying why.
  const bool reopenable = (r.info.status == "approved" || r.info.status == "rejected") && !partial;
  reopenB_->setEnabled(reopenable);
  reopenB_->setToolTip(reopenable ? tr("make this %1 session complete again, to correct and decide anew")
                                        .arg(QString::fromStdString(r.info.status))
                                  : tr("only an approved or rejected session is reopened"));
  acq::Snapshot snap;
  snap.session = r.info.id;
  snap.items = items;
  snap.step = r.engine.step();
  snap.rowsEnded = r.engine.rowsEnded();
  snap.preview = std::make_shared<acq::Preview>(acq::buildPreview(items, r.settings));
  preview_->show(snap);
  slider_->setEnabled(true);
  slider_->setRange(1, static_cast<int>(std::max<std::int64_t>(1, r.totalEvents)));
  slider_->setValue(static_cast<int>(r.replayedEvents));
  std::string kind;
  if (r.replayedEvents > 0) {
    const auto ev = store_->events(r.info.id, r.replayedEvents);
    if (!ev.empty()) kind = ev.front().kind;
  }
  replayLabel_->setText(tr("%1 / %2 %3").arg(r.replayedEvents).arg(r.totalEvents).arg(QString::fromStdString(kind)));
  replayLabel_->setToolTip(
      tr("event %1 of %2: %3").arg(r.replayedEvents).arg(r.totalEvents).arg(QString::fromStdString(kind)));
  fillChart(flags);
  filling_ = false;
}

void ReviewView::fillChart(const std::vector<acq::ReviewFlag>& flags) {
  // Compact: at 1366 × 768 the chart has about 250 px, and Qt Charts elides labels that
  // do not fit (a test looks for "…" in every label).
  QFont small;
  QChart* chart = compactChart(tr("Thickness along the leaf (row 1 = tip)"), small);
  chart->legend()->setFont(small);
  std::map<acq::What, QLineSeries*> series;
  const std::pair<acq::What, QString> kinds[] = {{acq::What::MidribThickness, tr("midrib")},
                                                 {acq::What::VeinOriginThickness, tr("vein origin")},
                                                 {acq::What::PointThickness, tr("points (mean per row)")}};
  auto* flagged = new QScatterSeries;
  flagged->setName(tr("flagged"));
  flagged->setMarkerSize(12);
  flagged->setColor(QColor(229, 57, 53));
  double maxV = 0.1;
  int maxRow = 1;
  for (const auto& [what, name] : kinds) {
    std::map<int, std::pair<double, int>> byRow;
    for (const auto& i : current_->engine.items())
      if (i.what == what) {
        byRow[i.row].first += i.valueMm;
        ++byRow[i.row].second;
        for (const auto& f : flags)
          if (f.what == i.what && f.row == i.row && (f.col == 0 || f.col == i.col)) flagged->append(i.row, i.valueMm);
      }
    if (byRow.empty()) continue;
    auto* s = new QLineSeries;
    s->setName(name);
    s->setPointsVisible(true);
    for (const auto& [row, sum] : byRow) {
      const double v = sum.first / sum.second;
      s->append(row, v);
      maxV = std::max(maxV, v);
      maxRow = std::max(maxRow, row);
    }
    chart->addSeries(s);
    series[what] = s;
  }
  chart->addSeries(flagged);
  auto* x = new QValueAxis;
  x->setTitleText(tr("row"));
  x->setRange(0.5, maxRow + 0.5);
  x->setLabelFormat("%d");
  x->setTickType(QValueAxis::TicksDynamic);  // whole rows: 1, 2, 3 … (every other one past 10)
  x->setTickAnchor(1);
  x->setTickInterval(maxRow > 10 ? 2 : 1);
  auto* y = new QValueAxis;
  y->setTitleText(tr("mm"));  // short: a vertical title longer than the plot is cut
  y->setRange(0, maxV * 1.15);
  showChart(chart_, chart, x, y);
}

void ReviewView::correctSelected() {
  const auto rows = markers_->selectionModel()->selectedRows();
  const auto item = rows.size() == 1 ? itemOfRow(rows[0].row()) : std::nullopt;
  if (!item) {
    banner_->setText(tr("REVIEW · select the item to correct in the table or the 3D view"));
    return;
  }
  acq::Correction stored;
  stored.what = item->what;
  stored.row = item->row;
  stored.col = item->col;
  if (acq::isStylusItem(item->what))
    stored.positionMm = item->positionMm;
  else
    stored.valueMm = item->valueMm;
  std::optional<acq::Correction> asked = askCorrection(
      this, tr("Correct %1").arg(QString::fromLatin1(acq::toString(item->what))), {{{}, stored}}, tr("thickness"));
  if (!asked) return;
  acq::Correction c = *asked;
  c.who = curator_->text().toStdString();
  // The effect shown before anything is written; the curator writes it or not.
  try {
    const acq::CorrectionEffect effect = acq::previewCorrection(*store_, current_->info.id, c);
    if (!confirmCorrection(this, effect, settings_.confirmMoveAboveMm)) {
      banner_->setText(tr("REVIEW · the correction was not written"));
      return;
    }
    c.seenHead = effect.head;  // what the curator confirmed: refused if the session moved on since
  } catch (const std::exception& e) {
    banner_->setText(tr("REVIEW · not corrected: %1").arg(QString::fromStdString(e.what())));
    return;
  }
  (void)correct(c);
}

QString ReviewView::correct(const acq::Correction& c) {
  if (!current_) return tr("no session open");
  try {
    (void)acq::correct(*store_, current_->info.id, c);
  } catch (const std::exception& e) {
    banner_->setText(tr("REVIEW · not corrected: %1").arg(QString::fromStdString(e.what())));
    return QString::fromStdString(e.what());
  }
  const auto id = current_->info.id;
  (void)openSession(id);
  if (const auto* i = acq::findItem(current_->engine.items(), c.what, c.row, c.col)) selectItem(*i);
  return {};
}

bool ReviewView::decisionsEnabled() const {
  return current_ && current_->info.status == "complete" && current_->replayedEvents >= current_->totalEvents;
}

bool ReviewView::reopenEnabled() const {
  return reopenB_->isEnabled();
}

QString ReviewView::approve(const QString& who) {
  return decide("approved", tr("not approved"), who, {});
}

QString ReviewView::reject(const QString& who, const QString& why) {
  return decide("rejected", tr("not rejected"), who, why);
}

QString ReviewView::reopen(const QString& who, const QString& why) {
  if (!current_) return tr("no session open");
  try {
    (void)acq::reopen(*store_, current_->info.id, who.toStdString(), why.toStdString());
  } catch (const std::exception& e) {
    banner_->setText(tr("REVIEW · not reopened: %1").arg(QString::fromStdString(e.what())));
    return QString::fromStdString(e.what());
  }
  const auto id = current_->info.id;
  refreshSessions();
  (void)openSession(id);
  return {};
}

QString ReviewView::decide(const char* status, const QString& failed, const QString& who, const QString& why) {
  if (!current_) return tr("no session open");
  try {
    (void)acq::review(*store_, current_->info.id, status, who.toStdString(), why.toStdString());
  } catch (const std::exception& e) {
    banner_->setText(tr("REVIEW · %1: %2").arg(failed, QString::fromStdString(e.what())));
    return QString::fromStdString(e.what());
  }
  const auto id = current_->info.id;
  refreshSessions();
  (void)openSession(id);
  return {};
}

}  // namespace leafdig::station
