// A leaf's capture on the capture loop (capture_loop.hpp): the leaf's commands in words, and
// LiveLeaf, the loop's kind for a leaf — it feeds a CaptureSession, hands every committed
// feedback and a fresh snapshot to the front end, and keeps the live preview.
//
// Thread contract (the loop's): onFeedback runs on the loop's thread; onSnapshot on it or, with
// PreviewDetail::Meshes, on the preview worker — never two at once, versions never going back.
// Neither may block for long.
#pragma once

#include <condition_variable>
#include <functional>
#include <istream>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "leafdig/acquisition/live/capture_loop.hpp"
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

// The loop's kind for a leaf (a LoopKind): run() returns the last snapshot, with the preview of
// its own version (the worker finishes it first).
class LiveLeaf {
 public:
  using Command = acquisition::Command;
  using Result = Snapshot;
  struct Listen {};  // the listeners come with the session, below
  // timeScale > 1 runs a simulated capture faster: the engine sees device time × timeScale.
  LiveLeaf(CaptureSession& session, LoopListener listener, double timeScale = 1.0,
           PreviewDetail preview = PreviewDetail::Meshes, PreviewBuilder builder = {});
  ~LiveLeaf();
  LiveLeaf(const LiveLeaf&) = delete;
  LiveLeaf& operator=(const LiveLeaf&) = delete;

  [[nodiscard]] double timeScale() const { return timeScale_; }
  void begin(Listen);
  void stylus(const StylusInput& s) { deliver(session_.onStylus(s)); }
  void caliper(const CaliperInput& c) { deliver(session_.onCaliper(c)); }
  bool command(const Command& c, std::int64_t now);
  void device(const std::string& device, const std::string& state, const std::string& message, std::int64_t now) {
    deliver(session_.deviceStatus(device, state, message, now));
  }
  void retryStore(std::int64_t now) { deliver(session_.resume(now)); }
  [[nodiscard]] bool storeBlocked() const { return session_.storeBlocked(); }
  [[nodiscard]] bool ended() const { return session_.ended(); }
  Snapshot finish();
  [[nodiscard]] CaptureSession& session() { return session_; }

 private:
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
  double timeScale_;
  PreviewDetail preview_;
  PreviewBuilder builder_;
  // The preview worker (PreviewDetail::Meshes).
  std::mutex publishMutex_;  // one onSnapshot at a time; guards latest_
  Snapshot latest_;          // the last snapshot delivered
  std::mutex jobMutex_;
  std::condition_variable jobCv_;
  std::optional<PreviewJob> job_;  // the newest request; an older one not yet started is dropped
  bool workerStop_ = false;
  std::thread worker_;
};

extern template class CaptureLoop<LiveLeaf>;
using LeafCaptureLoop = CaptureLoop<LiveLeaf>;

}  // namespace leafdig::acquisition
