// Latency statistics for Google Benchmark counters, shared by the benchmarks that time each
// operation themselves (capture pipeline, station preview).
#pragma once

#include <benchmark/benchmark.h>

#include <algorithm>
#include <string>
#include <vector>

namespace leafdig::bench {

// p50/p99/max of `ms`; all zero when nothing was measured.
struct Percentiles {
  double p50 = 0, p99 = 0, max = 0;
};

inline Percentiles percentiles(std::vector<double> ms) {
  if (ms.empty()) return {};
  std::sort(ms.begin(), ms.end());
  return {ms[ms.size() / 2], ms[std::min(ms.size() - 1, ms.size() * 99 / 100)], ms.back()};
}

// Reports `<prefix>p50_ms`, `<prefix>p99_ms` and `<prefix>max_ms` (nothing when `ms` is
// empty) and returns them.
inline Percentiles reportLatency(benchmark::State& state, const std::vector<double>& ms,
                                 const std::string& prefix = "") {
  const Percentiles p = percentiles(ms);
  if (ms.empty()) return p;
  state.counters[prefix + "p50_ms"] = p.p50;
  state.counters[prefix + "p99_ms"] = p.p99;
  state.counters[prefix + "max_ms"] = p.max;
  return p;
}

}  // namespace leafdig::bench
