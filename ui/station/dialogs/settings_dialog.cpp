#include "dialogs/settings_dialog.hpp"

#include <QDialogButtonBox>
#include <QFormLayout>
#include <QGroupBox>
#include <QMessageBox>
#include <QVBoxLayout>

namespace leafdig::station {

SettingsDialog::SettingsDialog(const StationSettings& s, QWidget* parent) : QDialog(parent), base_(s) {
  setWindowTitle(tr("leafdig · settings"));
  const auto spin = [](double v, double lo, double hi, double step, int decimals, const QString& suffix) {
    auto* b = new QDoubleSpinBox;
    b->setRange(lo, hi);
    b->setSingleStep(step);
    b->setDecimals(decimals);
    b->setSuffix(suffix);
    b->setValue(v);
    return b;
  };
  auto* display = new QGroupBox(tr("Display"));
  auto* df = new QFormLayout(display);
  units_ = new QComboBox;
  units_->addItem(tr("millimetres"), "mm");
  units_->addItem(tr("inches"), "in");
  units_->setCurrentIndex(units_->findData(s.units));
  theme_ = new QComboBox;
  theme_->addItem(tr("light"), "light");
  theme_->addItem(tr("dark"), "dark");
  theme_->setCurrentIndex(theme_->findData(s.theme));
  font_ = spin(s.fontScale, 0.8, 2.5, 0.05, 2, QStringLiteral(" ×"));
  df->addRow(tr("Units shown"), units_);
  df->addRow(tr("Theme"), theme_);
  df->addRow(tr("Font size (arm's length)"), font_);

  auto* sound = new QGroupBox(tr("Sounds and keys"));
  auto* sf = new QFormLayout(sound);
  sounds_ = new QCheckBox(tr("Accept, reject, step done, device error"));
  sounds_->setChecked(s.sounds);
  volume_ = spin(s.volume, 0, 1, 0.1, 1, QString());
  sf->addRow(tr("Sounds"), sounds_);
  sf->addRow(tr("Volume"), volume_);
  for (const auto& [action, key] : s.shortcuts) {
    auto* e = new QKeySequenceEdit(key);
    keys_[action] = e;
    sf->addRow(actionLabel(action), e);
  }

  auto* capture = new QGroupBox(tr("Capture (new sessions)"));
  auto* cf = new QFormLayout(capture);
  const auto& e = s.engine;
  still_ = spin(static_cast<double>(e.stillWindowNs) / 1e6, 50, 2000, 10, 0, " ms");
  stillTol_ = spin(e.stillToleranceMm, 0.1, 10, 0.1, 2, " mm");
  spacing_ = spin(e.spacingTolerance * 100, 10, 200, 5, 0, " %");
  midrib_ = spin(e.midribToleranceMm, 1, 100, 1, 1, " mm");
  relocation_ = spin(e.relocationToleranceMm, 0.1, 10, 0.1, 2, " mm");
  minT_ = spin(e.minThicknessMm, 0.001, 5, 0.01, 3, " mm");
  maxT_ = spin(e.maxThicknessMm, 1, 100, 1, 1, " mm");
  cf->addRow(tr("Stillness window before a press"), still_);
  cf->addRow(tr("Stillness tolerance"), stillTol_);
  cf->addRow(tr("Row spacing tolerance"), spacing_);
  cf->addRow(tr("Midrib line tolerance"), midrib_);
  cf->addRow(tr("Transmitter move: largest fit residual"), relocation_);
  cf->addRow(tr("Thinnest reading accepted"), minT_);
  cf->addRow(tr("Thickest reading accepted"), maxT_);
  fieldAge_ = spin(s.fieldCheckMaxAgeHours, 1, acquisition::kFieldCheckMaxAgeLimitHours, 1, 0, " h");
  cf->addRow(tr("A field check holds for"), fieldAge_);
  sentinels_ = new QComboBox;
  sentinels_->addItem(tr("none"), 0);
  for (int n = acquisition::kMinSentinels; n <= acquisition::kMaxSentinels; ++n)
    sentinels_->addItem(tr("%1 divots").arg(n), n);
  sentinels_->setCurrentIndex(std::max(0, sentinels_->findData(s.sentinels)));
  sentinels_->setToolTip(
      tr("Before a capture through a field check, this many of its divots are taken again (the jig where it lay "
         "for the check); a divot that moved beyond the check's tolerance stops the capture for a new check"));
  cf->addRow(tr("Sentinel divots before a capture"), sentinels_);

  auto* lab = new QGroupBox(tr("Lab server"));
  auto* lf = new QFormLayout(lab);
  labUrl_ = new QLineEdit(s.labUrl);
  labUrl_->setPlaceholderText(tr("postgresql://LOGIN@HOST/DATABASE (the password in ~/.pgpass)"));
  labMinutes_ = new QSpinBox;
  labMinutes_->setRange(0, 1440);
  labMinutes_->setSuffix(tr(" min"));
  labMinutes_->setSpecialValueText(tr("only by hand"));
  labMinutes_->setValue(s.labSyncMinutes);
  lf->addRow(tr("Server"), labUrl_);
  lf->addRow(tr("Sync every"), labMinutes_);

  auto* buttons = new QDialogButtonBox(QDialogButtonBox::Ok | QDialogButtonBox::Cancel);
  connect(buttons, &QDialogButtonBox::accepted, this, [this] {
    // The station never stores a password: a URL with one is refused here, in words.
    const QString url = labUrl_->text().trimmed();
    if (!url.isEmpty() && labUrlWithoutPassword(url) != url) {
      labUrl_->setStyleSheet("border: 2px solid #c0392b;");
      labUrl_->setToolTip(
          tr("This URL holds a password (or libpq cannot read it). The station never stores one: "
             "give postgresql://LOGIN@HOST/DATABASE and put the password in ~/.pgpass "
             "(HOST:5432:DATABASE:LOGIN:PASSWORD, mode 0600)."));
      QMessageBox::warning(this, tr("Lab server"), labUrl_->toolTip());
      return;
    }
    accept();
  });
  connect(buttons, &QDialogButtonBox::rejected, this, &QDialog::reject);
  auto* outer = new QVBoxLayout(this);
  outer->addWidget(display);
  outer->addWidget(sound);
  outer->addWidget(capture);
  outer->addWidget(lab);
  outer->addWidget(buttons);
}

StationSettings SettingsDialog::result() const {
  StationSettings s = base_;
  s.units = units_->currentData().toString();
  s.theme = theme_->currentData().toString();
  s.fontScale = font_->value();
  s.sounds = sounds_->isChecked();
  s.volume = volume_->value();
  for (const auto& [action, edit] : keys_) s.shortcuts[action] = edit->keySequence();
  s.engine.stillWindowNs = static_cast<std::int64_t>(still_->value() * 1e6);
  s.engine.stillToleranceMm = stillTol_->value();
  s.engine.spacingTolerance = spacing_->value() / 100.0;
  s.engine.midribToleranceMm = midrib_->value();
  s.engine.relocationToleranceMm = relocation_->value();
  s.engine.minThicknessMm = minT_->value();
  s.engine.maxThicknessMm = std::max(maxT_->value(), minT_->value() * 2);
  s.labUrl = labUrlWithoutPassword(labUrl_->text().trimmed());
  s.labSyncMinutes = labMinutes_->value();
  s.fieldCheckMaxAgeHours = fieldAge_->value();
  s.sentinels = sentinels_->currentData().toInt();
  return s;
}

}  // namespace leafdig::station
