#pragma once
// `leafdig mesh compare|study` (docs/meshing.md); the `--mesh` options that `model build` and
// `plant build` share are in mesh_choice.hpp.
#include <CLI/CLI.hpp>
#include <cstddef>
#include <cstdint>
#include <string>

#include "model/mesh_choice.hpp"

namespace leafdig::cli {

struct MeshCommandOptions {
  std::string a, b;  // compare
  std::string markers;
  std::string plan;
  std::string outDir;
  double maxErrorMm = 0.1;
  std::size_t samples = 200'000;
  std::size_t studySamples = 100'000;
  std::uint64_t seed = 1;
  bool json = false;
};

class CommandTable;
// Registers `mesh compare` and `mesh study`.
void addMeshCommands(CLI::App& app, CommandTable& table);

}  // namespace leafdig::cli
