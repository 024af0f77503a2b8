#pragma once
// Independent jobs on the machine's cores (plant exports, plant metrics).
#include <algorithm>
#include <atomic>
#include <cstddef>
#include <exception>
#include <thread>
#include <vector>

namespace leafdig::model::detail {

// Runs job(i) for every i in [0, count) on up to `threads` threads (0: one per core), the
// calling thread among them, taking jobs in the order `order` gives (all of 0..count-1) or
// else in index order. A job's exception is kept; once every thread has joined, the one of
// the lowest index is rethrown, so the error reported does not depend on timing.
template <class Job>
void parallelFor(std::size_t count, unsigned threads, Job&& job, const std::vector<std::size_t>& order = {}) {
  std::vector<std::exception_ptr> failures(count);
  std::atomic<std::size_t> next{0};
  const auto work = [&] {
    for (std::size_t k = next++; k < count; k = next++) {
      const std::size_t i = order.empty() ? k : order[k];
      try {
        job(i);
      } catch (...) {
        failures[i] = std::current_exception();
      }
    }
  };
  if (threads == 0) threads = std::max(1U, std::thread::hardware_concurrency());
  const std::size_t helpers = count == 0 ? 0 : std::min<std::size_t>(threads, count) - 1;
  std::vector<std::thread> pool;
  pool.reserve(helpers);
  for (std::size_t h = 0; h < helpers; ++h) pool.emplace_back(work);
  work();
  for (auto& t : pool) t.join();
  for (const auto& f : failures)
    if (f) std::rethrow_exception(f);
}

}  // namespace leafdig::model::detail
