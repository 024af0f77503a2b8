// The device registry: what is plugged in, which known device each one is, and the checks
// behind `leafdig doctor`.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "leafdig/devices/transports/hid.hpp"
#include "leafdig/devices/transports/serial_port.hpp"
#include "leafdig/devices/transports/usb.hpp"

namespace leafdig::devices {

struct Profile {
  std::uint16_t vid, pid;
  const char* name;    // "Mitutoyo USB-ITN"
  const char* role;    // "caliper" or "digitizer"
  const char* driver;  // the --caliper / --digitizer value, or a note
  const char* note;    // what to know (driver binding, firmware upload)
};

[[nodiscard]] const std::vector<Profile>& knownProfiles();
[[nodiscard]] const Profile* matchProfile(std::uint16_t vid, std::uint16_t pid);

struct Inventory {
  std::vector<SerialPortInfo> serial;
  std::vector<HidInfo> hid;
  std::vector<UsbDeviceInfo> usb;
};
[[nodiscard]] Inventory takeInventory();

struct Check {
  std::string what;
  bool ok = false;
  std::string detail;
  std::string remedy;
};
// Libraries, device nodes and permissions, group membership, udev rule.
[[nodiscard]] std::vector<Check> doctorChecks(const std::string& udevRulePath = "/lib/udev/rules.d/70-leafdig.rules");

}  // namespace leafdig::devices
