#include "review/correction_dialog.hpp"

#include <QDialog>
#include <QDialogButtonBox>
#include <QDoubleSpinBox>
#include <QFormLayout>
#include <QLineEdit>
#include <QMessageBox>
#include <QPushButton>
#include <QTreeWidget>
#include <map>

namespace leafdig::station {

std::optional<acquisition::Correction> askCorrection(QWidget* parent, const QString& title,
                                                     const std::vector<CorrectionChoice>& choices,
                                                     const QString& valueName) {
  if (choices.empty()) return std::nullopt;
  QDialog d(parent);
  d.setWindowTitle(title);
  auto* form = new QFormLayout(&d);
  // The items as a tree, each label's " · " parts its levels ("Node 3 · leaf marker · row 2 ·
  // point 1 (…)" sits under Node 3, leaf marker, row 2): a plant's hundred items are found by
  // opening the node, not by scrolling a list. Groups are not items; the first item is chosen.
  auto* which = new QTreeWidget;
  which->setObjectName("correctionItems");
  which->setHeaderHidden(true);
  which->setMinimumHeight(choices.size() > 8 ? 280 : 120);
  std::map<QString, QTreeWidgetItem*> groups;
  QTreeWidgetItem* first = nullptr;
  for (std::size_t i = 0; i < choices.size(); ++i) {
    const QStringList parts = choices[i].label.split(QStringLiteral(" · "));
    QTreeWidgetItem* parent = nullptr;
    QString path;
    for (qsizetype k = 0; k + 1 < parts.size(); ++k) {
      path += parts[k] + QChar(0x1f);
      auto it = groups.find(path);
      if (it == groups.end()) {
        auto* g = parent ? new QTreeWidgetItem(parent, {parts[k]}) : new QTreeWidgetItem(which, {parts[k]});
        g->setFlags(Qt::ItemIsEnabled);
        it = groups.emplace(path, g).first;
      }
      parent = it->second;
    }
    auto* item = parent ? new QTreeWidgetItem(parent, {parts.back()}) : new QTreeWidgetItem(which, {parts.back()});
    item->setData(0, Qt::UserRole, static_cast<int>(i));
    if (first == nullptr) first = item;
  }
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
  int chosen = 0;
  QObject::connect(which, &QTreeWidget::currentItemChanged, &d, [&](QTreeWidgetItem* current) {
    if (current == nullptr || !current->data(0, Qt::UserRole).isValid()) return;  // a group
    chosen = current->data(0, Qt::UserRole).toInt();
    fill(chosen);
  });
  for (QTreeWidgetItem* up = first ? first->parent() : nullptr; up != nullptr; up = up->parent()) up->setExpanded(true);
  which->setCurrentItem(first);
  auto* reason = new QLineEdit;
  reason->setPlaceholderText(QObject::tr("why (required)"));
  form->addRow(QObject::tr("Reason"), reason);
  auto* buttons = new QDialogButtonBox(QDialogButtonBox::Ok | QDialogButtonBox::Cancel);
  QObject::connect(buttons, &QDialogButtonBox::accepted, &d, &QDialog::accept);
  QObject::connect(buttons, &QDialogButtonBox::rejected, &d, &QDialog::reject);
  form->addRow(buttons);
  const int answer = d.exec();
  // The tree may say its current item changed while it is destroyed with the dialog, after the
  // locals the handler writes to are gone: it says nothing more.
  QObject::disconnect(which, nullptr, &d, nullptr);
  if (answer != QDialog::Accepted) return std::nullopt;
  acquisition::Correction c = choices[static_cast<std::size_t>(chosen)].item;
  if (c.positionMm)
    c.positionMm = acquisition::Vec3{boxes[0]->value(), boxes[1]->value(), boxes[2]->value()};
  else
    c.valueMm = boxes[3]->value();
  c.reason = reason->text().toStdString();
  return c;
}

QString effectText(const acquisition::CorrectionEffect& effect, double confirmAboveMm) {
  QStringList lines;
  if (effect.movedMm) {
    const QString move = QObject::tr("The point moves %1 mm.").arg(*effect.movedMm, 0, 'f', 1);
    lines << (*effect.movedMm > confirmAboveMm
                  ? QObject::tr("%1 That is more than the %2 mm a correction moves unconfirmed: check the position.")
                        .arg(move)
                        .arg(confirmAboveMm, 0, 'f', 1)
                  : move);
  }
  if (effect.events > 1)
    lines << QObject::tr("%1 more points are placed again by the refitted move of the transmitter.")
                 .arg(effect.events - 1);
  for (const auto& ch : effect.changes) {
    QString line = QObject::tr("%1: %2 → %3")
                       .arg(QString::fromStdString(ch.what))
                       .arg(ch.before, 0, 'f', 1)
                       .arg(ch.after, 0, 'f', 1);
    if (ch.before != 0)
      line += QString(" (%1%2 %)")
                  .arg(ch.after >= ch.before ? "+" : "")
                  .arg(100.0 * (ch.after - ch.before) / ch.before, 0, 'f', 1);
    lines << line;
  }
  if (lines.isEmpty()) lines << QObject::tr("No measure changes.");
  return lines.join("\n");
}

bool confirmCorrection(QWidget* parent, const acquisition::CorrectionEffect& effect, double confirmAboveMm) {
  const bool far = effect.movedMm && *effect.movedMm > confirmAboveMm;
  QMessageBox box(far ? QMessageBox::Warning : QMessageBox::Question, QObject::tr("Write this correction?"),
                  effectText(effect, confirmAboveMm), QMessageBox::NoButton, parent);
  box.setObjectName("confirmCorrection");
  auto* write = box.addButton(QObject::tr("Write the correction"), QMessageBox::AcceptRole);
  QPushButton* cancel = box.addButton(QMessageBox::Cancel);
  box.setDefaultButton(far ? cancel : write);
  box.exec();
  return box.clickedButton() == write;
}

}  // namespace leafdig::station
