// Settings: units shown, theme, font size, sounds, shortcuts (a foot pedal types one of
// them), and the capture tolerances and stillness window for new sessions.
#pragma once

#include <QCheckBox>
#include <QComboBox>
#include <QDialog>
#include <QDoubleSpinBox>
#include <QKeySequenceEdit>
#include <QLineEdit>
#include <QSpinBox>
#include <map>

#include "settings.hpp"

namespace leafdig::station {

class SettingsDialog : public QDialog {
  Q_OBJECT

 public:
  SettingsDialog(const StationSettings& current, QWidget* parent = nullptr);
  [[nodiscard]] StationSettings result() const;

  QComboBox* units() const { return units_; }
  QComboBox* theme() const { return theme_; }
  QDoubleSpinBox* fontScale() const { return font_; }
  QCheckBox* sounds() const { return sounds_; }
  QKeySequenceEdit* shortcut(Action a) const { return keys_.at(a); }
  QDoubleSpinBox* stillWindowMs() const { return still_; }
  QDoubleSpinBox* relocationToleranceMm() const { return relocation_; }
  QLineEdit* labUrl() const { return labUrl_; }
  QSpinBox* labSyncMinutes() const { return labMinutes_; }
  QDoubleSpinBox* fieldCheckMaxAgeHours() const { return fieldAge_; }
  QComboBox* sentinels() const { return sentinels_; }

 private:
  StationSettings base_;
  QComboBox *units_, *theme_, *sentinels_;
  QDoubleSpinBox *font_, *volume_, *still_, *stillTol_, *spacing_, *midrib_, *relocation_, *minT_, *maxT_, *fieldAge_;
  QCheckBox* sounds_;
  QLineEdit* labUrl_;
  QSpinBox* labMinutes_;
  std::map<Action, QKeySequenceEdit*> keys_;
};

}  // namespace leafdig::station
