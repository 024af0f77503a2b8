#pragma once
// A plant session's files (docs/plants.md, "Simulated plant capture and the plant's files"). The survey's own:
// `mtg` (the MTG in the AMAP conventions), `csv` (its entities one row each), `markers` (what
// was digitized, a leafdig.plant-markers/1 document in the digitizer's frame), `json` (the
// survey: frame, nodes, leaves, angles; once the transmitter was moved, its positions with each
// fit's residual and each node's position). The plant as a model (model/plant/surveyed_plant.hpp:
// the stem through the nodes, full leaves as digitized, quick leaves shaped from the organ
// library of this store or the built-in sample): `glb`, `obj`, `ply`, `stl` (meshes with plant
// / leaf / organ names), `can` (CARIBU, in metres, with its `.opt`), `model` (the
// leafdig.plant-model/1 JSON), and `plan` (a leafdig.plant/1 plan with the measured values
// and each leaf's markers in a folder beside it, for `plant build` and the Plant view).
//
// The session must verify and hold a whole plant frame; the survey's day is the session's
// date, else the day it was created. Everything is encoded before anything is written; each
// file is written atomically and recorded in `exports`.
#include <cstdint>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "leafdig/db/event_store.hpp"
#include "leafdig/model/mesh/mesh_method.hpp"
#include "leafdig/model/plant/plant.hpp"
#include "leafdig/model/plant/plant_survey.hpp"

namespace leafdig::acquisition {

class PlantEngine;

// Where the transmitter stood (issue 29): position 1 where the capture began, 2… after each
// move, with the fit that related it to the first (its residual and worst landmark) and how
// many of the plant's own points were taken from it.
struct TransmitterPosition {
  int position = 1;
  int points = 0;  // landmarks, collar, node points, quick leaves' points (a full leaf's are its own)
  double rmsMm = 0, worstMm = 0;
  int worstLandmark = 0;  // 0 for position 1
};
// Every position of a replayed plant engine, the first included.
[[nodiscard]] std::vector<TransmitterPosition> transmitterPositions(const PlantEngine& engine);
// As the survey's and `sessions show`'s JSON say them: [{"position", "points"[, "rms_mm",
// "worst_mm", "worst_landmark"]}, …].
[[nodiscard]] std::string transmitterPositionsJson(const std::vector<TransmitterPosition>& positions);

// A stored plant session read back: verified, replayed, surveyed (InputError when it holds no
// whole plant frame yet, SessionError when it is not a plant session or does not verify).
struct CapturedSurvey {
  model::PlantMarkers markers;  // what was digitized, dated (the session's date, else its day)
  model::PlantSurvey survey;
  std::string status;  // the session's ("complete", "approved", …)
  std::vector<TransmitterPosition> transmitter;
  std::map<int, int> nodePosition;  // node → the transmitter position its first point was taken from
  // Full leaves taken across a move of the transmitter (their points from two positions or
  // more): node → the digitizer noise their area interval was drawn with instead of the stated
  // accuracy, √(σ² + RMS²) with the largest RMS of the moves involved.
  std::map<int, double> leafSigmaMm;
  // How far each node's point may be from where it is, 95 % of the time (issue 50): the radius
  // kNodeTolerance95 × √(σ² + RMS² + H²) — σ the digitizer's stated accuracy per coordinate,
  // RMS the fit of the transmitter position the node was taken from (0 for the first), H the
  // checked field's correction's error on divots it did not see (0 without a field check).
  std::map<int, double> nodeToleranceMm;
  // The organ library's leaves, read once when the plant has a quick leaf (empty otherwise): the
  // shapes its quick leaves are drawn with, for their areas here and capturedModel's drawing.
  std::vector<model::LibraryLeaf> library;
  std::optional<double> fieldHoldoutRmsMm;  // H, when the session went through a checked field
};
[[nodiscard]] CapturedSurvey capturedSurvey(const db::EventStore& store, std::int64_t id);
// √χ²₃(0.95): a 3-D normal error of σ per coordinate stays within 2.80 σ of the truth 95 % of
// the time.
inline constexpr double kNodeTolerance95 = 2.7955;
// The survey as its JSON export says it (model::plantSurveyToJson) with what the capture adds:
// once the transmitter moved, its positions, each node's position and a moved leaf's interval
// noise; once it moved or went through a checked field, each node's position_tolerance_mm.
[[nodiscard]] nlohmann::json capturedSurveyJson(const CapturedSurvey& captured);

// The surveyed plant as a model (model/plant/surveyed_plant.hpp), its quick leaves shaped from
// the organ library capturedSurvey read (its `library`).
struct CapturedModel {
  model::Plant plant;
  std::vector<std::string> notes;  // where each quick leaf's shape came from
};
[[nodiscard]] CapturedModel capturedModel(const CapturedSurvey& captured);

// The survey's MTG and CSV of a plant session, as `sessions export` writes them (its provenance
// in their header comments): what a captured plant's `mtg()` and `csv()` give in Python, so a
// plant has one MTG whichever way it is asked for.
struct SurveyTexts {
  std::string mtg, csv;
};
[[nodiscard]] SurveyTexts surveyTexts(const db::EventStore& store, std::int64_t id, const CapturedSurvey& captured);

struct PlantExport {
  std::vector<std::string> written;
  model::PlantSurvey survey;
  std::vector<std::string> notes;  // what a reader should know (a quick leaf's borrowed shape)
};
// mtg, csv, markers, json, glb, obj, ply, stl, can, model, plan: what an export writes by default
[[nodiscard]] const std::vector<std::string>& plantExportFormats();
// xml (Helios), vgx (VegeSTAR): written when asked for by name (a default export keeps the files
// it always wrote)
[[nodiscard]] const std::vector<std::string>& plantRequestedFormats();
// How the model's formats (glb obj ply stl can model) are meshed: a resolution preset
// (model::kFileResolutionNames) and which organs they keep — a light model's blades alone are a
// fraction of the triangles and bytes.
struct PlantMeshChoice {
  std::string resolution = "export";
  model::OrganChoice organs = model::OrganChoice::All;
};
PlantExport exportPlantSession(db::EventStore& store, std::int64_t id, const std::vector<std::string>& formats,
                               const std::string& outDir, const PlantMeshChoice& meshChoice = {});

// The captured plant as a leafdig.plant/1 plan (`leaf markers` name each leaf's file relative to
// the plan, in the order of `plant.leaves`): the stem's points with their diameters, each leaf's
// rank, insertion height along the stem, azimuth, inclination and roll as measured.
[[nodiscard]] std::string plantPlanJson(const model::Plant& plant, const model::PlantSurvey& survey,
                                        const std::vector<std::string>& leafMarkers);

// One survey of a plant: a plant session of that plant id, dated (repeat surveys of the same
// plant are new sessions, each with its day).
struct PlantSurveyEntry {
  std::int64_t session = 0;
  std::string date;  // YYYY-MM-DD: the session's date, else the day it was created
  std::string status, project, operatorName, station, createdUtc;
  int nodes = 0;                        // nodes taken so far
  int full = 0, quick = 0, noLeaf = 0;  // leaves by kind, as far as taken
  std::int64_t events = 0;
  bool verified = false;  // its chain recomputes; an unverified session's counts are left at 0
  // Why a session whose chain verifies does not read (its settings, an event): the others are
  // still listed — one station's session never hides another's surveys.
  std::string problem;
};
// Every survey of `plant` in the store, oldest day first (then by session).
[[nodiscard]] std::vector<PlantSurveyEntry> plantSurveys(const db::EventStore& store, const std::string& plant);

}  // namespace leafdig::acquisition
