#pragma once
// `leafdig model build`: markers file -> veins + blade -> mesh and model exports.
#include <CLI/CLI.hpp>
#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "model/mesh_choice.hpp"

namespace leafdig::cli {

struct ModelBuildOptions {
  std::string markersPath;
  std::vector<std::string> outputs;
  std::string modelJsonPath;
  std::string blade = "interp";
  std::string resolution = "export";
  std::string caps;  // empty: the resolution preset's own
  std::string frame = "digitizer";
  std::string light = "0,0,1";
  std::optional<double> measuredAreaMm2;
  std::string measuredAreaScan;  // a scan of the leaf; its blade area is the measured area
  std::optional<double> scanDpi;
  double areaThresholdPercent = 5.0;
  bool json = false;
  MeshChoice mesh;
};

class CommandTable;
// Registers `model build`.
void addModelCommands(CLI::App& app, CommandTable& table);

// "x,y,z" (not all zero) as a light direction; throws model::InputError naming the option.
[[nodiscard]] Eigen::Vector3d parseLight(const std::string& text);

// Runs the command; returns 0 and throws what failed (the error map, failure.hpp, says it).
int runModelBuild(const ModelBuildOptions& options);

}  // namespace leafdig::cli
