#pragma once
// How accurate is a captured leaf (issue 16, docs/accuracy.md)?
//
// Two tools. `areaUncertainty` gives one leaf's blade area a 95 % interval: a Monte-Carlo
// over the digitizer's stated accuracy (every marker coordinate redrawn with Gaussian noise
// of σ, the blade rebuilt and its area measured at the resolution the nominal area settled
// at; the basic bootstrap interval), reaching upwards by what the rows lose (the larger of
// the row-drop estimate and, for interp, the under-estimate the study measured). The study
// found it holds the true area in more than 95 % of captures (docs/accuracy.md). `runAccuracyStudy` measures the whole
// chain on synthetic leaves whose answer is known: markers by the protocol with noise, the leaf model built from them,
// its blade area, midrib length and vein positions against the truth.
#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "leafdig/model/leaf/blade.hpp"
#include "leafdig/model/leaf/markers.hpp"
#include "leafdig/model/metrics/metrics.hpp"
#include "leafdig/model/synth/synthetic_leaf.hpp"

namespace leafdig::model {

struct AccuracyCase {
  LeafShape shape = LeafShape::Tobacco;
  double lengthMm = 300.0;
  int rows = 12;
  double sigmaMm = 0.0;
  std::uint64_t seed = 1;
  Serration serration = Serration::None;  // the margin's teeth (20 per side, 1.5 % of the width deep)
};

struct AccuracyResult {
  AccuracyCase leaf;
  BladeKind blade = BladeKind::Interp;
  double trueAreaMm2 = 0.0;
  double modelAreaMm2 = 0.0;
  double areaErrorPercent = 0.0;  // (model − true) / true × 100
  double trueMidribMm = 0.0;
  double modelMidribMm = 0.0;
  double midribErrorPercent = 0.0;
  double veinMeanMm = 0.0;  // distance of the model's vein centre lines from the true veins
  double veinMaxMm = 0.0;
  bool inInterval = false;  // the true area inside areaUncertainty's 95 % interval (when checked)
  // …and inside the interval a leaf whose serration was not declared gets (no margin term).
  bool inIntervalUndeclared = false;
  bool intervalChecked = false;
  AreaUncertainty interval;  // when checked
};

struct AccuracyPlan {
  std::vector<LeafShape> shapes;
  std::vector<double> lengthsMm;
  std::vector<int> rows;
  std::vector<double> sigmasMm;
  std::vector<BladeKind> blades;
  int seedsPerNoisyCase = 8;  // σ = 0 is deterministic: one seed
  // The interval's coverage is checked on every noisy interp capture (the interval assuming
  // the σ the capture had), with this many draws (0: never).
  int coverageDraws = 32;
  // Toothed margins (issue 26): every shape, length and row count again with each of these
  // serrations (declared as the leaf has it), captured with each of marginSigmasMm and
  // marginSeeds seeds, interp only, every capture's interval checked. The tables above are
  // of the smooth leaves alone.
  std::vector<Serration> margins;
  std::vector<double> marginSigmasMm;
  int marginSeeds = 0;

  // The study of docs/accuracy.md, and a small one for tests and CI.
  [[nodiscard]] static AccuracyPlan full();
  [[nodiscard]] static AccuracyPlan quick();
};

// Runs every case on `threads` threads (results in plan order whatever the thread count).
// `progress` (optional) is called with done and total counts from the calling thread.
[[nodiscard]] std::vector<AccuracyResult> runAccuracyStudy(
    const AccuracyPlan& plan, int threads, const std::function<void(std::size_t, std::size_t)>& progress = {});

// The report: docs/accuracy.md's text (tables and the answers), its CSV (one row per
// result) and its figures (SVG line charts, named as the Markdown links them).
struct AccuracyReport {
  std::string markdown;
  std::string csv;
  std::vector<std::pair<std::string, std::string>> figures;  // file name, SVG text
};
[[nodiscard]] AccuracyReport accuracyReport(const AccuracyPlan& plan, const std::vector<AccuracyResult>& results,
                                            const std::string& command);

}  // namespace leafdig::model
