// Helpers for driver/emulator tests: collect events and status changes, wait for them.
#pragma once

#include <chrono>
#include <condition_variable>
#include <map>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "leafdig/devices/links/driver.hpp"
#include "leafdig/devices/sim/sim.hpp"

namespace leafdig::devices::testing {

struct Collector {
  std::mutex mutex;
  std::condition_variable cv;
  std::vector<StylusSample> stylus;
  std::vector<CaliperReading> caliper;
  std::vector<DeviceStatus> statuses;

  Driver::Callbacks callbacks() {
    return {[this](const DeviceEvent& e) {
              {
                std::lock_guard lock(mutex);
                if (const auto* s = std::get_if<StylusSample>(&e))
                  stylus.push_back(*s);
                else
                  caliper.push_back(std::get<CaliperReading>(e));
              }
              cv.notify_all();
            },
            [this](const DeviceStatus& s) {
              {
                std::lock_guard lock(mutex);
                statuses.push_back(s);
              }
              cv.notify_all();
            }};
  }
  template <class Pred>
  bool waitFor(Pred pred, std::chrono::milliseconds timeout = std::chrono::seconds(10)) {
    std::unique_lock lock(mutex);
    return cv.wait_for(lock, timeout, [&] { return pred(*this); });
  }
  std::size_t stylusCount() {
    std::lock_guard lock(mutex);
    return stylus.size();
  }
  bool sawState(LinkState s, const std::string& messagePart = {}) {
    for (const auto& st : statuses)
      if (st.state == s && st.message.find(messagePart) != std::string::npos) return true;
    return false;
  }
  std::string statusLog() {
    std::string out;
    for (const auto& s : statuses) out += std::string(toString(s.state)) + ": " + s.message + " | " + s.remedy + "\n";
    return out;
  }
};

// A small leaf-sized walk: quick moves so that presses come early in a test.
inline sim::VirtualStylus quickStylus(std::uint64_t seed = 1, Vec3 offset = {0, 0, 0}) {
  sim::StylusOptions o;
  o.travelS = 0.15;
  o.dwellS = 0.45;
  o.pressAfterS = 0.1;
  o.pressS = 0.2;
  o.seed = seed;
  o.offsetMm = offset;
  return sim::VirtualStylus({{0, 0, 0}, {40, -20, 2}, {20, -20, 1}, {0, -20, 0}, {-20, -20, 1}, {-40, -20, 2}}, o);
}

inline double dist(const Vec3& a, const Vec3& b) {
  return std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]));
}

}  // namespace leafdig::devices::testing
