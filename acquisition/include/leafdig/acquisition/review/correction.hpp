// A curator's correction of a complete session, saying why (docs/decisions.md, "Corrections that cannot slip"): a
// leaf's items, a plant's own items and its full leaves' items (a landmark's correction carrying every point of its
// transmitter move with it). Each is a `corrected` event, replayed like any other.
//
// Thread contract: like the Store they take, one thread at a time.
#pragma once

#include <cstdint>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "leafdig/acquisition/protocol/plant_engine.hpp"
#include "leafdig/db/event_store.hpp"

namespace leafdig::acquisition {

// A correction that would move a point further than its limit is refused until the curator
// confirms the move (issue 49): a typo in one coordinate moves a point centimetres, the wrong
// point metres. The CLI and Python use kConfirmMoveAboveMm unless told (--confirm-above,
// --confirm); the words say how far the point would go.
inline constexpr double kConfirmMoveAboveMm = 20.0;
class UnconfirmedMove : public std::invalid_argument {
 public:
  UnconfirmedMove(const std::string& words, double moveMm) : std::invalid_argument(words), moveMm_(moveMm) {}
  [[nodiscard]] double moveMm() const noexcept { return moveMm_; }

 private:
  double moveMm_;
};

// The frame a corrected position is given in. A leaf's points are the digitizer's (its leaf frame
// comes from the board the points themselves make). A plant's can be given in the plant frame, as
// every export, the survey and `sessions show --json`'s `position_plant_mm` give them: the
// position is taken into the digitizer's frame through the plant frame as the session stands
// before the correction (a landmark corrected in the plant frame moves the frame with it after).
enum class PositionFrame { Digitizer, Plant };
[[nodiscard]] const char* toString(PositionFrame f);                        // "digitizer", "plant"
[[nodiscard]] PositionFrame positionFrameFromString(const std::string& s);  // std::invalid_argument naming both

struct Correction {
  What what = What::Marker;
  int row = 0, col = 0;
  std::optional<Vec3> positionMm;  // stylus items
  std::optional<double> valueMm;   // thickness items
  std::string reason, who;
  // A plant session's item (PlantCorrection, below): the plant's own (`plantWhat`,
  // row = landmark or node number, col = part) or, with `node`, that node's full leaf's (`what`).
  std::optional<PlantWhat> plantWhat;
  int node = 0;
  // A point moved further than this (mm, in the frame `sessions show` gives) is refused with
  // UnconfirmedMove; infinity: any move (the curator confirmed it).
  double confirmAboveMm = std::numeric_limits<double>::infinity();
  PositionFrame frame = PositionFrame::Digitizer;  // of positionMm (Plant: plant sessions only)
  // The session's last event when the curator saw the correction's effect (CorrectionEffect::head):
  // the write is refused if anything was added since. None: the last event as correct() reads it.
  std::optional<std::int64_t> seenHead;
};
// The item a curator names in words (the CLI's --what, Python's `what`): a leaf's (tip, marker,
// midrib_thickness, …) or a plant's (landmark, collar, point, reading, …), set in `c`
// (`what` or `plantWhat`). `node` > 0 names a plant's full leaf, whose items are a leaf's.
// Throws std::invalid_argument listing the words there are.
void setCorrectionItem(Correction& c, const std::string& word, int node = 0);
// Appends a `corrected` event (the projection row of the item is replaced in the same
// transaction). Only a complete session is corrected (approved and rejected ones are
// final; open ones are still being captured). Throws std::invalid_argument naming what is
// wrong (no reason, unknown item, value of the wrong kind or outside the settings' range)
// and SessionError when the session's chain is broken.
//
// A plant session's item: the plant's own (`plantWhat`; row: the landmark's or node's number;
// col: which part, 0 for the first) or, with `node`, node's full leaf's item (`what`, row and col
// as a leaf's). Replay puts the corrected item where the old one stood, so every point measured in
// the plant frame follows a corrected landmark; a correction that leaves no plant frame is refused.
//
// The correction is planned against the session's events as read once, and written only if the
// session still ends where it did (or at `seenHead`, the event the curator saw the effect at):
// else db::StoreError(Conflict), "moved on", and nothing written. With `effect`, what it changed
// (as previewCorrection says it) from the same plan.
struct CorrectionEffect;
std::int64_t correct(db::EventStore& store, std::int64_t id, const Correction& c, CorrectionEffect* effect = nullptr);

// What a correction would change, worked out with every check correct() makes and nothing
// written (issue 49: the curator sees the effect before it is written — the CLI's --dry-run, the
// station's question): the corrected point's move and the measures that change, before → after.
// A leaf: its blade and projected areas. A plant: each node's height, each leaf's length and
// area, and the plant's total leaf area. Measures the session cannot make yet are left out.
struct CorrectionEffect {
  struct Change {
    std::string what;  // "blade area_mm2", "node 4 height_mm", "leaf 3 area_mm2", "leaf area total_mm2"
    double before = 0, after = 0;
  };
  std::optional<double> movedMm;  // the corrected point's move (none for a reading)
  std::vector<Change> changes;    // only what changes
  int events = 0;                 // corrections written: the item's, and the points a refitted move places again
  std::int64_t head = 0;          // the session's last event the effect was worked out from (Correction::seenHead)
};
[[nodiscard]] CorrectionEffect previewCorrection(const db::EventStore& store, std::int64_t id, const Correction& c);

}  // namespace leafdig::acquisition
