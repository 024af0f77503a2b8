// Virtual stylus and caliper: deterministic motion, noise, tremor, dwell and presses.
#include <cmath>
#include <numbers>

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
  s.orientationDeg = {10.0 + 0.5 * gauss(o.seed, k, 3), -45.0 + 0.5 * gauss(o.seed, k, 4), 0.5 * gauss(o.seed, k, 5)};
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
      }
    }
  }
  for (std::size_t a = 0; a < 3; ++a) s.truthMm[a] += o_.offsetMm[a];
  addHandNoise(s, o_, now, k);
  return s;
}

}  // namespace leafdig::devices::sim
