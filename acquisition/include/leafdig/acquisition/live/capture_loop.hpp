// The capture thread of docs/architecture.md, once for every kind of capture: the digitizer's
// and the caliper's events, their changes of state and the operator's commands arrive on one
// queue from any thread (input_queue.hpp); one thread (the caller of run()) feeds them in the
// order they came to the kind's session, retries a store that refused a write, counts what it
// has dealt with, and ends when the session ends, on a quit command or on stop().
//
// What a capture does with each input is its kind's (a LoopKind): a leaf (leaf_loop.hpp's
// LiveLeaf: a CaptureSession, its feedback, snapshots and preview worker) or a plant
// (plant_loop.hpp's LivePlant: a PlantCaptureSession and its technician's feedback). A third
// kind is one more LoopKind beside them (docs/architecture.md, "Adding a kind of capture"), not
// another loop.
//
// Thread contract: post*(), command(), stop(), setPedal(), latestStylus(), the counters and
// sinks() from any thread; run() and session() on the thread that owns the session (and its
// store). The kind's listeners run on that thread (a leaf's preview on its worker).
#pragma once

#include <atomic>
#include <chrono>
#include <concepts>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <variant>

#include "leafdig/acquisition/live/input_queue.hpp"

namespace leafdig::acquisition {

// What a kind of capture gives the loop. Each input is handed over on the loop's thread; the
// kind decides, writes and tells its front end (its listeners), and says when it has ended.
template <class K>
concept LoopKind = requires(K k, const K ck, const StylusInput& s, const CaliperInput& c,
                            const typename K::Command& command, const std::string& word, std::int64_t now) {
  typename K::Command;  // what its operator asks (parsed from the kind's words)
  typename K::Result;   // what run() returns: the leaf's last snapshot, the plant's tally
  typename K::Listen;   // what run() is given: the front end's listeners, when not given before
  { ck.timeScale() } -> std::convertible_to<double>;  // > 1: a simulation faster than real time
  k.begin(typename K::Listen{});                      // run() starts: tell the front end where it is
  k.stylus(s);
  k.caliper(c);
  { k.command(command, now) } -> std::same_as<bool>;  // false: quit (the loop ends, nothing written)
  k.device(word, word, word, now);                    // a device changed state: device, state, message
  k.retryStore(now);                                  // the store refused a write: try again
  { ck.storeBlocked() } -> std::same_as<bool>;
  { ck.ended() } -> std::same_as<bool>;
  { k.finish() } -> std::same_as<typename K::Result>;  // run() ends (also when it threw)
  k.session();
};

template <LoopKind Kind>
class CaptureLoop {
 public:
  using Command = typename Kind::Command;
  using Clock = typename InputQueue<Command>::Clock;

  // The kind is made from the arguments; the queue runs at its time scale.
  template <class... A>
  explicit CaptureLoop(A&&... kindArgs) : kind_(std::forward<A>(kindArgs)...), inputs_(kind_.timeScale()) {}
  CaptureLoop(const CaptureLoop&) = delete;
  CaptureLoop& operator=(const CaptureLoop&) = delete;
  ~CaptureLoop() = default;

  // The inputs, from any thread.
  void post(const devices::DeviceEvent& e) { inputs_.post(e); }
  // A foot pedal (the station's Accept key) held down is the stylus button: stylus samples
  // posted while it is down are taken as pressed.
  void setPedal(bool down) { inputs_.setPedal(down); }
  [[nodiscard]] bool pedal() const { return inputs_.pedal(); }
  void postStatus(const devices::DeviceStatus& s) { inputs_.postStatus(s); }
  void command(const Command& c) { inputs_.command(c); }
  void stop() { inputs_.stop(); }  // run() returns soon after
  // What the devices deliver into (device_set.hpp's DeviceSet): their records posted here,
  // their changes of state queued (each change kept in the session's log) and told to
  // `onStatus` on the drivers' threads.
  [[nodiscard]] devices::Driver::Callbacks sinks(std::function<void(const devices::DeviceStatus&)> onStatus = {}) {
    return inputs_.sinks(std::move(onStatus));
  }
  // The latest stylus sample posted (a front end's cursor polls it at its own frame rate).
  [[nodiscard]] std::optional<devices::StylusSample> latestStylus() const { return inputs_.latestStylus(); }
  // How many commands run() has dealt with (each after the kind told it): a caller that sent n
  // knows its last one is answered, or ignored, once this reaches n. Likewise the stylus
  // button's releases (a press is decided at its release). From any thread.
  [[nodiscard]] std::uint64_t commandsTaken() const { return commandsTaken_; }
  [[nodiscard]] std::uint64_t releasesTaken() const { return releasesTaken_; }
  // The engines' clock (device time × the time scale).
  [[nodiscard]] std::int64_t monoNs(typename Clock::time_point t) const { return inputs_.monoNs(t); }

  // Runs until the session ends (complete or abandoned), a quit command, or stop().
  typename Kind::Result run(typename Kind::Listen listen = {});
  [[nodiscard]] decltype(auto) session() { return kind_.session(); }
  [[nodiscard]] Kind& kind() { return kind_; }

 private:
  using Input = typename InputQueue<Command>::Input;
  bool take(const Input& in);  // false: quit

  Kind kind_;
  InputQueue<Command> inputs_;
  std::atomic<std::uint64_t> commandsTaken_{0}, releasesTaken_{0};
  bool buttonDown_ = false;  // the last stylus sample's button (run's thread)
};

// The loop's body: a kind's source instantiates it once (`template class CaptureLoop<LiveLeaf>;`)
// and its header says `extern template` so that no includer compiles it again.
template <LoopKind Kind>
bool CaptureLoop<Kind>::take(const Input& in) {
  if (const auto* c = std::get_if<Command>(&in)) {
    if (!kind_.command(*c, inputs_.now())) return false;
    ++commandsTaken_;  // counted once told: a virtual technician waits for it before it acts again
    return true;
  }
  if (const auto* st = std::get_if<devices::DeviceStatus>(&in)) {
    if (const auto state = inputs_.changedState(*st))
      kind_.device(st->device, *state, detail::statusMessage(*st), inputs_.now());
    return true;
  }
  const auto& e = std::get<devices::DeviceEvent>(in);
  if (const auto* s = std::get_if<devices::StylusSample>(&e)) {
    const bool released = buttonDown_ && !s->button;  // the stylus button came up in this sample
    buttonDown_ = s->button;
    kind_.stylus(inputs_.stylusInput(*s));
    releasesTaken_ += released;
  } else if (const auto* r = std::get_if<devices::CaliperReading>(&e)) {
    kind_.caliper(inputs_.caliperInput(*r));
  }
  return true;
}

template <LoopKind Kind>
typename Kind::Result CaptureLoop<Kind>::run(typename Kind::Listen listen) {
  kind_.begin(std::move(listen));
  bool quit = false;
  auto lastRetry = Clock::now();
  while (!quit && !inputs_.stopped() && !kind_.ended()) {
    // The store refused a write (disk full, locked): try again every second; capture goes on
    // by itself once space is back.
    if (kind_.storeBlocked() && Clock::now() - lastRetry >= std::chrono::seconds(1)) {
      lastRetry = Clock::now();
      kind_.retryStore(monoNs(lastRetry));
    }
    for (const Input& in : inputs_.take(std::chrono::milliseconds(100))) {
      quit = !take(in);
      if (quit || kind_.ended()) break;
    }
  }
  return kind_.finish();
}

}  // namespace leafdig::acquisition
