#include "leafdig/acquisition/review/leaf_export.hpp"

#include <algorithm>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <variant>

#include "leafdig/acquisition/review/plant_export.hpp"
#include "leafdig/acquisition/review/provenance.hpp"
#include "leafdig/acquisition/review/review.hpp"
#include "leafdig/acquisition/session/preview.hpp"
#include "leafdig/model/files.hpp"
#include "leafdig/model/io/csv_text.hpp"
#include "leafdig/model/io/mesh_export.hpp"
#include "leafdig/model/io/model_json.hpp"
#include "leafdig/model/leaf/markers_json.hpp"
#include "leafdig/version.hpp"
#include "review_checks.hpp"

namespace leafdig::acquisition {
namespace {

using detail::infoOrThrow;
using detail::requireChain;
using model::csvText;
using nlohmann::json;

// Only the items of one leaf of a plant session, with their words as a leaf's ("node3.marker" → "marker").
void keepLeafItems(db::Projected& items, const std::string& prefix) {
  const auto strip = [&](auto& rows) {
    rows.erase(std::remove_if(rows.begin(), rows.end(), [&](const auto& x) { return x.what.rfind(prefix, 0) != 0; }),
               rows.end());
    for (auto& x : rows) x.what = x.what.substr(prefix.size());
  };
  strip(items.markers);
  strip(items.thickness);
}

}  // namespace

model::MarkerSet plantLeafMarkers(const db::EventStore& store, std::int64_t id, int node) {
  if (infoOrThrow(store, id).kind != "plant")
    throw SessionError(
        "session " + std::to_string(id) +
        " captured one leaf: --node names a full leaf of a plant session (node= in Python); leave it out");
  const CapturedSurvey captured = capturedSurvey(store, id);
  std::string full;  // the nodes that have one, for the message
  for (std::size_t k = 0; k < captured.markers.nodes.size(); ++k)
    if (std::holds_alternative<model::MarkerSet>(captured.markers.nodes[k].leaf))
      full += (full.empty() ? "" : ", ") + std::to_string(k + 1);
  const auto at = static_cast<std::size_t>(node) - 1;
  if (node < 1 || at >= captured.markers.nodes.size() ||
      !std::holds_alternative<model::MarkerSet>(captured.markers.nodes[at].leaf))
    throw std::invalid_argument(
        "plant session " + std::to_string(id) + " has no full leaf at node " + std::to_string(node) + ": " +
        (full.empty() ? std::string("none of its leaves was taken in full") : "its full leaves are at node " + full));
  model::MarkerSet set = std::get<model::MarkerSet>(captured.markers.nodes[at].leaf);
  set.leaf.plant = captured.markers.plant;
  set.leaf.id = captured.markers.plant + " node " + std::to_string(node);
  set.leaf.position = node;
  return set;
}

const std::vector<std::string>& exportFormats() {
  static const std::vector<std::string> formats{"glb", "obj", "ply", "stl", "model", "markers", "csv"};
  return formats;
}

ExportResult exportSession(db::EventStore& store, std::int64_t id, const ExportRequest& request) {
  detail::noteStoreAsInput(store);
  if (request.outDir.empty()) throw std::invalid_argument("choose a destination directory for the export");
  if (request.frame != "leaf" && request.frame != "digitizer")
    throw std::invalid_argument("unknown frame '" + request.frame + "': use leaf or digitizer");
  std::vector<std::string> formats = request.formats.empty() ? exportFormats() : request.formats;
  for (const auto& f : formats)
    if (std::find(exportFormats().begin(), exportFormats().end(), f) == exportFormats().end())
      throw std::invalid_argument("unknown export format '" + f + "': use glb, obj, ply, stl, model, markers, csv");
  model::MarkerSet set;
  std::optional<ReviewedSession> reviewed;  // a single leaf's session (not a plant's leaf)
  std::string base = request.outDir + "/session-" + std::to_string(id);
  std::string itemPrefix;  // a plant's leaf: its items' words begin "node<k>."
  if (request.node) {
    set = plantLeafMarkers(store, id, *request.node);
    base += ".node-" + std::to_string(*request.node);
    itemPrefix = "node" + std::to_string(*request.node) + ".";
  } else {
    reviewed = openForReview(store, id);
    requireChain(store, id, "exported");
    set = sessionMarkers(*reviewed);
  }
  const model::LeafInfo& info = set.leaf;
  model::LeafModel leaf = model::buildLeafModel(set, {model::bladeKindFromString(request.blade), nullptr});
  if (request.frame == "leaf") leaf = model::transformed(leaf, model::leafFrameFromDigitizer(leaf));
  model::MeshOptions meshOptions;
  meshOptions.method = model::meshMethodFromString(request.mesh);
  meshOptions.resolution = model::MeshResolution::preset(request.resolution);
  meshOptions.maxErrorMm = request.maxErrorMm;
  meshOptions.seed = request.seed;
  const model::LeafMesh mesh = model::withOrgans(model::meshLeaf(leaf, meshOptions), request.organs);
  ExportResult result;
  result.metrics = model::computeLeafMetrics(leaf, Eigen::Vector3d(0, 0, 1), 5.0);
  if (reviewed) widenForCapture(*reviewed, leaf, result.metrics);
  model::addSilhouette(result.metrics, mesh);
  result.rows = set.rows.size();
  // Which session, station, status, operator and curator: in every file's header or metadata.
  const model::Provenance provenance = sessionProvenance(store, infoOrThrow(store, id));
  const std::string comments = provenanceComments(provenance);
  const model::ExportHeader header{info.id, request.frame, std::string("leafdig ") + kVersion, provenance};
  std::vector<std::pair<std::string, std::string>> files;  // path, bytes
  for (const std::string& f : formats) {
    if (f == "glb" || f == "obj" || f == "ply" || f == "stl") {
      files.emplace_back(base + "." + f, model::encodeMesh(mesh, model::meshFormatForPath(base + "." + f), header));
    } else if (f == "model") {
      json doc = json::parse(model::modelToJson(leaf, request.frame, result.metrics));
      // Taken across a move of the transmitter: which points came from which position, and
      // each move's fit.
      if (reviewed && reviewed->engine.transmitterPositions() > 1)
        doc["transmitter_positions"] = json::parse(leafTransmitterPositionsJson(reviewed->engine, true));
      doc["provenance"] = json::parse(provenanceJson(provenance));
      files.emplace_back(base + ".model.json", doc.dump(1) + "\n");
    } else if (f == "markers") {
      files.emplace_back(base + ".markers.json", model::markersToJson(set));
    } else if (f == "csv") {
      // From the verified events (the tables agree with them, or verify refused above).
      db::Projected items = db::project(store.events(id));
      if (!itemPrefix.empty()) keepLeafItems(items, itemPrefix);
      std::ostringstream mk, th;
      mk << comments << std::setprecision(17) << "session,seq,what,row,col,x_mm,y_mm,z_mm\n";
      for (const auto& x : items.markers)
        mk << id << "," << x.seq << "," << x.what << "," << (x.row ? std::to_string(*x.row) : "") << ","
           << (x.col ? std::to_string(*x.col) : "") << "," << x.positionMm[0] << "," << x.positionMm[1] << ","
           << x.positionMm[2] << "\n";
      th << comments << std::setprecision(17) << "session,seq,what,row,col,thickness_mm,raw\n";
      for (const auto& x : items.thickness)
        th << id << "," << x.seq << "," << x.what << "," << (x.row ? std::to_string(*x.row) : "") << ","
           << (x.col ? std::to_string(*x.col) : "") << "," << x.valueMm << "," << csvText(x.raw) << "\n";
      files.emplace_back(base + ".markers.csv", mk.str());
      files.emplace_back(base + ".thickness.csv", th.str());
      // The leaf's numbers in one row (a spreadsheet of many sessions: concatenate these).
      const model::LeafMetrics& lm = result.metrics;
      std::ostringstream me;
      me << comments << std::setprecision(17);
      const auto cell = [&me](std::optional<double> v) {
        if (v) me << *v;
        me << ",";
      };
      me << "session,rows,blade_area_mm2,area_low95_mm2,area_high95_mm2,projected_area_mm2,silhouette_mm2,star,"
            "mesh_area_mm2,measured_area_mm2,margin\n"
         << id << "," << set.rows.size() << ",";
      cell(lm.blade.areaMm2);
      cell(lm.areaInterval ? std::optional<double>(lm.areaInterval->low95Mm2) : std::nullopt);
      cell(lm.areaInterval ? std::optional<double>(lm.areaInterval->high95Mm2) : std::nullopt);
      cell(lm.blade.projectedAreaMm2);
      cell(lm.silhouette ? std::optional<double>(lm.silhouette->silhouetteMm2) : std::nullopt);
      cell(lm.silhouette ? std::optional<double>(lm.silhouette->star) : std::nullopt);
      cell(lm.silhouette ? std::optional<double>(lm.silhouette->meshAreaMm2) : std::nullopt);
      cell(lm.areaConstraint ? std::optional<double>(lm.areaConstraint->measuredMm2) : std::nullopt);
      me << csvText(lm.areaInterval ? lm.areaInterval->margin : "") << "\n";
      files.emplace_back(base + ".metrics.csv", me.str());
    }
  }
  std::filesystem::create_directories(request.outDir);
  for (const auto& [path, bytes] : files) {
    model::writeFileAtomically(path, bytes);
    const auto dot = path.find('.', path.rfind('/') + 1);
    (void)store.recordExport(id, path, path.substr(dot + 1));
    result.written.push_back(path);
  }
  return result;
}

}  // namespace leafdig::acquisition
