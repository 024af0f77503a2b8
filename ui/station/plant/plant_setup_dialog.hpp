// A plant's set-up (docs/plants.md, "The station's plant capture view"): the plant's id, project,
// operator, the survey's day and protocol (optional), and the two devices
// (dialogs/device_fields.hpp, as every kind asks for them) — real ones, or the simulated pair
// with the plant the virtual technician digitizes (a leafdig.plant-markers/1 file, the sample
// plant by default).
#pragma once

#include <QCheckBox>
#include <QComboBox>
#include <QDialog>
#include <QLabel>
#include <QLineEdit>
#include <optional>
#include <vector>

#include "dialogs/device_fields.hpp"
#include "leafdig/acquisition/session/plant_session.hpp"

namespace leafdig::station {

struct PlantSetupChoice {
  acquisition::PlantSessionSetup setup;  // plant, project, operator, date, protocol; devices' specs when real
  bool simulated = false;                // both devices simulated: the virtual technician digitizes `plantMarkers`
  std::string plantMarkers;
  bool referenceReceiver = false;  // receiver 2 on the pot (real: in setup.digitizer's ",reference=2")
};

class PlantSetupDialog : public QDialog {
  Q_OBJECT

 public:
  // `known` fills the plant and project suggestions; `sampleMarkers` is the simulation's default plant.
  PlantSetupDialog(const acquisition::PlantSessionSetup& defaults, const std::vector<db::SessionInfo>& known,
                   const devices::Inventory& inventory, const QString& sampleMarkers, QWidget* parent = nullptr);
  // The validated choice, or the problem in words (nothing is read from disk but the protocol
  // and, for a simulation, the plant-markers file's existence).
  [[nodiscard]] std::optional<PlantSetupChoice> choice(QString* problem = nullptr) const;

  QComboBox* plant() const { return plant_; }
  QComboBox* project() const { return project_; }
  QLineEdit* operatorName() const { return operator_; }
  QLineEdit* date() const { return date_; }
  QLineEdit* protocol() const { return protocol_; }
  QComboBox* digitizer() const { return devices_.digitizer(); }
  QComboBox* caliper() const { return devices_.caliper(); }
  QLineEdit* plantMarkers() const { return markers_; }
  QCheckBox* referenceReceiver() const { return reference_; }

 public slots:
  void accept() override;

 private:
  QComboBox *plant_, *project_;
  DeviceFields devices_;
  QLineEdit *operator_, *date_, *protocol_, *markers_;
  QCheckBox* reference_;
  QLabel* problem_;
};

}  // namespace leafdig::station
