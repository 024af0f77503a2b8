// leafdig: the command line front end. A thin composition root over the modules: every
// command is registered in one table (commands.hpp) and every failure reported through one
// map (failure.hpp).
//
// Exit codes: 0 success; 2 bad input (a file or option the user must fix; nothing was
// written); 1 any other failure (I/O, disk full, a device, internal error); 130 interrupted.
#include <CLI/CLI.hpp>
#include <iostream>

#include "capture/capture_cmd.hpp"
#include "commands.hpp"
#include "devices_cmd.hpp"
#include "failure.hpp"
#include "field_cmd.hpp"
#include "lab_cmd.hpp"
#include "leafdig/version.hpp"
#include "model/leaf2d_cmd.hpp"
#include "model/mesh_cmd.hpp"
#include "model/model_build.hpp"
#include "model/synth_cmd.hpp"
#include "plant/plant_cmd.hpp"

namespace {

// Registers every command of leafdig on `app` and `table`. The options the commands parse
// into live in `app` (CLI11 keeps them alive for the parse and the run).
void addAllCommands(CLI::App& app, leafdig::cli::CommandTable& table) {
  leafdig::cli::addModelCommands(app, table);
  leafdig::cli::addPlantCommands(app, table);
  leafdig::cli::addMeshCommands(app, table);
  leafdig::cli::addSynthCommands(app, table);
  leafdig::cli::addLeaf2dCommands(app, table);
  leafdig::cli::addDevicesCommands(app, table);
  leafdig::cli::addFieldCommands(app, table);
  leafdig::cli::addCaptureCommands(app, table);
  leafdig::cli::addLabCommands(app, table);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"leafdig: digitizer-and-caliper acquisition station for plant morphology labs", "leafdig"};
  app.set_version_flag("--version", std::string("leafdig ") + leafdig::kVersion);
  app.require_subcommand(1);
  app.footer(
      "Exit codes: 0 success, 2 bad input (nothing written; the message says what to fix), "
      "1 other failures, 130 interrupted.");
  leafdig::cli::CommandTable table;
  addAllCommands(app, table);
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError&) {
    return leafdig::cli::reportFailure(std::current_exception(), std::cerr);
  }
  return table.run(std::cerr);
}
