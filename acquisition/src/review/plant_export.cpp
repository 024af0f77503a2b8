#include "leafdig/acquisition/review/plant_export.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <future>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <utility>
#include <variant>

#include "leafdig/acquisition/review/provenance.hpp"
#include "leafdig/acquisition/review/review.hpp"
#include "leafdig/acquisition/session/plant_session.hpp"
#include "leafdig/model/errors.hpp"
#include "leafdig/model/files.hpp"
#include "leafdig/model/io/plant_export.hpp"
#include "leafdig/model/io/survey_export.hpp"
#include "leafdig/model/leaf/markers_json.hpp"
#include "leafdig/model/metrics/area_interval.hpp"
#include "leafdig/model/plant/surveyed_plant.hpp"
#include "leafdig/model/synth/synthetic_leaf.hpp"
#include "leafdig/version.hpp"
#include "review_checks.hpp"

namespace leafdig::acquisition {

namespace {

using nlohmann::json;
namespace m = leafdig::model;

// The plant as a model: mesh files by their extension (encodePlant's), the plant-model JSON.
const std::vector<std::pair<std::string, std::string>>& modelFormats() {
  static const std::vector<std::pair<std::string, std::string>> formats{
      {"glb", ".glb"},        {"obj", ".obj"}, {"ply", ".ply"},
      {"stl", ".stl"},        {"can", ".can"}, {"model", ".plant-model.json"},
      {"xml", ".helios.xml"}, {"vgx", ".vgx"}};
  return formats;
}

bool wants(const std::vector<std::string>& chosen, const std::string& f) {
  return std::find(chosen.begin(), chosen.end(), f) != chosen.end();
}

// The first node that starts a branch, if any.
std::optional<m::SurveyedNode> firstBranch(const m::PlantSurvey& survey) {
  for (const m::SurveyedNode& n : survey.nodes)
    if (n.link.relation == '+') return n;
  return std::nullopt;
}

}  // namespace

const std::vector<std::string>& plantExportFormats() {
  static const std::vector<std::string> formats{"mtg", "csv", "markers", "json",  "glb", "obj",
                                                "ply", "stl", "can",     "model", "plan"};
  return formats;
}

const std::vector<std::string>& plantRequestedFormats() {
  static const std::vector<std::string> formats{"xml", "vgx"};
  return formats;
}

std::string plantPlanJson(const m::Plant& plant, const m::PlantSurvey& survey,
                          const std::vector<std::string>& leafMarkers) {
  if (const auto branch = firstBranch(survey))
    throw m::InputError("node " + std::to_string(branch->index) + " starts a branch (from node " +
                        std::to_string(branch->link.parent) +
                        "): a leafdig.plant/1 plan holds one stem and its leaves; export the plant's MTG, GLB or "
                        "plant-markers instead");
  // The stem's points as the plan reads them (the collar first), and each node's height
  // along them: the polyline's length to it, as the plan measures insertion heights.
  json points = json::array({json::array({0.0, 0.0, 0.0, survey.collarDiameterMm})});
  std::vector<double> along{0.0};
  for (const m::SurveyedNode& n : survey.nodes) {
    points.push_back({n.pointMm.x(), n.pointMm.y(), n.pointMm.z(), n.diameterMm});
    along.push_back(along.back() + n.internodeMm);  // the straight length from the node below
  }
  json leaves = json::array();
  for (std::size_t i = 0; i < plant.leaves.size(); ++i) {
    const m::PlacedLeaf& l = plant.leaves[i];
    leaves.push_back({{"rank", l.rank},
                      {"markers", leafMarkers.at(i)},
                      {"insertion_height", along.at(static_cast<std::size_t>(l.rank))},
                      {"azimuth_deg", l.azimuthDeg},
                      {"inclination_deg", l.inclinationDeg},
                      {"roll_deg", l.rollDeg}});
  }
  const json plan{{"format", m::kPlantPlanFormat}, {"units", "mm"},   {"id", plant.id}, {"seed", 0},
                  {"stem", {{"points", points}}},  {"leaves", leaves}};
  return plan.dump(2) + "\n";
}

CapturedSurvey capturedSurvey(const db::EventStore& store, std::int64_t id) {
  const auto info = store.session(id);
  if (!info) throw SessionError("there is no session " + std::to_string(id) + " in " + store.describe());
  if (info->kind != "plant")
    throw SessionError("session " + std::to_string(id) +
                       " captured one leaf: `leafdig sessions export` without a "
                       "plant's formats writes it");
  detail::requireChain(store, id, "exported or shown");
  const PlantSessionSetup setup = PlantCaptureSession::setupFromJson(info->settingsJson);
  CapturedSurvey out;
  out.status = info->status;
  const PlantEngine engine = PlantCaptureSession::replay(setup, store.events(id));
  out.markers = engine.captured(info->plant);
  out.transmitter = transmitterPositions(engine);
  for (const PlantItem& i : engine.items())
    if (i.what == PlantWhat::Point && i.part == 1) out.nodePosition[i.index] = i.frame + 1;
  out.markers.date = setup.date;
  if (!out.markers.date) out.markers.date = m::parseSurveyDate(info->createdUtc.substr(0, 10));
  try {
    out.survey = m::surveyPlant(out.markers);
  } catch (const m::InputError& e) {
    throw m::InputError("plant session " + std::to_string(id) + " holds no whole plant yet (" + e.what() +
                        "): go on with `leafdig plant capture --resume " + std::to_string(id) + "`");
  }
  // A quick leaf's area is its drawn shape's, from the organ library as the model draws it.
  if (m::hasQuickLeaf(out.survey)) {
    out.library = organLibrary(store).leaves;
    m::addDrawnAreas(out.survey, out.library, m::LibraryLeaf{m::kSampleShapeSource, m::sampleLeafShape()});
  }
  // A full leaf taken across a move of the transmitter: its points before and after stand in
  // frames related by a fit with a residual, which the interval's draws add to the noise.
  // A checked field's correction adds its error on divots it did not see to every full leaf's.
  for (m::SurveyedLeaf& leaf : out.survey.leaves) {
    const std::set<int> positions = engine.leafPositions(leaf.node);
    if ((positions.size() < 2 && !setup.field) || !leaf.markers || !leaf.areaLow95Mm2) continue;
    double rms = 0;
    for (int r : positions)
      if (r > 0) rms = std::max(rms, engine.fitOf(r).rmsMm);
    m::AreaUncertaintyOptions options;
    options.sigmaMm = std::hypot(options.sigmaMm, rms);
    if (setup.field) options.sigmaMm = std::hypot(options.sigmaMm, setup.field->holdoutRmsMm);
    const m::AreaUncertainty u = m::areaUncertainty(*leaf.markers, options);
    leaf.areaLow95Mm2 = u.low95Mm2;
    leaf.areaHigh95Mm2 = u.high95Mm2;
    out.leafSigmaMm[leaf.node] = options.sigmaMm;
  }
  if (setup.field) out.fieldHoldoutRmsMm = setup.field->holdoutRmsMm;
  for (const m::SurveyedNode& n : out.survey.nodes) {
    const auto at = out.nodePosition.find(n.index);
    const int r = at == out.nodePosition.end() ? 0 : at->second - 1;
    const double rms = r > 0 ? engine.fitOf(r).rmsMm : 0.0;
    out.nodeToleranceMm[n.index] =
        kNodeTolerance95 * std::sqrt(m::kFastrakSigmaMm * m::kFastrakSigmaMm + rms * rms +
                                     out.fieldHoldoutRmsMm.value_or(0) * out.fieldHoldoutRmsMm.value_or(0));
  }
  return out;
}

std::vector<TransmitterPosition> transmitterPositions(const PlantEngine& engine) {
  std::vector<TransmitterPosition> out;
  for (int r = 0; r < static_cast<int>(engine.toFirst().size()); ++r) {
    TransmitterPosition p;
    p.position = r + 1;
    for (const PlantItem& i : engine.items())
      p.points += isStylusItem(i.what) && i.what != PlantWhat::LandmarkAgain && i.frame == r;
    if (r > 0) {
      const RelocationFit fit = engine.fitOf(r);
      p.rmsMm = fit.rmsMm;
      p.worstMm = fit.worstMm;
      p.worstLandmark = fit.worstLandmark;
    }
    out.push_back(p);
  }
  return out;
}

std::string transmitterPositionsJson(const std::vector<TransmitterPosition>& positions) {
  json out = json::array();
  for (const TransmitterPosition& p : positions) {
    json j{{"position", p.position}, {"points", p.points}};
    if (p.position > 1) {
      j["rms_mm"] = p.rmsMm;
      j["worst_mm"] = p.worstMm;
      j["worst_landmark"] = p.worstLandmark;
    }
    out.push_back(j);
  }
  return out.dump();
}

namespace {

// The survey's JSON with where it came from and what the capture adds.
std::string surveyJson(const CapturedSurvey& captured, const m::Provenance& provenance) {
  json doc = capturedSurveyJson(captured);
  doc["provenance"] = json::parse(provenanceJson(provenance));
  return doc.dump(2) + "\n";
}

}  // namespace

json capturedSurveyJson(const CapturedSurvey& captured) {
  json doc = json::parse(m::plantSurveyToJson(captured.survey));
  const bool moved = captured.transmitter.size() >= 2;
  // A node's tolerance is said where it is more than the digitizer's own: across a move or a
  // checked field (the survey of a session with neither is as it always was).
  if (moved || captured.fieldHoldoutRmsMm)
    for (json& n : doc.at("nodes"))
      if (const auto it = captured.nodeToleranceMm.find(n.at("node").get<int>()); it != captured.nodeToleranceMm.end())
        n["position_tolerance_mm"] = it->second;
  if (!moved) return doc;
  doc["transmitter_positions"] = json::parse(transmitterPositionsJson(captured.transmitter));
  for (json& n : doc.at("nodes")) {
    const auto it = captured.nodePosition.find(n.at("node").get<int>());
    n["transmitter_position"] = it == captured.nodePosition.end() ? json(nullptr) : json(it->second);
  }
  for (json& l : doc.at("leaves"))
    if (const auto it = captured.leafSigmaMm.find(l.at("node").get<int>()); it != captured.leafSigmaMm.end())
      l["area_interval_sigma_mm"] = it->second;  // taken across a move: the residual added to the noise
  return doc;
}

CapturedModel capturedModel(const CapturedSurvey& captured) {
  CapturedModel out;
  out.plant =
      m::surveyedPlant(captured.survey, captured.library, m::LibraryLeaf{m::kSampleShapeSource, m::sampleLeafShape()});
  for (const m::PlacedLeaf& l : out.plant.leaves)
    if (!l.shapeDigitized) out.notes.push_back("leaf " + std::to_string(l.rank) + " (quick): shape from " + l.source);
  return out;
}

SurveyTexts surveyTexts(const db::EventStore& store, std::int64_t id, const CapturedSurvey& captured) {
  const std::string comments = provenanceComments(sessionProvenance(store, detail::infoOrThrow(store, id)));
  const m::SurveyDate day = captured.markers.date.value_or(m::SurveyDate{2000, 1, 1});
  return {comments + m::encodeSurveyMtg(captured.survey, day), comments + m::encodeSurveyCsv(captured.survey, day)};
}

PlantExport exportPlantSession(db::EventStore& store, std::int64_t id, const std::vector<std::string>& formats,
                               const std::string& outDir, const PlantMeshChoice& meshChoice) {
  detail::noteStoreAsInput(store);
  if (outDir.empty()) throw std::invalid_argument("choose a destination directory for the export");
  const std::vector<std::string>& all = plantExportFormats();
  // Helios and VegeSTAR when asked for: a default export keeps the files it always wrote.
  const std::vector<std::string>& onRequest = plantRequestedFormats();
  std::vector<std::string> chosen = formats.empty() ? all : formats;
  for (const std::string& f : chosen)
    if (!wants(all, f) && !wants(onRequest, f))
      throw std::invalid_argument("unknown export format '" + f +
                                  "' for a plant session: use mtg, csv, markers, json, glb, obj, ply, stl, can, "
                                  "model, plan, xml (Helios) or vgx (VegeSTAR)");
  const CapturedSurvey captured = capturedSurvey(store, id);
  const m::PlantMarkers& plant = captured.markers;
  // Which session, station, status, operator and curator: in every file's header or metadata.
  const m::Provenance provenance = sessionProvenance(store, detail::infoOrThrow(store, id));
  PlantExport out;
  out.survey = captured.survey;
  // Every format by default: a branched plant's plan is left out (a plan holds one stem), said.
  if (formats.empty() && firstBranch(out.survey)) {
    chosen.erase(std::find(chosen.begin(), chosen.end(), "plan"));
    out.notes.emplace_back("no leafdig.plant/1 plan: the plant has branches and a plan holds one stem");
  }
  const m::SurveyDate day = plant.date.value_or(m::SurveyDate{2000, 1, 1});
  const std::string name = "session-" + std::to_string(id);
  const std::string base = outDir + "/" + name;
  std::vector<m::EncodedFile> files;
  const bool texts = wants(chosen, "mtg") || wants(chosen, "csv");
  const SurveyTexts survey = texts ? surveyTexts(store, id, captured) : SurveyTexts{};
  for (const std::string& f : chosen) {
    if (f == "mtg") files.push_back({base + ".mtg", survey.mtg});
    if (f == "csv") files.push_back({base + ".plant.csv", survey.csv});
    if (f == "markers") files.push_back({base + ".plant-markers.json", m::plantMarkersToJson(plant)});
    if (f == "json") files.push_back({base + ".survey.json", surveyJson(captured, provenance)});
  }

  // The plant as a model: only when a model's format is asked for (it meshes every leaf).
  std::vector<std::filesystem::path> meshPaths;
  for (const auto& [f, extension] : modelFormats())
    if (wants(chosen, f)) meshPaths.emplace_back(base + extension);
  if (!meshPaths.empty() || wants(chosen, "plan")) {
    CapturedModel made = capturedModel(captured);
    const m::Plant& model = made.plant;
    out.notes.insert(out.notes.end(), made.notes.begin(), made.notes.end());
    if (!meshPaths.empty()) {
      m::MeshOptions meshOptions;
      meshOptions.resolution = m::MeshResolution::preset(meshChoice.resolution);
      const m::LeafMesh mesh = m::withOrgans(m::meshPlant(model, meshOptions), meshChoice.organs);
      const m::PlantMetrics metrics = m::computePlantMetrics(model, mesh, Eigen::Vector3d::UnitZ());
      const m::PlantExportOptions options{m::CanUnit::Metre, std::string("leafdig ") + kVersion};
      // The GLB's nodes are the MTG's entities (the survey's), encoded beside the model's other
      // formats (on their own threads); the GLB comes first, as modelFormats() lists it.
      std::vector<std::filesystem::path> others;
      std::optional<std::filesystem::path> glb;
      for (const auto& path : meshPaths) {
        if (path.extension() == ".glb")
          glb = path;
        else
          others.push_back(path);
      }
      std::future<std::string> glbBytes;
      if (glb)
        glbBytes = std::async(std::launch::async,
                              [&] { return m::encodeSurveyGlb(out.survey, day, mesh, options.generator, provenance); });
      std::vector<m::EncodedFile> encoded;
      if (!others.empty()) encoded = m::encodePlantFiles(others, model, mesh, metrics, options);
      if (glb) files.push_back({*glb, glbBytes.get()});
      for (auto& f : encoded) files.push_back(std::move(f));
    }
    if (wants(chosen, "plan")) {
      if (model.leaves.empty())
        throw m::InputError("plant session " + std::to_string(id) +
                            " has no leaf with points: a leafdig.plant/1 plan needs at least one leaf");
      std::vector<std::string> leafFiles;
      for (const m::PlacedLeaf& l : model.leaves) {
        const std::string file = name + ".leaves/leaf-" + std::to_string(l.rank) + ".markers.json";
        m::MarkerSet markers = l.model.markers;
        markers.leaf.plant = model.id;
        markers.leaf.id = model.id + " L" + std::to_string(l.rank);
        markers.leaf.position = l.rank;
        files.push_back({std::filesystem::path(outDir) / file, m::markersToJson(markers)});
        leafFiles.push_back(file);
      }
      files.push_back({base + ".plant.json", plantPlanJson(model, out.survey, leafFiles)});
    }
  }

  for (const m::EncodedFile& f : files) {
    std::filesystem::create_directories(f.path.parent_path());
    m::writeFileAtomically(f.path, f.bytes);
    const std::string fileName = f.path.filename().string();
    (void)store.recordExport(id, f.path.string(), fileName.substr(fileName.find('.') + 1));
    out.written.push_back(f.path.string());
  }
  return out;
}

std::vector<PlantSurveyEntry> plantSurveys(const db::EventStore& store, const std::string& plant) {
  std::vector<PlantSurveyEntry> out;
  for (const db::SessionInfo& info : store.sessions()) {
    if (info.kind != "plant" || info.plant != plant) continue;
    PlantSurveyEntry e;
    e.session = info.id;
    e.status = info.status;
    e.project = info.project;
    e.operatorName = info.operatorName;
    e.station = info.station;
    e.createdUtc = info.createdUtc;
    e.events = info.headSeq;
    e.date = info.createdUtc.substr(0, 10);
    try {
      e.verified = store.verify(info.id).ok;
    } catch (const db::StoreError&) {  // a damaged page under its events: not read
      e.verified = false;
    }
    if (e.verified) {
      try {
        const PlantSessionSetup setup = PlantCaptureSession::setupFromJson(info.settingsJson);
        if (setup.date) e.date = m::toIso(*setup.date);
        const m::PlantMarkers taken = PlantCaptureSession::replay(setup, store.events(info.id)).captured(info.plant);
        e.nodes = static_cast<int>(taken.nodes.size());
        for (const m::PlantNode& n : taken.nodes) {
          if (std::holds_alternative<m::MarkerSet>(n.leaf))
            ++e.full;
          else if (std::holds_alternative<m::QuickLeaf>(n.leaf))
            ++e.quick;
          else
            ++e.noLeaf;
        }
      } catch (const std::exception& x) {
        e.problem = x.what();
        e.nodes = e.full = e.quick = e.noLeaf = 0;
      }
    }
    out.push_back(std::move(e));
  }
  std::stable_sort(out.begin(), out.end(), [](const PlantSurveyEntry& a, const PlantSurveyEntry& b) {
    return a.date != b.date ? a.date < b.date : a.session < b.session;
  });
  return out;
}

}  // namespace leafdig::acquisition
