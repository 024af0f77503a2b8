#pragma once
// Reproducible random numbers for the model: SplitMix64 (Steele, Lea, Flood 2014), uniform
// doubles from its top 53 bits and Gaussian pairs by Box–Muller. The same numbers from every
// standard library, unlike the <random> distributions, so a seed gives the same file on
// every machine.
#include <cmath>
#include <cstdint>
#include <numbers>

namespace leafdig::model::detail {

// `v` to the nearest multiple of `step`: a reading as a device prints it (0.01 mm).
inline double roundTo(double v, double step) {
  return std::round(v / step) * step;
}

class Draws {
 public:
  explicit Draws(std::uint64_t seed, std::uint64_t stream = 0)
      : state_(seed ^ (0x9E3779B97F4A7C15ULL * (stream + 1))) {}
  // In [0, 1).
  double uniform() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }
  double in(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  // Standard normal.
  double gaussian() {
    if (hasSpare_) {
      hasSpare_ = false;
      return spare_;
    }
    const double u1 = 1.0 - uniform();  // (0, 1]
    const double u2 = uniform();
    const double r = std::sqrt(-2.0 * std::log(u1));
    const double a = 2.0 * std::numbers::pi * u2;
    spare_ = r * std::sin(a);
    hasSpare_ = true;
    return r * std::cos(a);
  }

 private:
  std::uint64_t next() {
    std::uint64_t z = (state_ += 0x9E3779B97F4A7C15ULL);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
    return z ^ (z >> 31);
  }
  std::uint64_t state_;
  double spare_ = 0.0;
  bool hasSpare_ = false;
};

}  // namespace leafdig::model::detail
