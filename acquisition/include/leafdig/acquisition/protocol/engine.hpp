// The marker-protocol engine (docs/method.md §1): a state machine fed with timestamped stylus samples,
// caliper readings and operator commands. It decides (accept / reject with a reason in the
// operator's words) and applies decisions; replaying the applied decisions of a stored
// session rebuilds its state exactly (crash recovery and review share that path).
//
// Thread contract: one thread owns an Engine (the capture thread); it never blocks.
#pragma once

#include <array>
#include <cstdint>
#include <deque>
#include <optional>
#include <string>
#include <vector>

#include "leafdig/acquisition/protocol/items.hpp"

namespace leafdig::acquisition {

class Engine {
 public:
  explicit Engine(Settings settings = {});

  // Inputs. A point is decided when the stylus button is released: the mean of the still
  // samples before the press; a long press ends the rows instead, a very long press
  // (undoPressNs) undoes the last action: a leaf needs no keyboard.
  Decision onStylus(const StylusInput& s);
  Decision onCaliper(const CaliperInput& c);
  // Commands; like the inputs, they decide and apply (the returned decision is what to store).
  Decision undo();     // the last accepted item (or the end of rows)
  Decision endRows();  // the key equivalent of the long press
  // Takes a chosen item out and makes it the next step; the next accepted input replaces it.
  // undo() before that puts the old item back.
  Decision retake(What what, int row, int col);
  // Moving the transmitter (docs/devices.md, "Moving the transmitter"): the three board points
  // are the landmarks. Starts relocation r (1, 2, …): the board points are taken again from the
  // new position, then a long press (or endRows()) fits the move — refused, naming the board
  // point, when they do not agree. From then on every sample is taken into the first
  // position's frame. Refused in words without a board frame, before it is taken, during a
  // retake or another move, or once the leaf is complete. undo() takes back a board point
  // again, the fit, or the move.
  Decision moveTransmitter();

  // Applies a decision (what onStylus/onCaliper/undo/endRows did, or one read back from
  // the store). Rejected and Ignored decisions change nothing.
  void apply(const Decision& d);

  [[nodiscard]] Step step() const;
  [[nodiscard]] std::string prompt() const;
  // The protocol's steps in the order they are asked for, as far as they are known: the
  // board and the tip, every row begun plus the open row (while rows are still being
  // taken), the thickness steps of the complete rows (sequential order: once the rows are
  // ended), the margin reading (once the rows are ended). A step being retaken is Current.
  [[nodiscard]] std::vector<PlannedStep> plan() const;
  [[nodiscard]] const std::vector<Item>& items() const { return items_; }
  [[nodiscard]] int completeRows() const;
  [[nodiscard]] bool rowsEnded() const { return rowsEnded_; }
  [[nodiscard]] bool complete() const { return step().what == What::Done; }
  [[nodiscard]] bool retaking() const { return retake_.has_value(); }
  [[nodiscard]] int relocating() const { return relocating_; }  // the move in progress, 0 none
  // Transmitter positions so far (1 + the fitted moves) and the fit of move r (1…).
  [[nodiscard]] int transmitterPositions() const { return static_cast<int>(toFirst_.size()); }
  // Position p's frame → the first's: row-major rotation, then translation (p = 0: the identity).
  [[nodiscard]] const std::array<double, 12>& positionToFirst(int p) const {
    return toFirst_.at(static_cast<std::size_t>(p));
  }
  [[nodiscard]] Decision fitOf(int relocation) const;  // RelocationFitted with its numbers, or Rejected
  [[nodiscard]] const Settings& settings() const { return settings_; }
  // Inside a plant: the plant's transmitter position the samples come from (the plant maps them
  // into its first position's frame itself), stamped on each stylus item as its frame.
  void setPlantPosition(int p) { plantPosition_ = p; }

 private:
  [[nodiscard]] Decision decidePoint(const StylusInput& release);
  [[nodiscard]] Decision decideEndRows() const;
  [[nodiscard]] Vec3 toFirst(const Vec3& p) const;  // the current position's frame → the first's
  [[nodiscard]] Decision reject(std::string reason) const;
  [[nodiscard]] const Item* find(What w, int row, int col) const;
  [[nodiscard]] int markersInRow(int row) const;
  [[nodiscard]] std::vector<Step> thicknessSteps(int row) const;

  void erase(std::size_t index);

  Settings settings_;
  std::vector<Item> items_;
  std::optional<Step> retake_;
  Item retakeOld_;
  // Applied actions in order: index into items_, or kRowsEnded, kMoveStarted, kMoveFitted.
  std::vector<int> actions_;
  static constexpr int kRowsEnded = -1, kMoveStarted = -2, kMoveFitted = -3;
  bool rowsEnded_ = false;
  int relocating_ = 0;
  // Each transmitter position's frame → the first's, row-major rotation then translation
  // ([0]: the identity); Eigen stays in engine.cpp.
  std::vector<std::array<double, 12>> toFirst_{{1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0}};
  StylusPress press_;
  std::int64_t lastAcceptedReleaseNs_ = -1;
  std::int64_t lastReadingAt_ = -1;
  double lastReading_ = -1;
  int plantPosition_ = 0;
};

// Move `relocation`'s fit from a leaf's items (its board points as first taken and taken
// again): its map into the first position's frame (positionToFirst's layout), or the refusal in
// words. A curator's correction of a board point refits every move from the items as they are.
struct BoardMoveFit {
  std::array<double, 12> toFirst{};
  std::optional<std::string> refusal;
};
[[nodiscard]] BoardMoveFit fitBoardMove(const std::vector<Item>& items, int relocation, double toleranceMm);

}  // namespace leafdig::acquisition
