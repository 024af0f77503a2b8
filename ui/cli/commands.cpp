#include "commands.hpp"

#include <exception>
#include <ostream>

#include "failure.hpp"

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

}  // namespace leafdig::cli
