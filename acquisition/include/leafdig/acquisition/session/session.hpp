// A capture session: the engine's decisions made durable. Every decision is appended to the
// store (with its projection) before the session reports it, so a front end cues "accepted"
// only for what is on disk. Opening an existing session replays its events through the
// engine: crash recovery, `sessions resume` and review share that path.
//
// When the store refuses a write (disk full, I/O error, locked), the decision is dropped,
// the engine is rebuilt from the store and the session pauses with the store's message;
// resume() retries once space is back. Nothing acknowledged is lost; the operator retakes
// the one input that was not acknowledged.
//
// Thread contract: one thread owns a CaptureSession (and its Store). snapshot() values are
// immutable and may be handed to other threads.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <tuple>
#include <vector>

#include "leafdig/acquisition/field/field_applied.hpp"
#include "leafdig/acquisition/field/tip_calibration.hpp"
#include "leafdig/acquisition/protocol/engine.hpp"
#include "leafdig/acquisition/session/preview.hpp"
#include "leafdig/acquisition/session/session_log.hpp"
#include "leafdig/db/store.hpp"

namespace leafdig::acquisition {

struct SessionSetup {
  std::string project, plant;
  int leafPosition = 1;                   // on the stem, from the base
  std::string leafType;                   // free text ("cauline", "lower", …); optional
  std::optional<double> measuredAreaMm2;  // from a leaf area meter; drives the area constraint
  // The leaf's margin for the area interval (model::LeafInfo): declared serration and tooth
  // depth, or what a scan showed; kept in the session's settings ("leaf_margin").
  std::optional<model::Serration> serration;
  std::optional<double> toothDepthMm;
  std::optional<model::MarginFromScan> marginFromScan;
  std::string operatorName = "technician";
  std::string station;  // empty: this machine's host name
  Settings settings;
  std::string digitizer, caliper;  // "fastrak:/dev/ttyUSB0", "sylvac:/dev/ttyUSB1", "hid:0fe7:4001"
  bool simulated = false;
  double timeScale = 1.0;  // simulated captures may run faster than real time
  // Simulated sessions: the leaf the virtual technician digitizes, kept with the session so
  // that a resumed simulation goes on with the same leaf.
  std::optional<model::MarkerSet> simulatedLeaf;
  // The field check whose correction every stylus sample goes through (field_applied.hpp).
  std::optional<FieldApplied> field;
  // The stylus' tip calibration the digitizer applies to every sample (tip_calibration.hpp).
  std::optional<TipApplied> tip;
};
// A field correction applies in the transmitter's frame: not with a reference receiver (whose
// frame the stylus is read in). std::invalid_argument in words, for the leaf's and the plant's
// setups.
void checkFieldWithDigitizer(const std::optional<FieldApplied>& field, const std::string& digitizerSpec);

// The leaf's margin as a session's settings keep it ("leaf_margin": {"serration",
// "tooth_depth_mm", "from_scan": [{"spacing_mm", "outside_mm", "inside_mm"}…]}), absent when
// nothing was said;
// and read back into a leaf's info (unknown words and bad numbers: SessionError).
[[nodiscard]] std::optional<nlohmann::json> leafMarginJson(const SessionSetup& setup);
void readLeafMargin(const std::string& settingsJson, model::LeafInfo& leaf);

// What a front end announces (after it was committed; seq is the event's number).
struct Feedback {
  enum class Kind {
    Accepted,
    Rejected,
    Undone,
    RowsEnded,
    RowsReopened,
    RetakeStarted,
    RetakeCancelled,
    Paused,
    Resumed,
    Complete,
    Abandoned,
    Device,
    Relocation  // a move of the transmitter: text is its step (started, fitted, reopened, cancelled)
  };
  Kind kind = Kind::Rejected;
  std::int64_t seq = 0;        // 0 only for a pause caused by the store (nothing was written)
  std::int64_t undoneSeq = 0;  // Undone / RetakeStarted: the event whose item is taken out
  Item item;
  std::string text;    // reason, pause message, device message, a move's step
  int relocation = 0;  // Relocation: the move's number, and when fitted its board points' residual
  double fitRmsMm = 0, fitWorstMm = 0;
  int fitWorstPoint = 0;
};
[[nodiscard]] const char* toString(Feedback::Kind k);  // "accepted", "rejected", "undone", …

struct Snapshot {
  std::int64_t session = 0;
  std::uint64_t version = 0;  // grows with every committed change
  Step step;
  std::string prompt;
  std::vector<PlannedStep> plan;  // Engine::plan()
  std::vector<Item> items;
  int completeRows = 0;
  bool rowsEnded = false, complete = false, retaking = false, paused = false;
  std::string pauseReason;
  std::string status;                      // the session's status in the store
  std::shared_ptr<const Preview> preview;  // null when not requested (or not built yet)
  std::uint64_t previewVersion = 0;        // the version `preview` was built for (≤ version)
};

class CaptureSession {
 public:
  // Creates the project/plant/leaf/operator/devices as needed and a new open session.
  static std::int64_t create(db::Store& store, const SessionSetup& setup);

  // Opens a stored session and replays it. Throws SessionError when it is not open
  // (complete, approved, rejected, abandoned) or its events do not replay.
  CaptureSession(db::Store& store, std::int64_t id);

  std::vector<Feedback> onStylus(const StylusInput& s);
  std::vector<Feedback> onCaliper(const CaliperInput& c);
  std::vector<Feedback> undo(std::int64_t monoNs = 0);
  std::vector<Feedback> endRows(std::int64_t monoNs = 0);
  std::vector<Feedback> retake(What what, int row, int col, std::int64_t monoNs = 0);
  // Engine::moveTransmitter; refused in words (a `rejected` event) for a capture through a
  // checked field (FieldApplied::moveRefusal).
  std::vector<Feedback> moveTransmitter(std::int64_t monoNs = 0);
  std::vector<Feedback> pause(const std::string& reason, std::int64_t monoNs = 0);
  // Resumes after pause() or a store failure; the store failure's message again if the
  // store still refuses.
  std::vector<Feedback> resume(std::int64_t monoNs = 0);
  std::vector<Feedback> abandon(const std::string& why, std::int64_t monoNs = 0);
  // A device changed state (connected, lost, warning): recorded, shown to the operator.
  std::vector<Feedback> deviceStatus(const std::string& device, const std::string& state, const std::string& message,
                                     std::int64_t monoNs = 0);

  // `withMeshes` false: the preview's model without its meshes (buildPreview).
  [[nodiscard]] Snapshot snapshot(bool withPreview = true, bool withMeshes = true) const;
  [[nodiscard]] std::int64_t id() const { return log_.id(); }
  [[nodiscard]] const Engine& engine() const { return engine_; }
  [[nodiscard]] bool paused() const { return paused_; }
  // Paused because the store refused a write (not by the operator): retry resume() now and then.
  [[nodiscard]] bool storeBlocked() const { return storeBlocked_; }
  [[nodiscard]] bool ended() const { return ended_; }
  [[nodiscard]] const SessionSetup& setup() const { return setup_; }
  // The seq of the event that accepted each current item, keyed by (what, row, col).
  [[nodiscard]] std::int64_t seqOf(const Item& item) const;

  // Rebuilds an engine from stored events (no store access; also used by review tools).
  // Throws SessionError naming the event that does not fit.
  static Engine replay(const Settings& settings, const std::vector<db::Event>& events,
                       std::map<std::tuple<int, int, int>, std::int64_t>* seqs = nullptr);
  static Settings settingsFromJson(const std::string& json);
  static std::string settingsToJson(const Settings& settings);

 private:
  std::vector<Feedback> commit(const Decision& d, std::int64_t monoNs, const std::string& raw);
  std::optional<std::int64_t> append(const db::EventInput& ev, std::vector<Feedback>& out);
  // A status change as an event; ends the session when written.
  std::optional<std::int64_t> appendStatus(const std::string& status, const std::string& why, std::int64_t monoNs,
                                           std::vector<Feedback>& out);
  // Writes the `complete` status once every step is captured.
  void closeIfComplete(std::int64_t monoNs, std::vector<Feedback>& out);
  void rebuild();

  SessionLog log_;
  SessionSetup setup_;
  Engine engine_;
  std::map<std::tuple<int, int, int>, std::int64_t> seqs_;
  bool paused_ = false, ended_ = false, storeBlocked_ = false;
  std::string pauseReason_, status_ = "open";
  std::uint64_t version_ = 0;
};

}  // namespace leafdig::acquisition
