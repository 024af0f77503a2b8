// What every kind's set-up dialog asks the same way (the leaf's capture/setup_dialog, the plant's
// plant/plant_setup_dialog): the two devices — a digitizer and a caliper from the device
// registry (serial ports and HID devices plugged in now, matched against known profiles), the
// simulated pair listed first like real ones, a spec typed in their place, "Rescan devices" —
// checked one way; the editable name boxes filled from the store's sessions; the problem line.
#pragma once

#include <QComboBox>
#include <QFormLayout>
#include <QLabel>
#include <QString>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "leafdig/devices/transports/registry.hpp"

namespace leafdig::station {

inline constexpr const char* kSimulatedDigitizer = "simulated FASTRAK";
inline constexpr const char* kSimulatedCaliper = "simulated Sylvac";

// A device list's spec: a listed device's item data, or the text typed.
[[nodiscard]] QString specOf(const QComboBox* box);
// The device choices the registry offers: (label shown, spec). Simulated ones first.
[[nodiscard]] std::vector<std::pair<QString, QString>> digitizerChoices(const devices::Inventory& inv);
[[nodiscard]] std::vector<std::pair<QString, QString>> caliperChoices(const devices::Inventory& inv);

// An editable box of the names known (projects, plants, operators), showing `current`.
[[nodiscard]] QComboBox* knownNamesBox(const std::set<QString>& names, const std::string& current);
// The dialog's line for what keeps it from closing, in the error colour.
[[nodiscard]] QLabel* problemLine();

// The pair of devices as chosen: both simulated (a virtual technician uses both), or two
// real devices' specs that parse.
struct ChosenDevices {
  bool simulated = false;
  std::string digitizer, caliper;  // real devices' specs (empty when simulated)
};

class DeviceFields {
 public:
  // Owned by the dialog whose form addRows() fills (Qt owns the widgets then).
  // `digitizer` / `caliper`: the spec to show first (a listed one, or typed).
  DeviceFields(const devices::Inventory& inventory, const QString& digitizer, const QString& caliper);
  DeviceFields(const DeviceFields&) = delete;
  DeviceFields& operator=(const DeviceFields&) = delete;

  // "Digitizer" and "Caliper" rows, then the registry's note with "Rescan devices".
  void addRows(QFormLayout* form);
  void rescan(const devices::Inventory& inventory);
  // The pair checked; the problem in words otherwise. `digitizerOptions` (e.g.
  // ",reference=2") is added to a real digitizer's spec before it is checked.
  [[nodiscard]] std::optional<ChosenDevices> chosen(QString* problem, const std::string& digitizerOptions = {}) const;

  [[nodiscard]] QComboBox* digitizer() const { return digitizer_; }
  [[nodiscard]] QComboBox* caliper() const { return caliper_; }

 private:
  QComboBox *digitizer_, *caliper_;
};

}  // namespace leafdig::station
