#include "review/correction_dialog.hpp"

#include <QComboBox>
#include <QDialog>
#include <QDialogButtonBox>
#include <QDoubleSpinBox>
#include <QFormLayout>
#include <QLineEdit>

namespace leafdig::station {

std::optional<acquisition::Correction> askCorrection(QWidget* parent, const QString& title,
                                                     const std::vector<CorrectionChoice>& choices,
                                                     const QString& valueName) {
  if (choices.empty()) return std::nullopt;
  QDialog d(parent);
  d.setWindowTitle(title);
  auto* form = new QFormLayout(&d);
  auto* which = new QComboBox;
  for (const CorrectionChoice& c : choices) which->addItem(c.label);
  if (choices.size() > 1) form->addRow(QObject::tr("Item"), which);
  std::vector<QDoubleSpinBox*> boxes;
  const QStringList names{QObject::tr("x"), QObject::tr("y"), QObject::tr("z"), valueName};
  for (int k = 0; k < 4; ++k) {
    auto* b = new QDoubleSpinBox;
    b->setRange(k < 3 ? -10000 : 0, 10000);
    b->setDecimals(3);
    b->setSuffix(" mm");
    boxes.push_back(b);
    form->addRow(names[k], b);
  }
  const auto fill = [&](int index) {
    const acquisition::Correction& c = choices[static_cast<std::size_t>(index)].item;
    for (std::size_t k = 0; k < 3; ++k) {
      boxes[k]->setEnabled(c.positionMm.has_value());
      boxes[k]->setValue(c.positionMm ? (*c.positionMm)[k] : 0.0);
    }
    boxes[3]->setEnabled(c.valueMm.has_value());
    boxes[3]->setValue(c.valueMm.value_or(0.0));
  };
  fill(0);
  QObject::connect(which, qOverload<int>(&QComboBox::currentIndexChanged), &d, fill);
  auto* reason = new QLineEdit;
  reason->setPlaceholderText(QObject::tr("why (required)"));
  form->addRow(QObject::tr("Reason"), reason);
  auto* buttons = new QDialogButtonBox(QDialogButtonBox::Ok | QDialogButtonBox::Cancel);
  QObject::connect(buttons, &QDialogButtonBox::accepted, &d, &QDialog::accept);
  QObject::connect(buttons, &QDialogButtonBox::rejected, &d, &QDialog::reject);
  form->addRow(buttons);
  if (d.exec() != QDialog::Accepted) return std::nullopt;
  acquisition::Correction c = choices[static_cast<std::size_t>(which->currentIndex())].item;
  if (c.positionMm)
    c.positionMm = acquisition::Vec3{boxes[0]->value(), boxes[1]->value(), boxes[2]->value()};
  else
    c.valueMm = boxes[3]->value();
  c.reason = reason->text().toStdString();
  return c;
}

}  // namespace leafdig::station
