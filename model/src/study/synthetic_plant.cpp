#include "leafdig/model/study/synthetic_plant.hpp"

#include <cmath>
#include <nlohmann/json.hpp>
#include <numbers>

#include "draws.hpp"
#include "json_text.hpp"
#include "leafdig/model/errors.hpp"
#include "leafdig/model/limits.hpp"
#include "leafdig/model/plant/marker_points.hpp"
#include "leafdig/model/plant/plant_frame.hpp"
#include "leafdig/model/synth/synthetic_leaf.hpp"

namespace leafdig::model {

namespace {

constexpr double kDeg = std::numbers::pi / 180.0;
constexpr double kRimRadiusMm = 110.0;
constexpr double kRimHeightMm = 25.0;  // the soil lies this far below the pot rim
constexpr double kPetioleMm = 15.0;    // from the stem's axis to a leaf's base, horizontally

using detail::roundTo;

// The unit direction with this azimuth (counterclockwise from +X, seen from above) and this
// inclination from +Z.
Eigen::Vector3d direction(double azimuthDeg, double inclinationDeg) {
  const double a = azimuthDeg * kDeg, i = inclinationDeg * kDeg;
  return {std::sin(i) * std::cos(a), std::sin(i) * std::sin(a), std::cos(i)};
}

// A rotation taking the leaf frame (+Y base to tip, +Z adaxial) to a leaf pointing along
// `along` with its adaxial side as near +Z as the direction allows.
Eigen::Matrix3d leafRotation(const Eigen::Vector3d& along) {
  Eigen::Vector3d up = Eigen::Vector3d::UnitZ() - along.z() * along;
  if (up.norm() < 1e-9) up = Eigen::Vector3d::UnitX();
  up.normalize();
  Eigen::Matrix3d r;
  r.col(0) = along.cross(up);
  r.col(1) = along;
  r.col(2) = up;
  return r;
}

// The stem's axis at height z above the collar: a gentle curve, as a tobacco stem leans.
Eigen::Vector3d stemAt(double z) {
  return {4.0e-5 * z * z, 0.02 * z, z};
}

}  // namespace

SyntheticPlant synthesizePlant(const SyntheticPlantSpec& spec) {
  if (spec.nodes < 2 || spec.nodes > 60) throw InputError("--nodes must be 2 to 60");
  // Every point must stay where a digitizer measures (within kMaxCoordinateMm of the
  // transmitter, which stands up to 700 mm off the plant's base) with its leaves (≤ 600 mm off
  // the stem): a plant its own `plant measure` would refuse is not written (issue 47, 22).
  const auto heightOf = [](int nodes) { return 55.0 * nodes + 3.0 * nodes * (nodes + 1); };
  if (heightOf(spec.nodes) + 1300.0 > kMaxCoordinateMm) {
    int most = 2;
    while (heightOf(most + 1) + 1300.0 <= kMaxCoordinateMm) ++most;
    throw InputError("--nodes " + std::to_string(spec.nodes) + " makes a plant " +
                     std::to_string(static_cast<int>(heightOf(spec.nodes) / 10.0) / 100.0).substr(0, 5) +
                     " m tall, beyond what a digitizer measures from its transmitter (" +
                     std::to_string(static_cast<int>(kMaxCoordinateMm / 1000.0)) + " m): give at most " +
                     std::to_string(most) + " nodes");
  }
  if (spec.fullEvery < 1) throw InputError("--full-every must be 1 or more");
  if (spec.leafRows < 2 || spec.leafRows > 60) throw InputError("--rows must be 2 to 60");
  if (!(spec.noiseMm >= 0.0 && spec.noiseMm <= 10.0)) throw InputError("--noise must be 0 to 10 mm");
  if (!(spec.caliperNoiseMm >= 0.0 && spec.caliperNoiseMm <= 1.0))
    throw InputError("the caliper's noise must be 0 to 1 mm");
  detail::Draws draws(spec.seed, 7);
  SyntheticPlant out;
  SyntheticPlantTruth& truth = out.truth;
  PlantMarkers& plant = out.markers;
  plant.plant = spec.id;
  plant.date = spec.date;

  // The transmitter's pose: a uniformly random rotation (a normalised Gaussian quaternion)
  // and a translation within ±400 mm.
  if (spec.randomPose) {
    Eigen::Quaterniond q(draws.gaussian(), draws.gaussian(), draws.gaussian(), draws.gaussian());
    q.normalize();
    truth.plantToDigitizer.linear() = q.toRotationMatrix();
    truth.plantToDigitizer.translation() =
        Eigen::Vector3d(draws.in(-400, 400), draws.in(-400, 400), draws.in(-400, 400));
  }
  const auto seen = [&](const Eigen::Vector3d& plantMm) {
    Eigen::Vector3d p = truth.plantToDigitizer * plantMm;
    for (int k = 0; k < 3; ++k) p[k] = roundTo(p[k] + spec.noiseMm * draws.gaussian(), 0.01);
    return p;
  };
  const auto caliper = [&](double mm) { return roundTo(mm + spec.caliperNoiseMm * draws.gaussian(), 0.01); };

  // Landmarks on the rim, unevenly spaced; the first sets +X.
  for (const double angle : {0.0, 95.0, 190.0, 280.0})
    plant.landmarksMm.push_back(
        seen({kRimRadiusMm * std::cos(angle * kDeg), kRimRadiusMm * std::sin(angle * kDeg), kRimHeightMm}));
  truth.collarDiameterMm = 22.0;
  plant.collarMm = seen(Eigen::Vector3d::Zero());
  plant.collarDiameterMm = caliper(truth.collarDiameterMm);

  // Nodes: internodes lengthening up the stem, the stem thinning.
  const int n = spec.nodes;
  double height = 0.0;
  int largest = 1;
  double largestLength = 0.0;
  const auto leafLength = [n](int k) { return 220.0 + 320.0 * std::sin(std::numbers::pi * (k - 0.5) / n); };
  for (int k = 1; k <= n; ++k)
    if (leafLength(k) > largestLength) largestLength = leafLength(k), largest = k;
  for (int k = 1; k <= n; ++k) {
    height += 55.0 + 6.0 * k;
    const Eigen::Vector3d node = stemAt(height);
    const double diameter = 22.0 - 13.0 * k / n;
    truth.nodesMm.push_back(node);
    truth.diametersMm.push_back(diameter);
    PlantNode pn;
    pn.pointMm = seen(node);
    pn.diameterMm = caliper(diameter);

    SyntheticPlantLeafTruth leaf;
    leaf.node = k;
    if (k == n) {  // the bare top
      plant.nodes.push_back(pn);
      continue;
    }
    if (k == 1) {  // the lowest leaf is senescent: flagged, not digitized
      leaf.kind = LeafKind::None;
      leaf.state = LeafState::Dead;
      pn.state = LeafState::Dead;
      truth.leaves.push_back(leaf);
      plant.nodes.push_back(pn);
      continue;
    }
    const double azimuth = std::fmod(30.0 + 137.5 * (k - 1), 360.0);
    const double inclination = 95.0 - 50.0 * (k - 1) / (n - 1);
    const Eigen::Vector3d out2d(std::cos(azimuth * kDeg), std::sin(azimuth * kDeg), 0.0);
    const Eigen::Vector3d base = node + (diameter / 2 + kPetioleMm) * out2d;
    const Eigen::Vector3d along = direction(azimuth, inclination);
    const Eigen::Matrix3d rotation = leafRotation(along);
    const double length = leafLength(k);
    if (k % spec.fullEvery == 0 || k == largest) {
      SyntheticLeafSpec ls = defaultSyntheticSpec(LeafShape::Tobacco);
      ls.outline.lengthMm = length;
      ls.rows = spec.leafRows;
      ls.id = spec.id + "-L" + std::to_string(k);
      ls.plant = spec.id;
      ls.type = k <= n / 3 ? "lower" : k <= 2 * n / 3 ? "middle" : "upper";
      const SyntheticLeaf synthetic(ls);
      MarkerSet exact = synthetic.markers(0.0, spec.seed + static_cast<std::uint64_t>(k));
      const auto place = [&](const Eigen::Vector3d& p) { return Eigen::Vector3d(base + rotation * p); };
      forEachPoint(exact, [&](Eigen::Vector3d& p) { p = place(p); });
      const LeafPose pose = leafPose(exact.rows.back().pointsMm[kMidribColumn], exact.tipMm);
      leaf.kind = LeafKind::Full;
      leaf.azimuthDeg = pose.azimuthDeg;
      leaf.inclinationDeg = pose.inclinationDeg;
      leaf.lengthMm = synthetic.midribLengthMm();
      leaf.areaMm2 = synthetic.area();
      MarkerSet noisy = exact;
      forEachPoint(noisy, [&](Eigen::Vector3d& p) { p = seen(p); });
      pn.leaf = std::move(noisy);
    } else {
      const double width = 0.5 * length;
      const Eigen::Vector3d tip = base + length * along;
      const Eigen::Vector3d side = base + 0.45 * length * along + 0.5 * width * rotation.col(0);
      leaf.kind = LeafKind::Quick;
      leaf.azimuthDeg = azimuth;
      leaf.inclinationDeg = inclination;
      leaf.lengthMm = length;
      leaf.widthMm = width;
      QuickLeaf q;
      q.baseMm = seen(base);
      q.tipMm = seen(tip);
      q.sideMm = seen(side);
      q.type = k <= n / 3 ? "lower" : k <= 2 * n / 3 ? "middle" : "upper";
      pn.leaf = q;
    }
    truth.leaves.push_back(leaf);
    plant.nodes.push_back(std::move(pn));
  }
  return out;
}

std::string syntheticPlantTruthToJson(const std::string& plant, const SyntheticPlantTruth& t) {
  using nlohmann::json;
  const auto optional = [](const std::optional<double>& v) { return v ? json(*v) : json(); };
  json matrix = json::array();
  const Eigen::Matrix4d m = t.plantToDigitizer.matrix();
  for (int r = 0; r < 4; ++r) matrix.push_back(json::array({m(r, 0), m(r, 1), m(r, 2), m(r, 3)}));
  json nodes = json::array();
  for (std::size_t i = 0; i < t.nodesMm.size(); ++i)
    nodes.push_back({{"node", i + 1},
                     {"point_mm", json::array({t.nodesMm[i].x(), t.nodesMm[i].y(), t.nodesMm[i].z()})},
                     {"diameter_mm", t.diametersMm[i]}});
  json leaves = json::array();
  for (const SyntheticPlantLeafTruth& l : t.leaves)
    leaves.push_back({{"node", l.node},
                      {"kind", toString(l.kind)},
                      {"state", toString(l.state)},
                      {"azimuth_deg", optional(l.azimuthDeg)},
                      {"inclination_deg", optional(l.inclinationDeg)},
                      {"length_mm", optional(l.lengthMm)},
                      {"width_mm", optional(l.widthMm)},
                      {"area_mm2", optional(l.areaMm2)}});
  const json doc = {{"format", "leafdig.plant-truth/1"},        {"plant", plant}, {"plant_to_digitizer", matrix},
                    {"collar_diameter_mm", t.collarDiameterMm}, {"nodes", nodes}, {"leaves", leaves}};
  return detail::dumpFinite(doc, 2);
}

}  // namespace leafdig::model
