// A leaf's set-up: project, plant, leaf position and type, mode, order, operator, measured
// leaf area (optional), board frame and the two devices (dialogs/device_fields.hpp, as every
// kind asks for them).
#pragma once

#include <QCheckBox>
#include <QComboBox>
#include <QDialog>
#include <QDoubleSpinBox>
#include <QLabel>
#include <QLineEdit>
#include <QSpinBox>
#include <optional>

#include "dialogs/device_fields.hpp"
#include "leafdig/acquisition/session/session.hpp"

namespace leafdig::station {

struct SetupChoice {
  acquisition::SessionSetup setup;  // digitizer / caliper hold specs, or the simulated names
  bool simulatedDigitizer = false, simulatedCaliper = false;
};

class SetupDialog : public QDialog {
  Q_OBJECT

 public:
  // `known` fills the project / plant / operator suggestions (from the store's sessions).
  SetupDialog(const acquisition::SessionSetup& defaults, const std::vector<db::SessionInfo>& known,
              const devices::Inventory& inventory, QWidget* parent = nullptr);
  // Validated choice (call after exec() returned Accepted), or the problem in words.
  [[nodiscard]] std::optional<SetupChoice> choice(QString* problem = nullptr) const;
  void rescan(const devices::Inventory& inventory) { devices_.rescan(inventory); }
  // Fills the measured area (cm²) from a scan of the leaf at `dpi` (the blade's area with its
  // holes filled and the petiole set apart, as `leafdig leaf2d scan` reports it), and keeps
  // what its margin shows for the area interval; false and the problem in words when the scan
  // cannot be read.
  bool areaFromScan(const QString& path, double dpi, QString* problem = nullptr);

  // For tests: the widgets.
  QComboBox* project() const { return project_; }
  QComboBox* plant() const { return plant_; }
  QSpinBox* leafPosition() const { return position_; }
  QLineEdit* leafType() const { return type_; }
  QComboBox* mode() const { return mode_; }
  QComboBox* order() const { return order_; }
  QComboBox* operatorName() const { return operator_; }
  QLineEdit* measuredArea() const { return area_; }
  QComboBox* serration() const { return serration_; }
  QLineEdit* toothDepth() const { return toothDepth_; }
  QCheckBox* board() const { return board_; }
  QComboBox* digitizer() const { return devices_.digitizer(); }
  QComboBox* caliper() const { return devices_.caliper(); }

 public slots:
  void accept() override;

 private:
  acquisition::Settings engine_;
  QComboBox *project_, *plant_, *mode_, *order_, *operator_, *serration_;
  DeviceFields devices_;
  QSpinBox* position_;
  QLineEdit *type_, *area_, *toothDepth_;
  std::optional<model::MarginFromScan> marginFromScan_;  // from "From a scan…"
  QCheckBox* board_;
  QLabel* problem_;
};

}  // namespace leafdig::station
