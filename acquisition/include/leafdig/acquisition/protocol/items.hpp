// The leaf protocol's vocabulary (docs/method.md §1): its settings, the items it takes, the steps
// it asks for, the decisions it makes, the stylus and caliper inputs it is fed, and the stylus
// press as an engine follows it. The engine (engine.hpp) and the point rules (point_rules.hpp)
// both speak it; the plant's engine reuses it for its leaves.
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

}  // namespace leafdig::acquisition
