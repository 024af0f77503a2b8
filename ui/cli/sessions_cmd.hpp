// leafdig sessions list|show|verify|approve|reject|reopen|correct|export: what was captured, on a
// station's file or the lab server, for technicians and curators (`sessions resume` is a
// capture's: capture_cmd).
#pragma once

#include <CLI/CLI.hpp>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "leafdig/db/event_store.hpp"
#include "sessions_options.hpp"

namespace leafdig::cli {

// `sessions export` (and the demo's exports): the session's files into o.out.
int runExport(db::EventStore& store, const SessionsOptions& o);

class CommandTable;
// Registers `sessions` and its commands but `resume`, which it returns for the capture's
// commands to declare and run (capture_cmd.cpp).
CLI::App* addSessionsCommands(CLI::App& app, CommandTable& table);

}  // namespace leafdig::cli
