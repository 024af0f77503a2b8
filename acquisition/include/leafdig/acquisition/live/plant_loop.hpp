// A plant's capture on the capture loop (capture_loop.hpp; docs/plants.md, "Real devices"):
// the plant's commands in words, and LivePlant, the loop's kind for a plant — it feeds a
// PlantCaptureSession and hands every committed decision to the front end. The same loop takes
// real devices (a DeviceSet on the operator's ports) and the simulated rig with its virtual
// technician (plant_simulation.hpp), so the simulated plant capture is the real one on
// pseudo-terminals.
//
// Thread contract (the loop's): the listeners run on the loop's thread.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <utility>

#include "leafdig/acquisition/live/capture_loop.hpp"
#include "leafdig/acquisition/session/plant_session.hpp"

namespace leafdig::acquisition {

struct PlantCommand {
  enum class Kind { Undo, End, Choose, Pause, Resume, Quit, Retake, Branch, MoveTransmitter };
  Kind kind = Kind::Undo;
  int node = 0;  // Choose; Retake: a full leaf's node (0: the plant's own item); Branch: from (0: the stem's last)
  LeafChoice choice{};                   // Choose
  std::string text{};                    // Pause: the reason
  PlantWhat what = PlantWhat::Landmark;  // Retake of the plant's own item: which, and its number
  int index = 0, part = 0;
  Step leaf{};  // Retake of a full leaf's item (node > 0)
};
// "undo", "end" (ends the landmarks, a full leaf's rows or the plant, as the long press),
// "leaf N full|quick|none [alive|dead|broken|yellow|pruned] [TYPE]" (node N's leaf),
// "pause [reason…]", "resume", "quit", "retake WHAT [N [PART]]" (landmark N, collar,
// collar_diameter, point N [PART], reading N [PART], quick_point N PART) and "retake node N
// WHAT [ROW [POINT]]" (node N's full leaf's item, as a leaf's retake), "branch [N]" (the next
// node starts a branch from main-stem node N, by default the stem's last; "end" at a branch
// node's first point ends the branch), "move" (the transmitter is being moved: the landmarks
// are taken again, then "end" fits).
// Throws std::invalid_argument naming the accepted words.
[[nodiscard]] PlantCommand parsePlantCommand(const std::string& line);

struct PlantRunStats {
  int accepted = 0, rejected = 0, gestures = 0, readings = 0, choices = 0;
};

// The loop's kind for a plant (a LoopKind): opens plant session `id` (SessionError when it is not
// an open plant session). run() is given the listeners: after every committed decision (or
// refusal) onFeedback, then onChange (what a technician reads next; also once as run() starts);
// it returns the tally.
class LivePlant {
 public:
  using Command = PlantCommand;
  using Result = PlantRunStats;
  struct Listen {
    using OnFeedback = std::function<void(const PlantFeedback&, const PlantCaptureSession&)>;
    using OnChange = std::function<void(const PlantCaptureSession&)>;
    Listen(OnFeedback feedback = {}, OnChange change = {})  // NOLINT(google-explicit-constructor): run({…})
        : onFeedback(std::move(feedback)), onChange(std::move(change)) {}
    OnFeedback onFeedback;
    OnChange onChange;
  };
  // timeScale > 1 runs a simulated capture faster: the engine sees device time × timeScale.
  LivePlant(db::Store& store, std::int64_t id, double timeScale = 1.0) : session_(store, id), timeScale_(timeScale) {}

  [[nodiscard]] double timeScale() const { return timeScale_; }
  void begin(Listen listen);
  void stylus(const StylusInput& s) { tell(session_.onStylus(s)); }
  void caliper(const CaliperInput& c) { tell(session_.onCaliper(c)); }
  bool command(const PlantCommand& c, std::int64_t now);
  // A device's change of state is kept in the session's log (a `device` event per change, as a
  // leaf capture keeps them); the technician hears of it only when the store refused it.
  void device(const std::string& device, const std::string& state, const std::string& message, std::int64_t now);
  // A plant session reports a refused write and stays as the store has it: nothing to retry.
  void retryStore(std::int64_t /*now*/) {}
  [[nodiscard]] bool storeBlocked() const { return false; }
  [[nodiscard]] bool ended() const { return session_.ended(); }
  PlantRunStats finish() { return stats_; }
  [[nodiscard]] PlantCaptureSession& session() { return session_; }

 private:
  void tell(const PlantFeedback& f);  // to the listeners, when there is anything to tell

  PlantCaptureSession session_;
  double timeScale_;
  Listen listen_;
  PlantRunStats stats_;
};

extern template class CaptureLoop<LivePlant>;
using PlantCaptureLoop = CaptureLoop<LivePlant>;

}  // namespace leafdig::acquisition
