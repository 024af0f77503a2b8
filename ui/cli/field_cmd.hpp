// leafdig field model|check|list|show: the digitizer's magnetic field (issue 50; docs/devices.md,
// "The field" and "Checking the field").
#pragma once

#include <CLI/CLI.hpp>

namespace leafdig::cli {

class CommandTable;
// Registers `field model`, `field check`, `field list` and `field show`.
void addFieldCommands(CLI::App& app, CommandTable& table);

}  // namespace leafdig::cli
