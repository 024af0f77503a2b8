// leafdig devices list|listen, leafdig sim, leafdig doctor.
#pragma once

#include <CLI/CLI.hpp>
#include <string>

namespace leafdig::cli {

struct DevicesOptions {
  bool json = false;
  // listen
  std::string digitizer, caliper, port, hid, unit = "mm", lineConfig;
  int baud = 0, count = 0, pollMs = 0;
  double seconds = 0;
  bool binary = false, dtrTrigger = false, noGrab = false, noFilter = false;
  // sim
  std::string simKind, markers, faults, link;
  std::string distortion;  // sim: a leafdig.field-distortion/1 file (issue 50)
  double rate = 0, pressEvery = 0, simSeconds = 0, sigma = 0.3;
  std::uint64_t seed = 1;
};

class CommandTable;
// Registers `devices list`, `devices listen`, `sim` and `doctor`.
void addDevicesCommands(CLI::App& app, CommandTable& table);

}  // namespace leafdig::cli
