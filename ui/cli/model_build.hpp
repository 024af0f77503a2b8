#pragma once
// `leafdig model build`: markers file -> veins + blade -> mesh and model exports.
#include <CLI/CLI.hpp>
#include <Eigen/Core>
#include <exception>
#include <optional>
#include <string>
#include <vector>

#include "mesh_cmd.hpp"

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

void addModelBuildCommand(CLI::App& model, ModelBuildOptions& options);

// "x,y,z" (not all zero) as a light direction; throws model::InputError naming the option.
[[nodiscard]] Eigen::Vector3d parseLight(const std::string& text);

// Says what a failure of a model command was and returns its exit code: 2 for an
// InputError (the user's file or option), 1 for an IoError or anything else.
int reportModelFailure(const std::exception_ptr& error);

// Runs the command; returns the process exit code (0 ok, 2 bad input, 1 other failure).
int runModelBuild(const ModelBuildOptions& options);

}  // namespace leafdig::cli
