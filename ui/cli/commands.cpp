#include "commands.hpp"

#include <exception>
#include <ostream>

#include "capture/capture_cmd.hpp"
#include "devices_cmd.hpp"
#include "failure.hpp"
#include "field_cmd.hpp"
#include "lab_cmd.hpp"
#include "model/leaf2d_cmd.hpp"
#include "model/mesh_cmd.hpp"
#include "model/model_build.hpp"
#include "model/synth_cmd.hpp"
#include "plant/plant_cmd.hpp"

namespace leafdig::cli {

void CommandTable::add(CLI::App* command, Run run, std::string inputContext) {
  entries_.push_back({command, std::move(run), std::move(inputContext)});
}

int CommandTable::run(std::ostream& err) const {
  for (const Entry& e : entries_) {
    if (!e.command->parsed()) continue;
    try {
      return e.run();
    } catch (...) {
      return reportFailure(std::current_exception(), err, e.inputContext);
    }
  }
  err << "leafdig: no command was chosen\n  what to do: run 'leafdig --help' for the commands\n";
  return 1;
}

std::vector<std::string> CommandTable::names() const {
  std::vector<std::string> out;
  for (const Entry& e : entries_) {
    std::string name;
    for (const CLI::App* a = e.command; a != nullptr && a->get_parent() != nullptr; a = a->get_parent())
      name = a->get_name() + (name.empty() ? "" : " " + name);
    out.push_back(name);
  }
  return out;
}

void addAllCommands(CLI::App& app, CommandTable& table) {
  addModelCommands(app, table);
  addPlantCommands(app, table);
  addMeshCommands(app, table);
  addSynthCommands(app, table);
  addLeaf2dCommands(app, table);
  addDevicesCommands(app, table);
  addFieldCommands(app, table);
  addCaptureCommands(app, table);
  addLabCommands(app, table);
}

}  // namespace leafdig::cli
