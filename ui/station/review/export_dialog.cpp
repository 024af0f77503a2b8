#include "review/export_dialog.hpp"

#include <QApplication>
#include <QDialogButtonBox>
#include <QFileDialog>
#include <QFormLayout>
#include <QHBoxLayout>
#include <QMessageBox>
#include <QProgressDialog>
#include <QPushButton>
#include <QVBoxLayout>

#include "leafdig/db/lab.hpp"
#include "leafdig/model/errors.hpp"

namespace leafdig::station {
namespace acq = leafdig::acquisition;

BatchResult exportBatch(const std::string& dbPath, const std::vector<std::int64_t>& sessions,
                        const acq::ExportRequest& request,
                        const std::function<bool(int, int, const QString&)>& progress) {
  BatchResult out;
  const std::unique_ptr<db::EventStore> opened = db::openEventStore(dbPath, false);
  db::EventStore& store = *opened;
  const int total = static_cast<int>(sessions.size());
  for (int k = 0; k < total; ++k) {
    const std::int64_t id = sessions[static_cast<std::size_t>(k)];
    if (!progress(k, total, QObject::tr("session %1").arg(id))) {
      out.cancelled = true;
      return out;
    }
    try {
      const auto r = acq::exportSession(store, id, request);
      out.written.insert(out.written.end(), r.written.begin(), r.written.end());
      if (const auto info = store.session(id); info && info->status != "approved")
        out.unapproved.emplace_back(id, info->status);
    } catch (const std::exception& e) {
      out.failed.emplace_back(id, e.what());  // the next session is still exported
    }
  }
  (void)progress(total, total, QObject::tr("done"));
  return out;
}

QString unapprovedWarning(const BatchResult& result) {
  if (result.unapproved.empty()) return {};
  QStringList sessions;
  for (const auto& [id, status] : result.unapproved)
    sessions << QObject::tr("session %1 (%2)").arg(id).arg(QString::fromStdString(status));
  return QObject::tr("Not approved by a curator: %1 — their numbers are as captured, unchecked.")
      .arg(sessions.join(", "));
}

ExportDialog::ExportDialog(StationSettings& settings, QWidget* parent) : QDialog(parent), settings_(settings) {
  setWindowTitle(tr("leafdig · export"));
  auto* form = new QFormLayout;
  ids_ = new QLineEdit;
  ids_->setPlaceholderText(tr("session ids, e.g. 3, 4, 7"));
  form->addRow(tr("Sessions"), ids_);
  auto* formats = new QHBoxLayout;
  for (const auto& f : acq::exportFormats()) {
    auto* c = new QCheckBox(QString::fromStdString(f));
    c->setChecked(f == "glb" || f == "model" || f == "csv");
    formats_[f] = c;
    formats->addWidget(c);
  }
  form->addRow(tr("Formats"), formats);
  frame_ = new QComboBox;
  frame_->addItem(tr("leaf frame (base at origin, midrib on +Y)"), "leaf");
  frame_->addItem(tr("digitizer frame (as captured)"), "digitizer");
  form->addRow(tr("Frame"), frame_);
  resolution_ = new QComboBox;
  for (const char* r : {"export", "paper", "preview"}) resolution_->addItem(r, r);
  form->addRow(tr("Mesh resolution"), resolution_);
  mesh_ = new MeshChoice;
  form->addRow(tr("Mesh"), mesh_);
  dir_ = new QLineEdit(settings_.exportDir);
  auto* browse = new QPushButton(tr("Browse…"));
  connect(browse, &QPushButton::clicked, this, [this] {
    const QString d = QFileDialog::getExistingDirectory(this, tr("Export into"), dir_->text());
    if (!d.isEmpty()) dir_->setText(d);
  });
  auto* where = new QHBoxLayout;
  where->addWidget(dir_, 1);
  where->addWidget(browse);
  form->addRow(tr("Destination"), where);
  auto* buttons = new QDialogButtonBox(QDialogButtonBox::Ok | QDialogButtonBox::Cancel);
  buttons->button(QDialogButtonBox::Ok)->setText(tr("Export"));
  connect(buttons, &QDialogButtonBox::accepted, this, &QDialog::accept);
  connect(buttons, &QDialogButtonBox::rejected, this, &QDialog::reject);
  auto* outer = new QVBoxLayout(this);
  outer->addLayout(form);
  outer->addWidget(buttons);
}

void ExportDialog::setSessions(const std::vector<std::int64_t>& ids) {
  sessions_ = ids;
  QStringList s;
  for (auto id : ids) s << QString::number(id);
  ids_->setText(s.join(", "));
}

acq::ExportRequest ExportDialog::request() const {
  acq::ExportRequest r;
  for (const auto& [f, box] : formats_)
    if (box->isChecked()) r.formats.push_back(f);
  r.frame = frame_->currentData().toString().toStdString();
  r.resolution = resolution_->currentData().toString().toStdString();
  const model::MeshOptions m = mesh_->options(r.resolution);
  r.mesh = model::toString(m.method);
  r.maxErrorMm = m.maxErrorMm;
  r.seed = m.seed;
  r.outDir = dir_->text().trimmed().toStdString();
  return r;
}

BatchResult ExportDialog::run(const std::string& dbPath) {
  std::vector<std::int64_t> ids;
  for (const QString& part : ids_->text().split(QRegularExpression("[,\\s]+"), Qt::SkipEmptyParts)) {
    bool ok = false;
    const auto id = part.toLongLong(&ok);
    if (!ok || id <= 0) {
      QMessageBox::warning(this, tr("Export"), tr("'%1' is not a session id: list ids separated by commas").arg(part));
      return {};
    }
    ids.push_back(id);
  }
  const acq::ExportRequest r = request();
  if (r.formats.empty() || r.outDir.empty()) {
    QMessageBox::warning(this, tr("Export"), tr("Choose at least one format and a destination directory."));
    return {};
  }
  settings_.exportDir = dir_->text().trimmed();
  QProgressDialog progress(tr("Exporting…"), tr("Cancel"), 0, static_cast<int>(ids.size()), parentWidget());
  progress.setWindowModality(Qt::WindowModal);
  progress.setMinimumDuration(0);
  BatchResult result;
  try {
    result = exportBatch(dbPath, ids, r, [&](int done, int total, const QString& what) {
      progress.setMaximum(total);
      progress.setValue(done);
      progress.setLabelText(
          tr("Exporting %1 (%2 of %3)…").arg(what).arg(done + 1 > total ? total : done + 1).arg(total));
      QApplication::processEvents();
      return !progress.wasCanceled();
    });
  } catch (const std::exception& e) {
    QMessageBox::critical(parentWidget(), tr("Export"), QString::fromStdString(e.what()));
    return {};
  }
  QString text = tr("%1 files written to %2.").arg(result.written.size()).arg(dir_->text());
  if (result.cancelled) text += "\n" + tr("Cancelled: the remaining sessions were not exported.");
  for (const auto& [id, why] : result.failed)
    text += "\n" + tr("Session %1 not exported: %2").arg(id).arg(QString::fromStdString(why));
  // Files of sessions no curator approved say so where the person exporting sees it, as the CLI
  // does on stderr: a warning, not the information box.
  if (const QString unchecked = unapprovedWarning(result); !unchecked.isEmpty()) {
    QMessageBox::warning(parentWidget(), tr("Export"), text + "\n" + unchecked);
    return result;
  }
  QMessageBox::information(parentWidget(), tr("Export"), text);
  return result;
}

}  // namespace leafdig::station
