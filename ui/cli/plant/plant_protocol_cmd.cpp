// `leafdig plant protocol [FILE]`: a plant protocol (leafdig.plant-protocol/1) read and checked,
// its steps in the order a plant capture asks for them; without a file, the built-in tobacco
// protocol (docs/plants.md, "The plant protocol file").
#include <iostream>
#include <memory>
#include <stdexcept>
#include <string>

#include "commands.hpp"
#include "leafdig/acquisition/protocol/plant_engine.hpp"
#include "leafdig/model/errors.hpp"
#include "leafdig/model/plant/plant_protocol.hpp"
#include "plant/plant_cmd.hpp"

namespace leafdig::cli {

namespace m = leafdig::model;

namespace {

struct ProtocolOptions {
  std::string input;
  bool json = false;
};

int runProtocol(const ProtocolOptions& o) {
  const m::PlantProtocol protocol = o.input.empty() ? m::defaultPlantProtocol() : m::readPlantProtocolFile(o.input);
  // The check is the capture's own: a protocol `plant capture` cannot follow (no stem, an axis
  // of order 3, two branches, …) is refused here in the same words, not passed.
  try {
    (void)acquisition::PlantEngine(protocol);
  } catch (const std::invalid_argument& e) {
    throw m::InputError((o.input.empty() ? std::string("the built-in protocol") : o.input) + ": " + e.what() +
                        " — plant capture cannot follow it");
  }
  if (o.json) {
    std::cout << m::plantProtocolToJson(protocol) << "\n";
    return 0;
  }
  std::cout << (o.input.empty() ? std::string("built-in protocol") : o.input) << ": " << protocol.species << ", "
            << protocol.entities.size() << " entit" << (protocol.entities.size() == 1 ? "y" : "ies") << "\n";
  int step = 0;
  for (const std::string& line : m::describeSteps(protocol)) std::cout << "  " << ++step << ". " << line << "\n";
  return 0;
}

}  // namespace

void addPlantProtocolCommand(CLI::App& plant, CommandTable& table) {
  auto o = std::make_shared<ProtocolOptions>();
  CLI::App* protocol = plant.add_subcommand(
      "protocol",
      "Check a plant protocol (leafdig.plant-protocol/1) and list its steps; without FILE the built-in one");
  protocol->add_option("input", o->input, "Plant protocol file (default: the built-in tobacco protocol)");
  protocol->add_flag("--json", o->json, "Print the protocol as read, every default filled in");
  table.add(protocol, [o] { return runProtocol(*o); });
}

}  // namespace leafdig::cli
