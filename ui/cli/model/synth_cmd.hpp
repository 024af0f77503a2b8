#pragma once
// `leafdig synth leaf|figure|study`: synthetic ground-truth leaves (docs/synthetic-leaves.md).
#include <CLI/CLI.hpp>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "leafdig/model/synth/synthetic_leaf.hpp"

namespace leafdig::cli {

// Shape options shared by `synth leaf` and the simulated captures (`--synth-*`).
struct SynthChoice {
  std::string shape = "tobacco";
  std::optional<double> lengthMm, widthMm, symmetry;
  std::string serration = "none";
  std::optional<double> toothDepthMm;
  std::optional<int> teeth;
  std::string toothDirection = "horizontal";
  std::vector<std::string> widthTerms;  // "a,k[,phase]"
  std::optional<double> asymmetry, tipNarrowing, tipExtent, baseNarrowing, baseExtent;
  std::optional<double> droopDeg, cupMm, twistDeg, waveMm, wavelengthMm;
  int rows = 12;
  std::optional<double> veinAngleTipDeg, veinAngleBaseDeg;
  std::string id, plant;
};

// Adds the options (names prefixed with `prefix`, e.g. "" or "synth-").
void addSynthChoice(CLI::App& command, SynthChoice& choice, const std::string& prefix);
// The spec, or an InputError naming the option at fault.
[[nodiscard]] model::SyntheticLeafSpec synthSpecFrom(const SynthChoice& choice);

// A compact spec for simulated captures, e.g. "shape=ovate,serration=round,teeth=14,rows=10":
// keys shape, length, width, symmetry, serration, tooth-depth, teeth, tooth-direction,
// droop, cup, twist, wave, wavelength, rows. Throws InputError naming a bad key or value.
[[nodiscard]] SynthChoice parseSynthSpec(const std::string& text);

struct SynthOptions {
  SynthChoice choice;
  double noiseMm = 0.0;
  std::uint64_t seed = 1;
  std::string markers, truth, glb, svg, figure;
  bool json = false;
  // synth scan
  double dpi = 300.0;
  double petioleLengthMm = 0.0;
  std::string scan;
  // synth study
  std::string study;
  bool quick = false;
  int threads = 0;  // 0: every core
};

class CommandTable;
// Registers `synth leaf`, `synth scan`, `synth figure`, `synth study` and `synth plant`.
void addSynthCommands(CLI::App& app, CommandTable& table);
// `synth plant` (synth_plant_cmd.cpp), under `synth`.
void addSynthPlantCommand(CLI::App& synth, CommandTable& table);

}  // namespace leafdig::cli
