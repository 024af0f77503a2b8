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

#include "leafdig/devices/sample.hpp"
#include "leafdig/model/leaf/thickness_mode.hpp"
#include "leafdig/names/name_table.hpp"

namespace leafdig::acquisition {

// A point in millimetres: the one Vec3 of leafdig, the devices' (std::array<double, 3>).
using devices::Vec3;

// docs/method.md §1: seven markers a row, from the right margin (1) over the midrib (4) to the left
// margin (7). Equal to model::kMarkersPerRow (checked in engine.cpp).
inline constexpr int kMarkersPerRow = 7;

// The thickness mode is the model's (one enum from the capture to the model file).
using Mode = model::ThicknessMode;
enum class Order { Sequential, Interleaved };
// Its words in files, options and messages (the CLI's choices and the station's lists too).
inline constexpr NameTable<Order, 2> kOrderNames{
    {{Order::Sequential, "sequential"}, {Order::Interleaved, "interleaved"}}};

[[nodiscard]] const char* toString(Order o);
[[nodiscard]] Order orderFromString(const std::string& s);  // throws UnknownName

struct Settings {
  Mode mode = Mode::Standard;
  Order order = Order::Sequential;
  double doubleTapMm = 2.0;                  // closer to the previous point…
  std::int64_t doubleTapNs = 500'000'000;    // …and pressed this soon after it: a double tap
  double stillToleranceMm = 1.5;             // samples around a press within this of their mean
  std::int64_t stillWindowNs = 250'000'000;  // …taken over this long before the press
  std::int64_t longPressNs = 1'200'000'000;  // a press this long ends the rows
  double minThicknessMm = 0.02, maxThicknessMm = 20.0;
  std::int64_t repeatWindowNs = 2'000'000'000;  // same reading again this soon: flagged
  double spacingTolerance = 0.6;                // neighbours within ±60 % of the row's spacing
  double midribToleranceMm = 15.0;              // 4th point off the midrib's local line by more: rejected
  int minRows = 2;                              // rows before the end-of-rows gesture counts
  std::int64_t undoPressNs = 3'000'000'000;     // a press this long undoes the last action
  bool boardFrame = false;                      // start with 3 board points: origin, +X, +Y
  double boardMinMm = 20.0;                     // board points at least this far apart / off the X axis
  double relocationToleranceMm = 1.5;           // a move's fit of the board points: RMS above this is refused
};

// BoardAgain: a board point taken again after moving the transmitter (row: the relocation,
// col: the board point; its position in the moved transmitter's frame).
enum class What {
  Board,
  Tip,
  Marker,
  MidribThickness,
  VeinOriginThickness,
  EdgeThickness,
  PointThickness,
  BoardAgain,
  Done
};
[[nodiscard]] const char* toString(What w);               // "board", "tip", "marker", "midrib_thickness", …
[[nodiscard]] What whatFromString(const std::string& s);  // throws UnknownName
[[nodiscard]] bool isStylusItem(What w);                  // board, tip, marker, board_again

struct Step {
  What what = What::Tip;
  int row = 0, col = 0;  // 1-based as in docs/method.md §1; 0 where it does not apply
  friend bool operator==(const Step&, const Step&) = default;
};

// One step of the protocol as a front end lists it: captured, the current one, or to come.
struct PlannedStep {
  enum class State { Done, Current, Pending };
  Step step;
  State state = State::Pending;
};

struct Item {
  What what = What::Tip;
  int row = 0, col = 0;
  Vec3 positionMm{};   // stylus items
  double valueMm = 0;  // caliper items (thickness)
  std::string raw;
  std::string flag;  // e.g. "repeated reading"; empty when clean
  int frame = 0;     // stylus items: the transmitter position it was pressed from (0: the first)
};

// Helpers on a list of items (the engine's, or a snapshot's).
[[nodiscard]] const Item* findItem(const std::vector<Item>& items, What what, int row, int col);
[[nodiscard]] int completeRows(const std::vector<Item>& items);  // rows 1..k holding all 7 markers
[[nodiscard]] double distanceMm(const Vec3& a, const Vec3& b);

struct Decision {
  enum class Kind {
    Ignored,
    Accepted,
    Rejected,
    Undone,
    RowsEnded,
    RowsReopened,
    RetakeStarted,
    RetakeCancelled,
    RelocationStarted,    // the transmitter is moved: relocation `relocation` begins, board points again
    RelocationFitted,     // its fit (fit*): later samples go into the first position's frame
    RelocationReopened,   // the fit undone: the board points again are asked for once more
    RelocationCancelled,  // the move undone before any board point was taken again
  };
  Kind kind = Kind::Ignored;
  Item item;           // Accepted / Undone / the item a retake replaces (RetakeStarted, RetakeCancelled)
  std::string reason;  // Rejected: what was wrong and what to do
  int relocation = 0;  // Relocation*: its number (1, 2, …)
  double fitRmsMm = 0, fitWorstMm = 0;  // RelocationFitted: the board points' residual…
  int fitWorstPoint = 0;                // …and the board point farthest off (1–3)
};

struct StylusInput {
  std::int64_t tNs = 0;  // monotonic
  Vec3 positionMm{};
  bool button = false;
  std::string status = "ok";
  std::string raw;
  // The first sample after the digitizer (re)connected: nothing before it is continuous with
  // it, and a press under way was cut (StylusSample::streamBegins).
  bool streamBegins = false;
};
struct CaliperInput {
  std::int64_t tNs = 0;
  double valueMm = 0;
  std::string raw;
};

// How a press ended: held this long — or cut, when the digitizer's stream began again while the
// button was down (a reset, an unplug): its length spans the outage and says nothing.
struct PressEnd {
  std::int64_t heldNs = 0;
  bool cut = false;
};
// The words a cut press is refused with (leaf and plant alike).
[[nodiscard]] std::string cutPressWords(std::int64_t heldNs);

// The stylus between samples as an engine follows it (the leaf's and the plant's): the recent
// samples and the button.
class StylusPress {
 public:
  // Takes a sample; when it releases the button (or the stream begins again under a press),
  // how the press ended.
  std::optional<PressEnd> take(const StylusInput& s, const Settings& settings);
  // The samples a press ending at releaseNs settles from: from stillWindow before the press
  // to the release.
  [[nodiscard]] std::vector<const StylusInput*> window(std::int64_t releaseNs, const Settings& settings) const;
  [[nodiscard]] std::int64_t pressedAt() const { return pressedAt_; }

 private:
  std::deque<StylusInput> recent_;
  bool pressed_ = false;
  std::int64_t pressedAt_ = 0;
};

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
