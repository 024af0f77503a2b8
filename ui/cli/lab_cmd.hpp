// leafdig server init|add-user|web, leafdig sync push|pull: the lab's PostgreSQL server
// (docs/lab.md; the web review: docs/web.md).
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
  double lockWaitSeconds = 30;            // server init
  std::string listen = "127.0.0.1:8080";  // server web
  double idleMinutes = 30;
  bool secureCookie = false;
  bool json = false;
};

class CommandTable;
// Registers `server init`, `server add-user`, `server web`, `sync push` and `sync pull`.
void addLabCommands(CLI::App& app, CommandTable& table);

}  // namespace leafdig::cli
