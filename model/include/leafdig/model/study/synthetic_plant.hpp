#pragma once
// A synthetic plant digitized in place, with its truth (docs/plants.md, "Synthetic plants"):
// a curved, tapering stem with nodes, seed 002's synthetic tobacco leaves of known area placed
// at known azimuths (a golden-angle spiral) and inclinations, quick leaves (base, tip, the
// widest margin point), a senescent leaf and a bare top node; pot-rim landmarks; everything
// seen by a digitizer whose transmitter stands at a random pose, with Gaussian noise on every
// stylus point and on every caliper reading. For the tests, the accuracy of `plant measure`
// and the demo. A spec and a seed give the same plant on every machine.
#include <Eigen/Geometry>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "leafdig/model/plant/plant_markers.hpp"

namespace leafdig::model {

struct SyntheticPlantSpec {
  std::string id = "P-synth";
  int nodes = 10;                // 2..60, from the base; the top one bare
  int fullEvery = 3;             // every k-th node's leaf is digitized in full (and the largest one)
  int leafRows = 10;             // marker rows of a full leaf (2..60)
  double noiseMm = 0.3;          // σ per stylus coordinate (a FASTRAK's static accuracy is ~0.8 mm RMS)
  double caliperNoiseMm = 0.02;  // σ of a stem diameter
  bool randomPose = true;        // the transmitter at a random pose; false: the digitizer's frame is the plant's
  std::uint64_t seed = 1;
  std::optional<SurveyDate> date;
};

struct SyntheticPlantLeafTruth {
  int node = 0;
  LeafKind kind = LeafKind::None;
  LeafState state = LeafState::Alive;
  std::optional<double> azimuthDeg, inclinationDeg;  // of the base-to-tip chord, in the plant frame
  std::optional<double> lengthMm;                    // full: along the midrib; quick: base to tip
  std::optional<double> widthMm;                     // quick: twice the side point's distance from the chord
  std::optional<double> areaMm2;                     // full: the exact 3-D blade area
};

struct SyntheticPlantTruth {
  Eigen::Isometry3d plantToDigitizer = Eigen::Isometry3d::Identity();
  double collarDiameterMm = 0.0;
  std::vector<Eigen::Vector3d> nodesMm;  // in the plant frame (origin at the collar, +Z up)
  std::vector<double> diametersMm;
  std::vector<SyntheticPlantLeafTruth> leaves;
};

struct SyntheticPlant {
  PlantMarkers markers;  // in the digitizer's frame, noisy
  SyntheticPlantTruth truth;
};

// Throws InputError naming the parameter that makes no plant.
[[nodiscard]] SyntheticPlant synthesizePlant(const SyntheticPlantSpec& spec);

// `leafdig.plant-truth/1`: {"format", "plant", "plant_to_digitizer" (4×4 row-major),
// "collar_diameter_mm", "nodes": [{"node", "point_mm", "diameter_mm"}], "leaves": [{"node",
// "kind", "state", "azimuth_deg", "inclination_deg", "length_mm", "width_mm", "area_mm2"}]}.
[[nodiscard]] std::string syntheticPlantTruthToJson(const std::string& plant, const SyntheticPlantTruth& truth);

}  // namespace leafdig::model
