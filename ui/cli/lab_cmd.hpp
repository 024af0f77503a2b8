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

class CommandTable;
// Registers `server init`, `server add-user`, `sync push` and `sync pull`.
void addLabCommands(CLI::App& app, CommandTable& table);

}  // namespace leafdig::cli
