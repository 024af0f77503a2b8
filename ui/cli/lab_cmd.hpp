// leafdig server init|add-user, leafdig sync push|pull: the lab's PostgreSQL server
// (docs/lab.md).
#pragma once

#include <CLI/CLI.hpp>
#include <string>

namespace leafdig::cli {

struct LabOptions {
  std::string url;  // --url / --to / --from
  std::string db;   // the station's file
  std::string station;
  std::string login, role, passwordFile;
  std::size_t eventsPerTransaction = 2000;
  double lockWaitSeconds = 30;  // server init
  bool json = false;
};

void addLabCommands(CLI::App& app, LabOptions& options);
// Returns the exit code, or -1 when none of these commands was chosen.
int runLabCommands(CLI::App& app, const LabOptions& options);

}  // namespace leafdig::cli
