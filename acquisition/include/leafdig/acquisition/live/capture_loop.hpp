// The capture thread of docs/architecture.md: device events and operator commands arrive on a
// queue from any thread; one thread (the caller of run()) feeds them to the session in
// order, and hands every committed feedback and a fresh snapshot to the front end.
//
// Thread contract: post*() and command() from any thread; run() on the thread that owns the
// session. onFeedback runs on that thread; onSnapshot on it or, with PreviewDetail::Meshes, on
// the preview worker — never two at once, versions never going back. Neither may block for
// long.
#pragma once

#include <condition_variable>
#include <functional>
#include <istream>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include "leafdig/acquisition/live/input_queue.hpp"
#include "leafdig/acquisition/session/session.hpp"

namespace leafdig::acquisition {

struct Command {
  enum class Kind { Undo, EndRows, Retake, MoveTransmitter, Pause, Resume, Abandon, Quit };
  Kind kind = Kind::Undo;
  What what = What::Marker;  // Retake
  int row = 0, col = 0;      // Retake
  std::string text;          // Pause reason, Abandon reason
};
// "undo", "end", "retake marker 3 5", "retake tip", "retake midrib_thickness 2", "move
// [transmitter]", "pause", "resume", "abandon [why]", "quit". Throws std::invalid_argument naming the accepted words.
[[nodiscard]] Command parseCommand(const std::string& line);
// What may follow "move" (a leaf's or a plant's command): nothing, or "transmitter";
// std::invalid_argument naming anything else.
void readMoveWords(std::istream& in);
// A leaf's item in words, read from `in` ("marker 3 5", "tip", "midrib_thickness 2", "board 2")
// as a Step (a midrib or vein-origin reading at point 4); `command` names the command in the
// words of what is wrong (std::invalid_argument).
[[nodiscard]] Step parseLeafItemWords(std::istream& in, const std::string& command);

struct LoopListener {
  std::function<void(const Feedback&)> onFeedback;  // after the event is committed
  std::function<void(const Snapshot&)> onSnapshot;  // after every committed change
};

// What the snapshots carry of the live preview.
enum class PreviewDetail {
  None,   // nothing (scripts, the demo)
  Model,  // the preview's model without meshes, built on the capture thread (a terminal)
  // The model and its meshes (a view draws them), built on a preview worker that keeps only
  // the newest request: the capture thread never waits for a mesh, and every snapshot carries
  // the newest preview built so far (Snapshot::previewVersion; the worker catches up).
  Meshes,
};

// How the worker builds a preview (buildPreview with meshes unless a test says otherwise).
using PreviewBuilder = std::function<Preview(const std::vector<Item>& items, const Settings& settings)>;

class CaptureLoop {
 public:
  using Clock = InputQueue<Command>::Clock;
  // timeScale > 1 runs a simulated capture faster: the engine sees device time x timeScale.
  CaptureLoop(CaptureSession& session, LoopListener listener, double timeScale = 1.0,
              PreviewDetail preview = PreviewDetail::Meshes, PreviewBuilder builder = {});
  ~CaptureLoop();
  CaptureLoop(const CaptureLoop&) = delete;
  CaptureLoop& operator=(const CaptureLoop&) = delete;

  // The inputs (input_queue.hpp, shared with the plant's loop), from any thread.
  void post(const devices::DeviceEvent& e) { inputs_.post(e); }
  // A foot pedal (or key) held down acts as the stylus button: stylus samples posted while
  // it is down carry button = true. Any thread.
  void setPedal(bool down) { inputs_.setPedal(down); }
  [[nodiscard]] bool pedal() const { return inputs_.pedal(); }
  void postStatus(const devices::DeviceStatus& s) { inputs_.postStatus(s); }
  void command(const Command& c) { inputs_.command(c); }
  void stop() { inputs_.stop(); }  // run() returns soon after
  // What the devices deliver into (device_set.hpp's DeviceSet).
  [[nodiscard]] devices::Driver::Callbacks sinks() { return inputs_.sinks(); }

  // Runs until the session is complete or abandoned, a Quit command, or stop(). Returns the
  // last snapshot, with the preview of its own version (the worker finishes it first).
  Snapshot run();

  [[nodiscard]] std::int64_t monoNs(Clock::time_point t) const { return inputs_.monoNs(t); }
  // The latest stylus sample posted (any thread; a front end's cursor polls it at its own
  // frame rate instead of receiving every sample).
  [[nodiscard]] std::optional<devices::StylusSample> latestStylus() const { return inputs_.latestStylus(); }

 private:
  using Item_ = InputQueue<Command>::Input;
  void handle(const Item_& item, bool& quit);
  void deliver(const std::vector<Feedback>& feedback);
  void publish();        // a snapshot of the session to the listener (and a preview request)
  void buildPreviews();  // the preview worker
  void stopWorker();     // finishes the newest request, then joins

  struct PreviewJob {
    std::uint64_t version = 0;
    std::vector<Item> items;
    Settings settings;
  };

  CaptureSession& session_;
  LoopListener listener_;
  PreviewDetail preview_;
  PreviewBuilder builder_;
  InputQueue<Command> inputs_;
  // The preview worker (PreviewDetail::Meshes).
  std::mutex publishMutex_;  // one onSnapshot at a time; guards latest_
  Snapshot latest_;          // the last snapshot delivered
  std::mutex jobMutex_;
  std::condition_variable jobCv_;
  std::optional<PreviewJob> job_;  // the newest request; an older one not yet started is dropped
  bool workerStop_ = false;
  std::thread worker_;
};

}  // namespace leafdig::acquisition
