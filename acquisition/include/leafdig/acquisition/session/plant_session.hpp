// A plant capture session: the PlantEngine's decisions made durable (docs/plants.md, "Plant
// sessions"). Every decision is appended to the store's hash-chained log before it is
// reported, so a front end announces only what is on disk; opening a session replays its events
// through the engine (crash recovery and `plant capture` resuming share that path). A store
// that refuses a write leaves the engine as the store has it (rebuilt from the events) and the
// session reports the refusal; nothing acknowledged is lost.
//
// Events (docs/schema.md, "Plant sessions"): `accepted` / `undone` with the plant's items
// ("landmark", "collar", "collar_diameter", "point", "reading", "quick_point"; row = landmark or
// node number, col = which point) or a full leaf's ("node3.marker", row and col the leaf's),
// `rows_ended` / `rows_reopened` {"node"}, `landmarks_ended`, `landmarks_reopened`,
// `plant_ended`, `plant_reopened`, `leaf_chosen` / `choice_undone` {"node", "kind", "state"},
// `retake` (the item and the seq of the event that put it in) / `retake_cancelled` (the item),
// `rejected`, `status`, `paused` {"reason"} / `resumed`, `ignored_reading` (a reading while
// paused), `device` {"device","state","message"}, and a curator's `corrected`
// (correct(), review/correction.hpp).
//
// Thread contract: one thread owns a PlantCaptureSession (and its Store).
#pragma once

#include <cstdint>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "leafdig/acquisition/field/field_applied.hpp"
#include "leafdig/acquisition/field/tip_calibration.hpp"
#include "leafdig/acquisition/protocol/plant_engine.hpp"
#include "leafdig/acquisition/session/session_log.hpp"
#include "leafdig/db/store.hpp"
#include "leafdig/model/plant/plant_markers.hpp"
#include "leafdig/model/plant/plant_protocol.hpp"
#include "leafdig/model/plant/plant_survey.hpp"

namespace leafdig::acquisition {

struct PlantSessionSetup {
  std::string project, plant;
  std::string operatorName = "technician";
  std::string station;  // empty: this machine's (thisStation())
  model::PlantProtocol protocol = model::defaultPlantProtocol();
  Settings settings;  // the stylus guards and the full leaves' leaf protocol
  std::optional<model::SurveyDate> date;
  std::string digitizer, caliper;
  bool simulated = false;
  // Simulated sessions: the plant the virtual technician digitizes, kept with the session.
  std::optional<model::PlantMarkers> simulatedPlant;
  // The field check whose correction every stylus sample goes through (field_applied.hpp).
  std::optional<FieldApplied> field;
  // The stylus' tip calibration the digitizer applies to every sample (tip_calibration.hpp).
  std::optional<TipApplied> tip;
};

// What a front end announces, after it was committed (seq: the event's number; 0 for a
// rejection the store refused to record and for an ignored input).
struct PlantFeedback {
  PlantDecision decision;
  std::int64_t seq = 0;
  std::optional<std::int64_t> completeSeq;  // the `complete` status, when this decision finished the plant
  std::optional<std::string> storeRefused;  // the store's words when the write failed (nothing changed)
  // An operator's pause or resume (the decision is Ignored): `paused` holds the reason.
  enum class Control { None, Paused, Resumed } control = Control::None;
  std::string paused;
};

class PlantCaptureSession {
 public:
  // Creates the project, plant and operator as needed and a new open plant session.
  static std::int64_t create(db::Store& store, const PlantSessionSetup& setup);

  // Opens a stored plant session and replays it. Throws SessionError when it is not a plant
  // session, not open, or its events do not replay.
  PlantCaptureSession(db::Store& store, std::int64_t id);

  PlantFeedback onStylus(const StylusInput& s);
  PlantFeedback onCaliper(const CaliperInput& c);
  PlantFeedback undo(std::int64_t monoNs = 0);
  PlantFeedback end(std::int64_t monoNs = 0);
  PlantFeedback chooseLeaf(int node, LeafChoice choice, std::int64_t monoNs = 0);
  // PlantEngine::branch made durable (`node_placed`; its undo `placement_undone`).
  PlantFeedback branch(int from, std::int64_t monoNs = 0);
  // PlantEngine::moveTransmitter made durable (`relocation` events: started, fitted, reopened,
  // cancelled; the landmarks taken again are `accepted` landmark_again items).
  // Refused in words (a `rejected` event) for a capture through a checked field
  // (FieldApplied::moveRefusal).
  PlantFeedback moveTransmitter(std::int64_t monoNs = 0);
  // PlantEngine::retake / retakeLeaf made durable (`retake` names the event that put the item
  // in; undo before the new one puts it back: `retake_cancelled` with the item).
  PlantFeedback retake(PlantWhat what, int index, int part, std::int64_t monoNs = 0);
  PlantFeedback retakeLeaf(int node, What what, int row, int col, std::int64_t monoNs = 0);
  // Ends the session unfinished (status `abandoned`, with why).
  PlantFeedback abandon(const std::string& why, std::int64_t monoNs = 0);
  // An operator's pause (a `paused` event with the reason): until resume() the stylus and the
  // caliper change nothing (a reading is logged as `ignored_reading`), and undo, end and leaf
  // choices wait; a pause survives a restart (the session opens paused). Nothing when already
  // paused or ended.
  PlantFeedback pause(const std::string& reason, std::int64_t monoNs = 0);
  PlantFeedback resume(std::int64_t monoNs = 0);
  [[nodiscard]] bool paused() const { return paused_; }
  // A device's change of state, kept in the log (a `device` event {"device","state","message"}),
  // as a leaf capture keeps it; a store that refuses it loses nothing acknowledged.
  PlantFeedback deviceStatus(const std::string& device, const std::string& state, const std::string& message,
                             std::int64_t monoNs = 0);
  [[nodiscard]] const std::string& pauseReason() const { return pauseReason_; }

  [[nodiscard]] std::int64_t id() const { return log_.id(); }
  [[nodiscard]] const PlantEngine& engine() const { return engine_; }
  [[nodiscard]] const PlantSessionSetup& setup() const { return setup_; }
  [[nodiscard]] bool ended() const { return status_ != "open"; }
  [[nodiscard]] const std::string& status() const { return status_; }

  // The settings a plant session keeps (its protocol, leaf settings, date, devices and the
  // simulated plant) and back; SessionError for what does not read.
  [[nodiscard]] static std::string setupToJson(const PlantSessionSetup& setup);
  [[nodiscard]] static PlantSessionSetup setupFromJson(const std::string& json);
  // Rebuilds an engine from stored events (no store access; review and exports use it).
  // Throws SessionError naming the event that does not fit.
  [[nodiscard]] static PlantEngine replay(const PlantSessionSetup& setup, const std::vector<db::Event>& events,
                                          std::map<std::string, std::int64_t>* seqs = nullptr);

 private:
  PlantFeedback commit(const PlantDecision& d, std::int64_t monoNs, const std::string& raw);
  // Appends an event that is no decision (a status, a pause, a device's state): its seq into f,
  // or the store's words into f.storeRefused and false.
  bool appendInto(const db::EventInput& ev, PlantFeedback& f);
  void rebuild();

  SessionLog log_;
  PlantSessionSetup setup_;
  PlantEngine engine_;
  std::map<std::string, std::int64_t> seqs_;  // the event that accepted each current item
  std::string status_ = "open";
  bool paused_ = false;
  std::string pauseReason_;
};

}  // namespace leafdig::acquisition
