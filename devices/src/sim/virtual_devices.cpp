// Virtual stylus and caliper: deterministic motion, noise, tremor, dwell and presses.
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <numbers>

#include "leafdig/devices/rotation_eigen.hpp"
#include "leafdig/devices/sim/sim.hpp"

namespace leafdig::devices::sim {
namespace {

std::uint64_t splitmix(std::uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}
double uniform(std::uint64_t h) {
  return (static_cast<double>(h >> 11) + 0.5) / 9007199254740992.0;
}
double gauss(std::uint64_t seed, std::uint64_t k, int axis) {
  const std::uint64_t h1 = splitmix(seed * 0x1000193ull + k * 7 + static_cast<std::uint64_t>(axis));
  const std::uint64_t h2 = splitmix(h1);
  return std::sqrt(-2.0 * std::log(uniform(h1))) * std::cos(2 * std::numbers::pi * uniform(h2));
}

// Sensor noise, 9 Hz physiological tremor and a slightly wobbling orientation.
void addHandNoise(StylusMotion::State& s, const StylusOptions& o, double t, std::uint64_t k) {
  const double w = 2 * std::numbers::pi * 9.0;
  for (std::size_t a = 0; a < 3; ++a)
    s.positionMm[a] = s.truthMm[a] + o.sigmaMm * gauss(o.seed, k, static_cast<int>(a)) +
                      o.tremorMm * std::sin(w * t + 1.7 * static_cast<double>(a));
  s.orientationDeg = {kHandOrientationDeg[0] + 0.5 * gauss(o.seed, k, 3),
                      kHandOrientationDeg[1] + 0.5 * gauss(o.seed, k, 4),
                      kHandOrientationDeg[2] + 0.5 * gauss(o.seed, k, 5)};
}

// The orientation `deg` (azimuth, elevation, roll) turned by `angleDeg` about the horizontal axis
// at azimuth `axisDeg`, on the transmitter's side.
Vec3 tilted(const Vec3& deg, double angleDeg, double axisDeg) {
  const double rad = std::numbers::pi / 180.0;
  const Eigen::Vector3d axis(std::cos(axisDeg * rad), std::sin(axisDeg * rad), 0.0);
  return eulerDegFromRotation(
      rotationOf(Eigen::AngleAxisd(angleDeg * rad, axis).toRotationMatrix() * matrixOf(rotationFromEulerDeg(deg))));
}

}  // namespace

VirtualStylus::VirtualStylus(std::vector<Vec3> targets, StylusOptions o) : targets_(std::move(targets)), o_(o) {
  if (targets_.empty()) targets_.push_back({0, 0, 0});
  for (auto& t : targets_)
    for (std::size_t i = 0; i < 3; ++i) t[i] += o_.offsetMm[i];
}

double VirtualStylus::period() const {
  return static_cast<double>(targets_.size()) * (o_.travelS + o_.dwellS);
}

StylusMotion::State VirtualStylus::at(double t, std::uint64_t k) const {
  State s;
  const double step = o_.travelS + o_.dwellS;
  double local = std::fmod(std::max(t, 0.0), period());
  const auto i = std::min(static_cast<std::size_t>(local / step), targets_.size() - 1);
  local -= static_cast<double>(i) * step;
  const Vec3& to = targets_[i];
  // Travel from the previous marker, lifted up to 30 mm off the leaf on the way.
  const Vec3& from = targets_[i == 0 ? targets_.size() - 1 : i - 1];
  if (local < o_.travelS) {
    const double f = local / o_.travelS;
    const double u = 0.5 - 0.5 * std::cos(std::numbers::pi * f);  // smooth start and stop
    for (std::size_t a = 0; a < 3; ++a) s.truthMm[a] = from[a] + u * (to[a] - from[a]);
    s.truthMm[2] += 30.0 * std::sin(std::numbers::pi * f) * std::sin(std::numbers::pi * f);
  } else {
    s.truthMm = to;
    const double d = local - o_.travelS;
    s.target = static_cast<int>(i);
    s.button = d >= o_.pressAfterS && d < o_.pressAfterS + o_.pressS;
  }
  addHandNoise(s, o_, t, k);
  return s;
}

VirtualCaliper::VirtualCaliper(std::vector<double> v, CaliperOptions o) : values_(std::move(v)), o_(o), rng_(o.seed) {
  if (values_.empty()) values_.push_back(1.0);
}

double VirtualCaliper::next() {
  std::lock_guard lock(mutex_);
  std::normal_distribution<double> n(0.0, o_.sigmaMm);
  const double truth = held_ ? *held_ : values_[index_ % values_.size()];
  ++index_;
  const double v = truth + n(rng_);
  const double r = std::round(v / o_.resolutionMm) * o_.resolutionMm;
  return r == 0.0 ? 0.0 : r;
}

void VirtualCaliper::hold(double thicknessMm) {
  std::lock_guard lock(mutex_);
  held_ = thicknessMm;
}
void VirtualCaliper::release() {
  std::lock_guard lock(mutex_);
  held_.reset();
}

std::size_t VirtualCaliper::count() const {
  std::lock_guard lock(mutex_);
  return index_;
}

// ---- operator hand -------------------------------------------------------------------------
OperatorHand::OperatorHand(StylusOptions o, double speed) : o_(o), speed_(speed > 0 ? speed : 1.0) {}

void OperatorHand::perform(const Gesture& g) {
  std::lock_guard lock(mutex_);
  // It begins at the device's latest record: however late the device's records reach the host,
  // the whole gesture is in them, as long and as still as the hand made it.
  const double start = std::max(seenUntil_, busyUntil_);
  queue_.emplace_back(start, g);
  busyUntil_ = start + g.travelS + g.settleS + g.pressS + (g.pressS > 0 ? 0.05 : 0.0);
}

bool OperatorHand::idle() const {
  std::lock_guard lock(mutex_);
  return seenUntil_ >= busyUntil_;
}

StylusMotion::State OperatorHand::at(double t, std::uint64_t k) const {
  const double now = speed_ * t;
  State s;
  double pivotDeg = 0, pivotU = 0;  // a pivot under way: its tilt and how far it has gone (0…1)
  {
    std::lock_guard lock(mutex_);
    seenUntil_ = std::max(seenUntil_, now);
    // Gestures that are over leave the hand resting on their target.
    auto& q = queue_;
    auto& rest = restMm_;
    while (!q.empty()) {
      const auto& [start, g] = q.front();
      if (now < start + g.travelS + g.settleS + g.pressS) break;
      rest = g.targetMm;
      q.pop_front();
    }
    s.truthMm = rest;
    if (!q.empty() && now >= q.front().first) {
      const auto& [start, g] = q.front();
      const double local = now - start;
      if (local < g.travelS) {
        const double f = local / g.travelS;
        const double u = 0.5 - 0.5 * std::cos(std::numbers::pi * f);
        for (std::size_t a = 0; a < 3; ++a) s.truthMm[a] = rest[a] + u * (g.targetMm[a] - rest[a]);
        s.truthMm[2] += 30.0 * std::sin(std::numbers::pi * f) * std::sin(std::numbers::pi * f);
      } else {
        s.truthMm = g.targetMm;
        s.target = 0;
        s.button = g.pressS > 0 && local >= g.travelS + g.settleS;
        if (s.button && g.pivotDeg > 0) {
          pivotDeg = g.pivotDeg;
          pivotU = (local - g.travelS - g.settleS) / g.pressS;
        }
      }
    }
  }
  for (std::size_t a = 0; a < 3; ++a) s.truthMm[a] += o_.offsetMm[a];
  addHandNoise(s, o_, now, k);
  if (pivotDeg > 0) {
    // Twice round, the tilt swinging between 60 % and all of pivotDeg; it starts upright.
    const double ramp = std::min(1.0, pivotU * 10.0);
    const double tilt = ramp * pivotDeg * (0.8 + 0.2 * std::sin(6.0 * std::numbers::pi * pivotU));
    s.orientationDeg = tilted(s.orientationDeg, tilt, 720.0 * pivotU);
  }
  return s;
}

// ---- a stylus whose sensor is not at its tip -------------------------------------------------
StylusSensor::StylusSensor(std::shared_ptr<const StylusMotion> tip, Vec3 tipMm, double tiltDegPerMm)
    : tip_(std::move(tip)), tipMm_(tipMm), tiltDegPerMm_(tiltDegPerMm) {}

namespace {

// The hand leans the stylus towards where it presses: `deg` turned by the tip's place.
Vec3 leaning(const Vec3& deg, const Vec3& tipTruthMm, double degPerMm) {
  const auto lean = [&](double mm) { return std::clamp(degPerMm * mm, -30.0, 30.0); };
  return {deg[0] + lean(tipTruthMm[0]), deg[1] + lean(tipTruthMm[1]), deg[2]};
}

Vec3 rotate(const Vec3& deg, const Vec3& v) {
  const Eigen::Vector3d r = matrixOf(rotationFromEulerDeg(deg)) * Eigen::Vector3d(v[0], v[1], v[2]);
  return {r.x(), r.y(), r.z()};
}

}  // namespace

Vec3 StylusSensor::turned(const Vec3& tipTruthMm, const Vec3& v) const {
  return rotate(leaning(kHandOrientationDeg, tipTruthMm, tiltDegPerMm_), v);
}

Vec3 StylusSensor::sensorFromTip(const Vec3& tipTruthMm) const {
  const Vec3 o = turned(tipTruthMm, tipMm_);
  return {-o[0], -o[1], -o[2]};
}

StylusMotion::State StylusSensor::at(double t, std::uint64_t k) const {
  State s = tip_->at(t, k);
  if (tipMm_ == Vec3{0, 0, 0}) return s;
  s.orientationDeg = leaning(s.orientationDeg, s.truthMm, tiltDegPerMm_);
  const Vec3 offset = rotate(s.orientationDeg, tipMm_);
  for (std::size_t a = 0; a < 3; ++a) {
    s.truthMm[a] -= offset[a];
    s.positionMm[a] -= offset[a];
  }
  return s;
}

}  // namespace leafdig::devices::sim
