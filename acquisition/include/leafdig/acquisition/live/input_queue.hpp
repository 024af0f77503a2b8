// The front half of every capture loop, the same for each kind (a leaf's CaptureLoop, a plant's
// PlantCaptureLoop; docs/architecture.md, "Threads"): the digitizer's and the caliper's events,
// their changes of state and the operator's commands arrive from any thread; the loop's thread
// takes them in the order they came. What the loop then does with them — which session, which
// commands — is its kind's; how they are queued, timed, pressed by a pedal and turned into the
// engines' inputs is here once.
//
// Thread contract: post(), postStatus(), command(), stop(), setPedal(), latestStylus() and the
// sinks from any thread; take(), changedState() and the input conversions on the loop's thread.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <utility>
#include <variant>

#include "leafdig/acquisition/protocol/items.hpp"
#include "leafdig/devices/links/driver.hpp"

namespace leafdig::acquisition {

namespace detail {
// The stylus sample as the engines take it: timed by the device's clock where it has one
// (issue 26), else by when its bytes arrived; the stored record is text (binary bytes \xNN).
[[nodiscard]] StylusInput stylusInput(const devices::StylusSample& s, std::int64_t monoNs);
[[nodiscard]] CaliperInput caliperInput(const devices::CaliperReading& r, std::int64_t monoNs);
// A device's status message as the session's `device` event keeps it: the message, then " — "
// and the remedy when there is one.
[[nodiscard]] std::string statusMessage(const devices::DeviceStatus& s);
}  // namespace detail

template <class CommandT>
class InputQueue {
 public:
  using Clock = std::chrono::steady_clock;
  using Input = std::variant<devices::DeviceEvent, devices::DeviceStatus, CommandT>;

  // timeScale > 1 runs a simulated capture faster: the engines see device time × timeScale (a
  // scale that is not above 0 is taken as 1).
  explicit InputQueue(double timeScale = 1.0) : timeScale_(timeScale > 0 ? timeScale : 1.0) {}

  // A device's record. A foot pedal (or the station's Accept key) held down is the stylus
  // button: a stylus sample posted while it is down is taken as pressed.
  void post(const devices::DeviceEvent& e) {
    {
      std::lock_guard lock(mutex_);
      if (const auto* s = std::get_if<devices::StylusSample>(&e)) {
        latestStylus_ = *s;
        if (pedal_ && !s->button) {
          devices::StylusSample pressed = *s;
          pressed.button = true;
          inputs_.emplace_back(devices::DeviceEvent{pressed});
        } else {
          inputs_.emplace_back(e);
        }
      } else {
        inputs_.emplace_back(e);
      }
    }
    cv_.notify_one();
  }
  void postStatus(const devices::DeviceStatus& s) { push(Input{s}); }
  void command(const CommandT& c) { push(Input{c}); }
  void stop() {
    stop_ = true;
    cv_.notify_one();
  }
  [[nodiscard]] bool stopped() const { return stop_; }
  void setPedal(bool down) { pedal_ = down; }
  [[nodiscard]] bool pedal() const { return pedal_; }
  // The latest stylus sample posted (a front end's cursor polls it at its own frame rate
  // instead of receiving every sample).
  [[nodiscard]] std::optional<devices::StylusSample> latestStylus() const {
    std::lock_guard lock(mutex_);
    return latestStylus_;
  }
  // What the devices deliver into (device_set.hpp's DeviceSet): their records posted here,
  // their changes of state queued and told to `onStatus` too (on the drivers' threads).
  [[nodiscard]] devices::Driver::Callbacks sinks(std::function<void(const devices::DeviceStatus&)> onStatus = {}) {
    return {[this](const devices::DeviceEvent& e) { post(e); },
            [this, status = std::move(onStatus)](const devices::DeviceStatus& s) {
              postStatus(s);
              if (status) status(s);
            }};
  }

  // Everything posted so far, in order, after waiting up to `wait` for something (or stop()).
  [[nodiscard]] std::deque<Input> take(std::chrono::milliseconds wait) {
    std::deque<Input> batch;
    std::unique_lock lock(mutex_);
    cv_.wait_for(lock, wait, [&] { return !inputs_.empty() || stop_.load(); });
    batch.swap(inputs_);
    return batch;
  }

  // Nanoseconds since the queue was made, × the time scale: the engines' clock.
  [[nodiscard]] std::int64_t monoNs(Clock::time_point t) const {
    return static_cast<std::int64_t>(
        static_cast<double>(std::chrono::duration_cast<std::chrono::nanoseconds>(t - t0_).count()) * timeScale_);
  }
  [[nodiscard]] std::int64_t now() const { return monoNs(Clock::now()); }
  [[nodiscard]] StylusInput stylusInput(const devices::StylusSample& s) const {
    return detail::stylusInput(s, monoNs(s.deviceTime.value_or(s.t)));
  }
  [[nodiscard]] CaliperInput caliperInput(const devices::CaliperReading& r) const {
    return detail::caliperInput(r, monoNs(r.t));
  }
  // The state's word when `s` changes its device's state since the last one logged, else
  // nothing: a session keeps one `device` event per change of state (not per message or rate),
  // enough to see an unplug and its end. The loop's thread only.
  [[nodiscard]] std::optional<std::string> changedState(const devices::DeviceStatus& s) {
    std::string state = devices::toString(s.state);
    std::string& last = deviceStates_[s.device];
    if (last == state) return std::nullopt;
    last = state;
    return state;
  }

 private:
  void push(Input in) {
    {
      std::lock_guard lock(mutex_);
      inputs_.push_back(std::move(in));
    }
    cv_.notify_one();
  }

  double timeScale_;
  Clock::time_point t0_ = Clock::now();
  mutable std::mutex mutex_;
  std::condition_variable cv_;
  std::deque<Input> inputs_;
  std::optional<devices::StylusSample> latestStylus_;
  std::atomic<bool> stop_{false};
  std::atomic<bool> pedal_{false};
  std::map<std::string, std::string> deviceStates_;  // the last state logged per device (loop's thread)
};

}  // namespace leafdig::acquisition
