#pragma once
// `leafdig plant build|grow`: a leafdig.plant/1 plan -> a whole plant (stem, placed leaves,
// organ library draws, growth states) -> meshes, CARIBU, MTG, CSV, JSON.
#include <CLI/CLI.hpp>
#include <optional>
#include <string>
#include <vector>

#include "model/mesh_choice.hpp"

namespace leafdig::model {
struct PlantSurvey;
}

namespace leafdig::cli {

struct PlantOptions {
  std::string planPath;
  std::vector<std::string> outputs;
  std::string resolution = "export";
  std::string organs = "all";  // build: --organs (model::kOrganChoiceNames)
  std::string light = "0,0,1";
  std::string canUnit = "m";
  std::optional<double> time;
  std::string times;  // grow: start:end:step
  bool json = false;
  bool animate = false;  // grow: one animated glTF instead of a file per time
  MeshChoice mesh;
};

class CommandTable;
// Registers `plant build`, `plant grow`, `plant measure`, `plant import`, `plant protocol` and `plant capture`.
void addPlantCommands(CLI::App& app, CommandTable& table);
// `plant measure` under the `plant` command (plant_measure_cmd.cpp).
void addPlantMeasureCommand(CLI::App& plant, CommandTable& table);
// A plant's survey as `plant measure` prints it: "LABEL: plant …", the collar, each node (height,
// internode, stem diameter, where a branch hangs), each leaf (kind, angles, chord, area with its
// 95 % interval). `sessions show` of a plant session prints the same (plant_measure_cmd.cpp).
void printSurvey(const model::PlantSurvey& survey, const std::string& label);
// `plant capture` (plant_capture_cmd.cpp).
void addPlantCaptureCommand(CLI::App& plant, CommandTable& table);
// `leafdig plant surveys ID --db DB`: every dated survey of one plant (plant_capture_cmd.cpp).
void addPlantSurveysCommand(CLI::App& plant, CommandTable& table);
// `plant import` (plant_import_cmd.cpp).
void addPlantImportCommand(CLI::App& plant, CommandTable& table);
// `plant protocol` (plant_protocol_cmd.cpp).
void addPlantProtocolCommand(CLI::App& plant, CommandTable& table);

}  // namespace leafdig::cli
