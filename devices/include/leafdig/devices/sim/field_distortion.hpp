// A distorted magnetic field for the simulated digitizers (issue 50; docs/devices.md, "The
// field"). Metal near a magnetic tracker — a steel bench, a pot stand, a radiator — bends its
// field: the sensor's reported position and orientation are off by a static, repeatable error
// that grows with the distance from the transmitter. A `leafdig.field-distortion/1` file holds
// that error on a regular grid in the transmitter's frame:
//
//   {"format": "leafdig.field-distortion/1", "units": "mm", "frame": "transmitter",
//    "origin": [x, y, z], "spacing_mm": s, "shape": [nx, ny, nz],
//    "displacement_mm": [[dx, dy, dz], …],   // nx·ny·nz cells, x fastest, then y, then z
//    "rotation_deg": [[rx, ry, rz], …]}      // optional, on the same grid
//
// Between grid points the error is trilinear; outside the grid it is the nearest cell's (the
// position is clamped to the grid's box). A simulated sensor at true position p reports
// p + displacement(p) and its orientation turned by the small rotation rotation(p) (about the
// transmitter's x, y and z axes, in that order). The file is checked as any file leafdig reads:
// every refusal names the file, the field and what to do (FieldDistortionError).
#pragma once

#include <array>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "leafdig/devices/sim/sim.hpp"

namespace leafdig::devices::sim {

class FieldDistortionError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

inline constexpr const char* kFieldDistortionFormat = "leafdig.field-distortion/1";
// Limits of what a distortion file may hold: a grid of at most 2 000 000 cells of at most 400
// per axis, a spacing of 1–1000 mm, an origin within ±10 m, displacements within ±1000 mm and
// rotations within ±45°.
inline constexpr std::size_t kMaxFieldCells = 2'000'000;

struct FieldDistortion {
  Vec3 originMm{};
  double spacingMm = 100;
  std::array<int, 3> shape{2, 2, 2};
  std::vector<Vec3> displacementMm;  // shape[0]·shape[1]·shape[2], x fastest
  std::vector<Vec3> rotationDeg;     // empty, or as many as displacementMm

  // The error at a position in the transmitter's frame (mm; degrees).
  [[nodiscard]] Vec3 displacementAt(const Vec3& pMm) const;
  [[nodiscard]] Vec3 rotationAt(const Vec3& pMm) const;  // zero without rotation_deg
  // A sensor at `truthMm` with `orientationDeg` (azimuth, elevation, roll) as the field makes it
  // report: the position moved, the orientation turned.
  [[nodiscard]] Vec3 reportedPosition(const Vec3& truthMm) const;
  [[nodiscard]] Vec3 reportedOrientation(const Vec3& truthMm, const Vec3& orientationDeg) const;
};

// Reads a distortion file's text; `source` names it in refusals.
[[nodiscard]] FieldDistortion parseFieldDistortion(const std::string& json, const std::string& source);
[[nodiscard]] FieldDistortion readFieldDistortion(const std::string& path);
// The file's text (the displacement and rotation to 0.001 mm / 0.0001°); what parse reads back.
[[nodiscard]] std::string encodeFieldDistortion(const FieldDistortion& f);

// The steel-bench preset (docs/devices.md, "The field"): a conducting steel plate `belowMm`
// under the transmitter, modelled as an image of the transmitter mirrored in the plate whose
// coupling opposes the source's. The tracker takes its range from the coupling's strength
// (∝ 1/r³), so a sensor at distance r from the source and r' from the image reads its range as
// r·(1 − k·(r/r')³)^(−1/3): pushed outwards, most near the plate and far from the source. Its
// direction tilts about the horizontal axis across the line to the source by k·(r/r')³/2 rad.
// The grid starts 50 mm above the plate (no sensor goes into the bench) and spans 1.6 × 1.6 ×
// 1 m around the transmitter, every 100 mm.
struct SteelBenchModel {
  double belowMm = 250;    // the plate's depth under the transmitter (a stand on a steel bench)
  double strength = 0.08;  // k: the share of the source's coupling the plate's eddy currents take back
  double spacingMm = 100;
  std::array<int, 3> shape{17, 17, 11};  // from (−800, −800, 50 − belowMm)
};
[[nodiscard]] FieldDistortion steelBench(const SteelBenchModel& m = {});

// A sensor moved through a distorted field: what `inner` does, reported as the field makes it
// (its truth left as it is). Thread contract: as StylusMotion (the field is read-only).
class DistortedMotion final : public StylusMotion {
 public:
  DistortedMotion(std::shared_ptr<const StylusMotion> inner, std::shared_ptr<const FieldDistortion> field);
  [[nodiscard]] State at(double t, std::uint64_t k) const override;

 private:
  std::shared_ptr<const StylusMotion> inner_;
  std::shared_ptr<const FieldDistortion> field_;
};

}  // namespace leafdig::devices::sim
