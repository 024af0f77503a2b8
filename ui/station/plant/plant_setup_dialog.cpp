#include "plant/plant_setup_dialog.hpp"

#include <QDialogButtonBox>
#include <QFormLayout>
#include <QVBoxLayout>
#include <filesystem>
#include <set>

#include "leafdig/model/plant/plant_protocol.hpp"

namespace leafdig::station {

namespace acq = leafdig::acquisition;
namespace m = leafdig::model;

PlantSetupDialog::PlantSetupDialog(const acq::PlantSessionSetup& defaults, const std::vector<db::SessionInfo>& known,
                                   const devices::Inventory& inventory, const QString& sampleMarkers, QWidget* parent)
    : QDialog(parent), devices_(inventory, kSimulatedDigitizer, kSimulatedCaliper) {
  setWindowTitle(tr("New plant"));
  std::set<QString> plants, projects;
  for (const db::SessionInfo& s : known) {
    if (s.kind == "plant") plants.insert(QString::fromStdString(s.plant));
    projects.insert(QString::fromStdString(s.project));
  }
  plant_ = knownNamesBox(plants, defaults.plant);
  plant_->setToolTip(tr("The plant's id; the same plant digitized again later is a new dated survey"));
  project_ = knownNamesBox(projects, defaults.project);
  operator_ = new QLineEdit(QString::fromStdString(defaults.operatorName));
  date_ = new QLineEdit;
  date_->setPlaceholderText(tr("YYYY-MM-DD (default: today)"));
  protocol_ = new QLineEdit;
  protocol_->setPlaceholderText(tr("leafdig.plant-protocol/1 file (default: tobacco, built in)"));
  markers_ = new QLineEdit(sampleMarkers);
  markers_->setToolTip(tr("The plant the virtual technician digitizes (simulated devices only)"));
  reference_ = new QCheckBox(tr("Receiver 2 is fixed to the pot (reference receiver): turn the pot freely"));
  reference_->setToolTip(
      tr("Every stylus point is taken in the frame of the receiver on the pot, so turning or nudging the pot "
         "changes nothing (docs/devices.md, \"A reference receiver\")"));
  problem_ = problemLine();
  auto* form = new QFormLayout;
  form->addRow(tr("Plant"), plant_);
  form->addRow(tr("Project"), project_);
  form->addRow(tr("Operator"), operator_);
  form->addRow(tr("Survey day"), date_);
  form->addRow(tr("Protocol"), protocol_);
  devices_.addRows(form);
  form->addRow(tr("Simulated plant"), markers_);
  form->addRow(tr("Reference"), reference_);
  auto* buttons = new QDialogButtonBox(QDialogButtonBox::Ok | QDialogButtonBox::Cancel);
  connect(buttons, &QDialogButtonBox::accepted, this, &PlantSetupDialog::accept);
  connect(buttons, &QDialogButtonBox::rejected, this, &QDialog::reject);
  auto* layout = new QVBoxLayout(this);
  layout->addLayout(form);
  layout->addWidget(problem_);
  layout->addWidget(buttons);
}

std::optional<PlantSetupChoice> PlantSetupDialog::choice(QString* problem) const {
  const auto fail = [problem](const QString& why) -> std::optional<PlantSetupChoice> {
    if (problem) *problem = why;
    return std::nullopt;
  };
  PlantSetupChoice c;
  c.setup.plant = plant_->currentText().trimmed().toStdString();
  c.setup.project = project_->currentText().trimmed().toStdString();
  c.setup.operatorName = operator_->text().trimmed().toStdString();
  if (c.setup.plant.empty()) return fail(tr("Name the plant (its id, e.g. tobacco-p12)."));
  if (c.setup.project.empty()) return fail(tr("Name the project the plant belongs to."));
  if (c.setup.operatorName.empty()) return fail(tr("Say who digitizes (the operator)."));
  if (const QString day = date_->text().trimmed(); !day.isEmpty()) {
    c.setup.date = m::parseSurveyDate(day.toStdString());
    if (!c.setup.date) return fail(tr("The survey day %1 is not a date: give it as YYYY-MM-DD.").arg(day));
  }
  if (const QString file = protocol_->text().trimmed(); !file.isEmpty()) {
    try {
      c.setup.protocol = m::readPlantProtocolFile(file.toStdString());
    } catch (const std::exception& e) {
      return fail(QString::fromStdString(e.what()));
    }
  }
  c.referenceReceiver = reference_->isChecked();
  // A reference receiver on a real digitizer is its spec's option (unless the spec says which).
  const bool saysReference = specOf(devices_.digitizer()).contains(",reference=");
  QString deviceProblem;
  const auto chosen = devices_.chosen(&deviceProblem, c.referenceReceiver && !saysReference ? ",reference=2" : "");
  if (!chosen) return fail(deviceProblem);
  c.simulated = chosen->simulated;
  if (c.simulated) {
    c.plantMarkers = markers_->text().trimmed().toStdString();
    if (c.plantMarkers.empty() || !std::filesystem::is_regular_file(c.plantMarkers))
      return fail(tr("The simulated plant %1 is not a file: give a leafdig.plant-markers/1 file.")
                      .arg(QString::fromStdString(c.plantMarkers)));
    return c;
  }
  c.setup.digitizer = chosen->digitizer;
  c.setup.caliper = chosen->caliper;
  return c;
}

void PlantSetupDialog::accept() {
  QString problem;
  if (!choice(&problem)) {
    problem_->setText(problem);
    return;
  }
  QDialog::accept();
}

}  // namespace leafdig::station
