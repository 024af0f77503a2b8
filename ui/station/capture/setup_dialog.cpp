#include "capture/setup_dialog.hpp"

#include <QDialogButtonBox>
#include <QDoubleValidator>
#include <QFileDialog>
#include <QFormLayout>
#include <QHBoxLayout>
#include <QInputDialog>
#include <QPushButton>
#include <QVBoxLayout>
#include <set>

#include "leafdig/model/leaf2d/leaf_scan.hpp"

namespace leafdig::station {
namespace acq = leafdig::acquisition;

SetupDialog::SetupDialog(const acq::SessionSetup& d, const std::vector<db::SessionInfo>& known,
                         const devices::Inventory& inventory, QWidget* parent)
    : QDialog(parent),
      engine_(d.settings),
      devices_(inventory, d.simulated ? kSimulatedDigitizer : QString::fromStdString(d.digitizer),
               d.simulated ? kSimulatedCaliper : QString::fromStdString(d.caliper)) {
  setWindowTitle(tr("leafdig · new session"));
  auto* form = new QFormLayout;
  std::set<QString> projects, plants, operators;
  for (const auto& s : known) {
    projects.insert(QString::fromStdString(s.project));
    plants.insert(QString::fromStdString(s.plant));
    operators.insert(QString::fromStdString(s.operatorName));
  }
  project_ = knownNamesBox(projects, d.project);
  plant_ = knownNamesBox(plants, d.plant);
  operator_ = knownNamesBox(operators, d.operatorName);
  position_ = new QSpinBox;
  position_->setRange(1, 99);
  position_->setValue(d.leafPosition);
  type_ = new QLineEdit(QString::fromStdString(d.leafType));
  type_->setPlaceholderText(tr("e.g. lower, middle, upper (optional)"));
  mode_ = new QComboBox;
  for (const auto& m : wordsIn(model::kThicknessModeNames)) mode_->addItem(QString::fromStdString(m));
  mode_->setCurrentText(model::toString(d.settings.mode));
  mode_->setToolTip(tr("standard: midrib and vein origin per row; full: all 7 points; small: midrib only"));
  order_ = new QComboBox;
  for (const auto& o : wordsIn(acq::kOrderNames)) order_->addItem(QString::fromStdString(o));
  order_->setCurrentText(acq::toString(d.settings.order));
  area_ = new QLineEdit;
  area_->setPlaceholderText(tr("cm² from a leaf area meter (optional)"));
  auto* v = new QDoubleValidator(0.01, 100000.0, 3, area_);
  v->setNotation(QDoubleValidator::StandardNotation);
  area_->setValidator(v);
  if (d.measuredAreaMm2) area_->setText(QString::number(*d.measuredAreaMm2 / 100.0));
  // The margin, for the area interval: teeth the markers cannot see between them.
  serration_ = new QComboBox;
  serration_->addItem(tr("not declared"), QString());
  for (const auto& word : wordsIn(model::kSerrationNames))
    serration_->addItem(QString::fromStdString(word), QString::fromStdString(word));
  if (d.serration)
    serration_->setCurrentIndex(serration_->findData(QString::fromLatin1(model::toString(*d.serration))));
  serration_->setToolTip(
      tr("The leaf's margin teeth: the area's 95 % interval then accounts for the teeth between the markers "
         "(none: an entire margin). Not declared: the interval says teeth are not in it."));
  toothDepth_ = new QLineEdit;
  toothDepth_->setPlaceholderText(tr("tooth depth, mm (default 1.5 % of the width)"));
  auto* depthValidator = new QDoubleValidator(0.01, 100.0, 3, toothDepth_);
  depthValidator->setNotation(QDoubleValidator::StandardNotation);
  toothDepth_->setValidator(depthValidator);
  if (d.toothDepthMm) toothDepth_->setText(QString::number(*d.toothDepthMm));
  marginFromScan_ = d.marginFromScan;
  board_ = new QCheckBox(tr("Start with 3 board points (origin, +X, +Y)"));
  board_->setChecked(d.settings.boardFrame);

  form->addRow(tr("Project"), project_);
  form->addRow(tr("Plant"), plant_);
  form->addRow(tr("Leaf position (from the base)"), position_);
  form->addRow(tr("Leaf type"), type_);
  form->addRow(tr("Mode"), mode_);
  form->addRow(tr("Order"), order_);
  form->addRow(tr("Operator"), operator_);
  // The area may come from a scan of the leaf, segmented as `leafdig leaf2d scan` does.
  auto* fromScan = new QPushButton(tr("From a scan…"));
  fromScan->setToolTip(tr("Read the blade area (holes filled, petiole set apart) from a scan of this leaf"));
  connect(fromScan, &QPushButton::clicked, this, [this] {
    const QString path = QFileDialog::getOpenFileName(this, tr("Scan of the leaf"), QString(),
                                                      tr("Images (*.png *.tif *.tiff *.jpg *.jpeg *.bmp)"));
    if (path.isEmpty()) return;
    bool ok = false;
    const double dpi =
        QInputDialog::getDouble(this, tr("Scan resolution"), tr("Dots per inch, as set in the scanner's software:"),
                                300.0, 10.0, 4800.0, 0, &ok);
    if (!ok) return;
    QString problem;
    if (!areaFromScan(path, dpi, &problem)) problem_->setText(problem);
  });
  auto* areaRow = new QHBoxLayout;
  areaRow->addWidget(area_, 1);
  areaRow->addWidget(fromScan);
  form->addRow(tr("Measured leaf area"), areaRow);
  auto* marginRow = new QHBoxLayout;
  marginRow->addWidget(serration_);
  marginRow->addWidget(toothDepth_, 1);
  form->addRow(tr("Margin teeth"), marginRow);
  form->addRow(QString(), board_);
  devices_.addRows(form);
  problem_ = problemLine();
  auto* buttons = new QDialogButtonBox(QDialogButtonBox::Ok | QDialogButtonBox::Cancel);
  buttons->button(QDialogButtonBox::Ok)->setText(tr("Start capture"));
  connect(buttons, &QDialogButtonBox::accepted, this, &SetupDialog::accept);
  connect(buttons, &QDialogButtonBox::rejected, this, &QDialog::reject);
  auto* outer = new QVBoxLayout(this);
  outer->addLayout(form);
  outer->addWidget(problem_);
  outer->addWidget(buttons);
}

bool SetupDialog::areaFromScan(const QString& path, double dpi, QString* problem) {
  try {
    const model::LeafScan scan = model::scanLeaf(path.toStdString(), {dpi});
    area_->setText(QString::number(scan.filledAreaMm2 / 100.0, 'f', 2));
    QString note = tr("Area from %1: %2 cm² (blade, holes filled").arg(path).arg(scan.filledAreaMm2 / 100.0, 0, 'f', 2);
    if (scan.petioleFound) note += tr("; petiole set apart");
    note += ")";
    if (scan.touchesBorder) note += tr(" — the leaf touches the scan's edge; it may be cut off");
    area_->setToolTip(note);
    marginFromScan_ = model::marginProfile(scan.outline);  // the interval's margin term, measured
    problem_->clear();
    return true;
  } catch (const std::exception& e) {
    if (problem) *problem = tr("Scan: %1").arg(QString::fromStdString(e.what()));
    return false;
  }
}

std::optional<SetupChoice> SetupDialog::choice(QString* problem) const {
  const auto fail = [&](const QString& p) -> std::optional<SetupChoice> {
    if (problem) *problem = p;
    return std::nullopt;
  };
  SetupChoice c;
  auto& s = c.setup;
  s.project = project_->currentText().trimmed().toStdString();
  s.plant = plant_->currentText().trimmed().toStdString();
  s.operatorName = operator_->currentText().trimmed().toStdString();
  if (s.project.empty()) return fail(tr("Name the project."));
  if (s.plant.empty()) return fail(tr("Name the plant."));
  if (s.operatorName.empty()) return fail(tr("Who captures? Fill in the operator."));
  s.leafPosition = position_->value();
  s.leafType = type_->text().trimmed().toStdString();
  if (!area_->text().trimmed().isEmpty()) {
    bool ok = false;
    const double cm2 = QLocale().toDouble(area_->text().trimmed(), &ok);
    const double any = ok ? cm2 : area_->text().trimmed().toDouble(&ok);
    if (!ok || !(any > 0)) return fail(tr("The measured area must be a positive number of cm² (or leave it empty)."));
    s.measuredAreaMm2 = any * 100.0;
  }
  if (const QString word = serration_->currentData().toString(); !word.isEmpty())
    s.serration = model::serrationFromString(word.toStdString());
  if (!toothDepth_->text().trimmed().isEmpty()) {
    bool ok = false;
    const double mm = QLocale().toDouble(toothDepth_->text().trimmed(), &ok);
    const double any = ok ? mm : toothDepth_->text().trimmed().toDouble(&ok);
    if (!ok || !(any > 0 && any <= 100))
      return fail(tr("The tooth depth must be a number of mm above 0 and at most 100 (or leave it empty)."));
    if (!s.serration || *s.serration == model::Serration::None)
      return fail(tr("A tooth depth is for a toothed margin: choose the margin's teeth, or leave the depth empty."));
    s.toothDepthMm = any;
  }
  s.marginFromScan = marginFromScan_;
  s.settings = engine_;
  s.settings.mode = model::thicknessModeFromString(mode_->currentText().toStdString());
  s.settings.order = acq::orderFromString(order_->currentText().toStdString());
  s.settings.boardFrame = board_->isChecked();
  QString deviceProblem;
  const auto chosen = devices_.chosen(&deviceProblem);
  if (!chosen) return fail(deviceProblem);
  c.simulatedDigitizer = c.simulatedCaliper = s.simulated = chosen->simulated;
  s.digitizer = chosen->simulated ? kSimulatedDigitizer : chosen->digitizer;
  s.caliper = chosen->simulated ? kSimulatedCaliper : chosen->caliper;
  return c;
}

void SetupDialog::accept() {
  QString problem;
  if (!choice(&problem)) {
    problem_->setText(problem);
    return;
  }
  QDialog::accept();
}

}  // namespace leafdig::station
