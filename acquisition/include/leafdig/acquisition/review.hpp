// What curators and modellers do with a stored session: open it (any status) through the
// same replay as capture, step through it event by event, correct an item with a reason (a
// `corrected` event, replayed like any other), approve or reject it, and export it. The CLI
// (`leafdig sessions …`) and the station's review view both sit on these functions.
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

#include "leafdig/acquisition/plant_engine.hpp"
#include "leafdig/acquisition/session.hpp"
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
  // A plant session's item (plant_session.hpp's PlantCorrection): the plant's own (`plantWhat`,
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
// correctPlantSession (plant_session.hpp).
std::int64_t correct(db::EventStore& store, std::int64_t id, const Correction& c);

// approve: only complete sessions; reject: complete ones, with a reason. Checks the chain
// first. Returns the status event's seq.
std::int64_t review(db::EventStore& store, std::int64_t id, const std::string& status, const std::string& who,
                    const std::string& why);

// Throws SessionError naming the first event that does not replay when `events` are taken as
// the whole of session `info` (a leaf's or a plant's replay). `leafdig sync pull` and the
// station's sync pass it as db::SyncOptions::replays, so a pull never leaves the station's
// own file holding a session it cannot read.
void requireReplays(const db::SessionInfo& info, const std::vector<db::Event>& events);

struct ExportRequest {
  std::vector<std::string> formats;   // glb obj ply stl model markers csv; empty: all
  std::string frame = "leaf";         // or "digitizer"
  std::string resolution = "export";  // a MeshResolution preset (mesh "uniform")
  std::string mesh = "uniform";       // or "adaptive" (maxErrorMm), "seed" (seed parameters)
  double maxErrorMm = 0.1;
  model::SeedMeshParameters seed;
  std::string blade = "interp";  // approx, bezier, nurbs
  std::string outDir;
  // A plant session's full leaf, alone: the leaf digitized at this node (files
  // session-N.node-K.*, in the digitizer's or the leaf's frame, the CSV of that leaf's items).
  std::optional<int> node;
};
struct ExportResult {
  std::vector<std::string> written;  // files, in the order written
  model::LeafMetrics metrics;
  std::size_t rows = 0;
};
// Checks the chain and the tables against the events (a session that fails verify is not
// exported: SessionError), writes each file atomically and records it in `exports`. Throws std::invalid_argument
// (unknown format, no directory) and model::InputError (the capture is not a whole leaf).
ExportResult exportSession(db::EventStore& store, std::int64_t id, const ExportRequest& request);
// The format names exportSession knows, in order.
[[nodiscard]] const std::vector<std::string>& exportFormats();

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
