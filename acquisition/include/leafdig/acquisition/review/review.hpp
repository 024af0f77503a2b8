// What curators and modellers do with a stored session: open it (any status) through the
// same replay as capture, step through it event by event, flag what to look at, approve or
// reject it, summarize it. Corrections are correction.hpp's, exports leaf_export.hpp's and
// plant_export.hpp's. The CLI (`leafdig sessions …`) and the station's review view both sit on
// these functions.
//
// Thread contract: like the Store they take, one thread at a time.
#pragma once

#include <cstdint>
#include <limits>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <tuple>
#include <vector>

#include "leafdig/acquisition/protocol/plant_engine.hpp"
#include "leafdig/acquisition/session/session.hpp"
#include "leafdig/model/mesh/mesh_method.hpp"
#include "leafdig/model/metrics/metrics.hpp"
#include "leafdig/model/plant/plant.hpp"

namespace leafdig::acquisition {

struct ReviewedSession {
  db::SessionInfo info;
  Settings settings;
  Engine engine;                                           // after the events replayed
  std::map<std::tuple<int, int, int>, std::int64_t> seqs;  // event that put each item in
  std::int64_t replayedEvents = 0;                         // how many events the engine has seen
  std::int64_t totalEvents = 0;
};

// Opens a session of any status. upToSeq > 0 replays only events 1..upToSeq (step-by-step
// replay in review). Throws SessionError when it does not exist or does not replay.
[[nodiscard]] ReviewedSession openForReview(const db::EventStore& store, std::int64_t id, std::int64_t upToSeq = 0);
// The same from a leaf session's row and every event it holds, read once by the caller (a
// correction plans and previews against the very events it read). SessionError as above.
[[nodiscard]] ReviewedSession reviewedFrom(db::SessionInfo info, const std::vector<db::Event>& events);

// One finding a curator should look at.
struct ReviewFlag {
  What what = What::Marker;
  int row = 0, col = 0;
  std::string text;  // "repeated reading", "thickness 3.1 mm is 4.2 MAD from the row's median", …
};
// Flags recorded at capture (item flags) plus thickness outliers: a reading further than
// `madLimit` median absolute deviations from the median of its kind (midrib, vein origin,
// point) over the leaf, and midrib readings that grow towards the tip.
[[nodiscard]] std::vector<ReviewFlag> reviewFlags(const std::vector<Item>& items, double madLimit = 3.5);

// approve: only complete sessions; reject: complete ones, with a reason. Checks the chain
// first. Returns the status event's seq.
std::int64_t review(db::EventStore& store, std::int64_t id, const std::string& status, const std::string& who,
                    const std::string& why);
// A curator reopens an approved or rejected session, saying why (a mistaken approval, a leaf
// to measure again): a `status` event back to complete naming the decision it reopens, signed as
// a review is. After it the session is complete again: corrections and a new decision may follow,
// capture events may not; the history keeps the decision and the reopening. Throws
// std::invalid_argument naming what is missing or why the session cannot be reopened, and
// SessionError when its chain is broken. Returns the event's seq.
std::int64_t reopen(db::EventStore& store, std::int64_t id, const std::string& who, const std::string& why);

// Throws SessionError naming the first event that does not replay when `events` are taken as
// the whole of session `info` (a leaf's or a plant's replay). `leafdig sync pull` and the
// station's sync pass it as db::SyncOptions::replays, so a pull never leaves the station's
// own file holding a session it cannot read.
void requireReplays(const db::SessionInfo& info, const std::vector<db::Event>& events);

// A reviewed leaf session's markers, with the session's leaf (plant, position, type, measured
// area): what summarize() builds, `sessions export --format markers` writes and the organ
// library takes.
[[nodiscard]] model::MarkerSet sessionMarkers(const ReviewedSession& r);

// The leaf's metrics and model (for review: area, the area constraint). Throws
// model::InputError when the capture is not a whole leaf.
struct LeafSummary {
  model::LeafModel model;
  model::LeafMetrics metrics;
};
[[nodiscard]] LeafSummary summarize(const ReviewedSession& r);

// What a capture adds to the digitizer's noise in the area interval's draws: a move of the
// transmitter (the points before and after stand in frames related by a fit with a residual: the
// largest move's RMS) and a checked field's correction (its RMS on divots it did not see), each
// added in quadrature. summarize() and the exports apply it.
void widenForCapture(const ReviewedSession& r, const model::LeafModel& leaf, model::LeafMetrics& metrics);
// The field check a session's stylus samples went through, from its settings (none when none).
[[nodiscard]] std::optional<FieldApplied> sessionField(const db::SessionInfo& info);
// The tip calibration its stylus samples went through (field/tip_calibration.hpp; none when none).
[[nodiscard]] std::optional<TipApplied> sessionTip(const db::SessionInfo& info);

// A leaf taken across a move of the transmitter (engine.transmitterPositions() > 1): each
// position, the first included, with how many of the leaf's points were pressed from it and,
// after the first, its fit — [{"position", "points"[, "rms_mm", "worst_mm", "worst_point",
// "refusal"]}, …] as `sessions show` says them; with `withItems`, each position's points too,
// "items": [{"what", "row", "col"}, …] (the leaf's model file).
[[nodiscard]] std::string leafTransmitterPositionsJson(const Engine& engine, bool withItems);

// The organ library of seed 003: every approved session of the store as a leaf (markers
// with its type and position). An approved session that does not replay into a whole leaf
// is left out and named in `skipped`.
struct OrganLibrary {
  std::vector<model::LibraryLeaf> leaves;
  std::vector<std::string> skipped;
};
[[nodiscard]] OrganLibrary organLibrary(const db::EventStore& store);

}  // namespace leafdig::acquisition
