// The capture thread of ARCHITECTURE.md: device events and operator commands arrive on a
// queue from any thread; one thread (the caller of run()) feeds them to the session in
// order, and hands every committed feedback and a fresh snapshot to the front end.
//
// Thread contract: post*() and command() from any thread; run() on the thread that owns the
// session; the listener's callbacks run on that thread and must not block for long.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <deque>
#include <functional>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <variant>

#include "leafdig/acquisition/session.hpp"
#include "leafdig/devices/driver.hpp"

namespace leafdig::acquisition {

struct Command {
  enum class Kind { Undo, EndRows, Retake, Pause, Resume, Abandon, Quit };
  Kind kind = Kind::Undo;
  What what = What::Marker;  // Retake
  int row = 0, col = 0;      // Retake
  std::string text;          // Pause reason, Abandon reason
};
// "undo", "end", "retake marker 3 5", "retake tip", "retake midrib_thickness 2", "pause",
// "resume", "abandon [why]", "quit". Throws std::invalid_argument naming the accepted words.
[[nodiscard]] Command parseCommand(const std::string& line);

struct LoopListener {
  std::function<void(const Feedback&)> onFeedback;  // after the event is committed
  std::function<void(const Snapshot&)> onSnapshot;  // after every committed change
};

class CaptureLoop {
 public:
  using Clock = std::chrono::steady_clock;
  // timeScale > 1 runs a simulated capture faster: the engine sees device time x timeScale.
  // `previews`: snapshots carry the live preview; `previewMeshes`: with its meshes.
  CaptureLoop(CaptureSession& session, LoopListener listener, double timeScale = 1.0, bool previews = true,
              bool previewMeshes = true);

  void post(const devices::DeviceEvent& e);
  // A foot pedal (or key) held down acts as the stylus button: stylus samples posted while
  // it is down carry button = true. Any thread.
  void setPedal(bool down) { pedal_ = down; }
  [[nodiscard]] bool pedal() const { return pedal_; }
  void postStatus(const devices::DeviceStatus& s);
  void command(const Command& c);
  void stop();  // run() returns soon after

  // Runs until the session is complete or abandoned, a Quit command, or stop(). Returns the
  // last snapshot.
  Snapshot run();

  [[nodiscard]] std::int64_t monoNs(Clock::time_point t) const;
  // The latest stylus sample posted (any thread; a front end's cursor polls it at its own
  // frame rate instead of receiving every sample).
  [[nodiscard]] std::optional<devices::StylusSample> latestStylus() const;

 private:
  using Item_ = std::variant<devices::DeviceEvent, devices::DeviceStatus, Command>;
  void handle(const Item_& item, bool& quit);
  void deliver(const std::vector<Feedback>& feedback);

  CaptureSession& session_;
  LoopListener listener_;
  double timeScale_;
  bool previews_;
  bool previewMeshes_;
  Clock::time_point t0_;
  mutable std::mutex mutex_;
  std::condition_variable cv_;
  std::deque<Item_> queue_;
  std::optional<devices::StylusSample> latestStylus_;
  std::atomic<bool> stop_{false};
  std::atomic<bool> pedal_{false};
  std::map<std::string, std::string> deviceStates_;
};

}  // namespace leafdig::acquisition
