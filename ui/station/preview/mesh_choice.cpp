#include "preview/mesh_choice.hpp"

#include <QComboBox>
#include <QDoubleSpinBox>
#include <QHBoxLayout>
#include <QVBoxLayout>

namespace leafdig::station {

MeshChoice::MeshChoice(QWidget* parent) : QWidget(parent) {
  method_ = new QComboBox;
  method_->addItem(tr("uniform grid"), "uniform");
  method_->addItem(tr("adaptive (max error)"), "adaptive");
  method_->addItem(tr("seed rule (patent)"), "seed");
  method_->setToolTip(
      tr("uniform: the resolution's grid · adaptive: fewest triangles within the error of the exact "
         "surface · seed: division length M and merge angle α of patent CN101650836 (blades without "
         "interior points, coarse)"));
  maxError_ = new QDoubleSpinBox;
  maxError_->setRange(0.01, 10.0);
  maxError_->setDecimals(2);
  maxError_->setSingleStep(0.05);
  maxError_->setValue(0.1);
  maxError_->setSuffix(tr(" mm"));
  maxError_->setToolTip(tr("Largest distance between the mesh and the exact leaf surface"));
  minLength_ = new QDoubleSpinBox;
  minLength_->setRange(0.1, 50.0);
  minLength_->setValue(2.0);
  minLength_->setSuffix(tr(" mm"));
  minLength_->setToolTip(tr("Seed rule: division length M along veins, margin and midrib"));
  maxAngle_ = new QDoubleSpinBox;
  maxAngle_->setRange(91.0, 180.0);
  maxAngle_->setValue(170.0);
  maxAngle_->setSuffix(tr("°"));
  maxAngle_->setToolTip(tr("Seed rule: merge segments while their angle exceeds α (180° = straight)"));
  maxError_->setPrefix(tr("max error "));
  minLength_->setPrefix(tr("M "));
  maxAngle_->setPrefix(tr("α "));
  // The method on its own line, below it only the parameters it takes.
  auto* column = new QVBoxLayout(this);
  column->setContentsMargins(0, 0, 0, 0);
  column->addWidget(method_);
  auto* row = new QHBoxLayout;
  row->addWidget(maxError_);
  row->addWidget(minLength_);
  row->addWidget(maxAngle_);
  column->addLayout(row);
  connect(method_, &QComboBox::currentIndexChanged, this, [this] { updateEnabled(); });
  updateEnabled();
}

void MeshChoice::updateEnabled() {
  const QString m = method_->currentData().toString();
  maxError_->setEnabled(m == "adaptive");
  minLength_->setEnabled(m == "seed");
  maxAngle_->setEnabled(m == "seed");
  maxError_->setVisible(m == "adaptive");
  minLength_->setVisible(m == "seed");
  maxAngle_->setVisible(m == "seed");
}

model::MeshOptions MeshChoice::options(const std::string& resolution) const {
  model::MeshOptions o;
  o.method = model::meshMethodFromString(method_->currentData().toString().toStdString());
  o.resolution = model::MeshResolution::preset(resolution);
  o.maxErrorMm = maxError_->value();
  o.seed.minLengthMm = minLength_->value();
  o.seed.maxAngleDeg = maxAngle_->value();
  return o;
}

}  // namespace leafdig::station
