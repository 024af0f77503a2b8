#pragma once
// `leafdig leaf2d build|scan`: leaves known only in 2-D (seed 001, docs/leaf2d.md) — an
// outline file or a scan becomes a curled, area-constrained 3-D blade.
#include <CLI/CLI.hpp>
#include <optional>
#include <string>
#include <vector>

namespace leafdig::cli {

struct Leaf2dCommandOptions {
  std::string input;  // outline (.json, .csv) or scan image
  std::optional<double> dpi;
  double petioleWidthMm = 3.0;
  std::string curl = "parabola";
  std::optional<double> amplitudeMm;
  std::string light = "0,0,1";
  int rows = 30;
  std::optional<double> measuredAreaMm2;
  std::vector<std::string> outputs;
  std::string outlineOut;
  std::string figure;  // leaf2d figure -o
  bool json = false;
};

class CommandTable;
// Registers `leaf2d build`, `leaf2d scan` and `leaf2d figure`.
void addLeaf2dCommands(CLI::App& app, CommandTable& table);

// True for the image extensions a scan may have (.png .tif .tiff .jpg .jpeg .bmp).
[[nodiscard]] bool isScanPath(const std::string& path);

}  // namespace leafdig::cli
