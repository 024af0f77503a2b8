// A curator's correction of a complete session, saying why (docs/review.md): a leaf's items, a
// plant's own items and its full leaves' items (a landmark's correction carrying every point of
// its transmitter move with it). Each is a `corrected` event, replayed like any other.
//
// Thread contract: like the Store they take, one thread at a time.
#pragma once

#include <cstdint>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>

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
// and SessionError when the session's chain is broken. A plant session's item goes to
// correctPlantSession (below).
std::int64_t correct(db::EventStore& store, std::int64_t id, const Correction& c);

// A curator's correction of one item of a complete plant session, saying why (review.hpp's
// correct() on a plant session): the plant's own item (`what`; row: the landmark's or node's
// number; col: which part, 0 for the first) or, with `node`, node's full leaf's item (`leafWhat`,
// row and col as a leaf's). Appends a `corrected` event naming the event that put the item in;
// replay puts the corrected item where the old one stood, so every point measured in the plant
// frame follows a corrected landmark. Throws std::invalid_argument naming what is wrong (no
// reason, no such item, a value of the wrong kind or out of range, a correction that leaves no
// plant frame: nothing written) and SessionError when the session is not a plant's or does not
// verify.
struct PlantCorrection {
  int node = 0;
  What leafWhat = What::Marker;
  PlantWhat what = PlantWhat::Landmark;
  int row = 0, col = 0;
  std::optional<Vec3> positionMm;  // stylus items
  std::optional<double> valueMm;   // caliper items
  std::string reason, who;
  double confirmAboveMm = std::numeric_limits<double>::infinity();  // as Correction's (review.hpp)
};
std::int64_t correctPlantSession(db::EventStore& store, std::int64_t id, const PlantCorrection& c);

}  // namespace leafdig::acquisition
