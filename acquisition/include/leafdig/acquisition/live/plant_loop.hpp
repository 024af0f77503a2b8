// A plant capture from devices (docs/plants.md, "Real devices"): the digitizer's and the
// caliper's events and the operator's commands arrive on one queue from any thread; one thread
// (the caller of run()) feeds them to a PlantCaptureSession in the order they arrived, and hands
// every committed decision to the front end. The same loop takes real devices (a DeviceSet on
// the operator's ports) and the simulated rig with its virtual technician
// (plant_simulation.hpp), so the simulated plant capture is the real one on pseudo-terminals.
//
// Thread contract: post(), command() and stop() from any thread; run() and session() on the
// thread that owns the session (and its store). The listeners run on that thread.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <string>

#include "leafdig/acquisition/live/input_queue.hpp"
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

class PlantCaptureLoop {
 public:
  using Clock = InputQueue<PlantCommand>::Clock;
  using Listener = std::function<void(const PlantFeedback&, const PlantCaptureSession&)>;
  // Opens plant session `id` (SessionError when it is not an open plant session). timeScale > 1
  // runs a simulated capture faster: the engine sees device time × timeScale.
  PlantCaptureLoop(db::Store& store, std::int64_t id, double timeScale = 1.0);
  PlantCaptureLoop(const PlantCaptureLoop&) = delete;
  PlantCaptureLoop& operator=(const PlantCaptureLoop&) = delete;

  // The inputs (input_queue.hpp, shared with the leaf's loop), from any thread.
  void post(const devices::DeviceEvent& e) { inputs_.post(e); }
  // A foot pedal (the station's Accept key) held down is the stylus button, as in a leaf
  // capture: every stylus sample while it is down is taken as pressed. From any thread.
  void setPedal(bool down) { inputs_.setPedal(down); }
  [[nodiscard]] bool pedal() const { return inputs_.pedal(); }
  void command(const PlantCommand& c) { inputs_.command(c); }
  // The latest stylus sample posted (a front end's cursor polls it).
  [[nodiscard]] std::optional<devices::StylusSample> latestStylus() const { return inputs_.latestStylus(); }
  // How many commands run() has dealt with (each after its onChange): a caller that sent n
  // knows its last one is answered, or ignored, once this reaches n. From any thread.
  [[nodiscard]] std::uint64_t commandsTaken() const { return commandsTaken_; }
  // Likewise the stylus button's releases (a press is decided at its release).
  [[nodiscard]] std::uint64_t releasesTaken() const { return releasesTaken_; }
  void stop() { inputs_.stop(); }

  // Runs until the session ends (complete or abandoned), a Quit command, or stop(). After every
  // committed decision (or refusal): onFeedback, then onChange (what a technician reads next).
  PlantRunStats run(const Listener& onFeedback, const std::function<void(const PlantCaptureSession&)>& onChange = {});
  [[nodiscard]] PlantCaptureSession& session() { return session_; }
  // What the devices deliver into (device_set.hpp's DeviceSet on the operator's ports): their
  // records posted here, their status changes to `onStatus` (on the drivers' threads) and into
  // the session's log (a `device` event per change of state, as a leaf capture keeps them).
  [[nodiscard]] devices::Driver::Callbacks sinks(std::function<void(const devices::DeviceStatus&)> onStatus = {}) {
    return inputs_.sinks(std::move(onStatus));
  }

 private:
  using Input = InputQueue<PlantCommand>::Input;

  PlantCaptureSession session_;
  InputQueue<PlantCommand> inputs_;
  std::atomic<std::uint64_t> commandsTaken_{0}, releasesTaken_{0};
  bool buttonDown_ = false;  // the last stylus sample's button (run's thread)
};

}  // namespace leafdig::acquisition
