#include "leafdig/acquisition/review.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <sstream>
#include <stdexcept>
#include <variant>

#include "chain_check.hpp"
#include "item_json.hpp"
#include "leafdig/acquisition/plant_export.hpp"
#include "leafdig/acquisition/plant_session.hpp"
#include "leafdig/acquisition/preview.hpp"
#include "leafdig/model/files.hpp"
#include "leafdig/model/io/csv_text.hpp"
#include "leafdig/model/io/mesh_export.hpp"
#include "leafdig/model/io/model_json.hpp"
#include "leafdig/model/leaf/markers_json.hpp"
#include "leafdig/model/limits.hpp"
#include "leafdig/version.hpp"
#include "rigid_map.hpp"

namespace leafdig::acquisition {
namespace {

using detail::requireChain;
using nlohmann::json;

db::SessionInfo infoOrThrow(const db::EventStore& store, std::int64_t id) {
  const auto info = store.session(id);
  if (!info)
    throw SessionError("there is no session " + std::to_string(id) + " in " + store.describe() +
                       ": 'leafdig sessions list' shows them");
  return *info;
}

// A plant session's full leaf at `node`, as markers with its leaf's names (the plant, the node).
model::MarkerSet plantLeafMarkers(const db::EventStore& store, std::int64_t id, int node) {
  if (infoOrThrow(store, id).kind != "plant")
    throw SessionError("session " + std::to_string(id) +
                       " captured one leaf: --node names a full leaf of a plant session; leave it out");
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

using model::csvText;

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

model::LeafInfo leafInfoOf(const db::SessionInfo& info) {
  model::LeafInfo leaf;
  leaf.id = info.project + "/" + info.plant + "/leaf-" + std::to_string(info.leafPosition) + "/session-" +
            std::to_string(info.id);
  leaf.plant = info.plant;
  leaf.position = info.leafPosition;
  leaf.type = info.leafType;
  leaf.measuredAreaMm2 = info.measuredAreaMm2;
  readLeafMargin(info.settingsJson, leaf);
  return leaf;
}

}  // namespace

ReviewedSession openForReview(const db::EventStore& store, std::int64_t id, std::int64_t upToSeq) {
  ReviewedSession r{infoOrThrow(store, id), {}, Engine{}, {}, 0, 0};
  if (r.info.kind != "leaf")
    throw SessionError("session " + std::to_string(id) +
                       " captured a whole plant, not one leaf: `leafdig sessions export " + std::to_string(id) +
                       "` writes its files (`--node K` one full leaf's)");
  r.settings = CaptureSession::settingsFromJson(r.info.settingsJson);
  std::vector<db::Event> events = store.events(id);
  r.totalEvents = static_cast<std::int64_t>(events.size());
  if (upToSeq > 0) {
    events.erase(std::remove_if(events.begin(), events.end(), [&](const db::Event& e) { return e.seq > upToSeq; }),
                 events.end());
  }
  r.replayedEvents = static_cast<std::int64_t>(events.size());
  r.engine = CaptureSession::replay(r.settings, events, &r.seqs);
  return r;
}

void requireReplays(const db::SessionInfo& info, const std::vector<db::Event>& events) {
  if (info.kind == "plant")
    (void)PlantCaptureSession::replay(PlantCaptureSession::setupFromJson(info.settingsJson), events);
  else
    (void)CaptureSession::replay(CaptureSession::settingsFromJson(info.settingsJson), events);
}

std::vector<ReviewFlag> reviewFlags(const std::vector<Item>& items, double madLimit) {
  std::vector<ReviewFlag> out;
  for (const Item& i : items)
    if (!i.flag.empty()) out.push_back({i.what, i.row, i.col, i.flag});
  for (const What kind : {What::MidribThickness, What::VeinOriginThickness, What::PointThickness}) {
    std::vector<double> values;
    for (const Item& i : items)
      if (i.what == kind) values.push_back(i.valueMm);
    if (values.size() < 4) continue;
    const double m = median(values);
    std::vector<double> dev;
    for (double v : values) dev.push_back(std::abs(v - m));
    // 1.4826 MAD estimates a standard deviation; a floor keeps identical readings quiet.
    const double mad = std::max(1.4826 * median(dev), 0.01);
    for (const Item& i : items) {
      if (i.what != kind) continue;
      const double z = std::abs(i.valueMm - m) / mad;
      if (z > madLimit) {
        std::ostringstream t;
        t << std::fixed << std::setprecision(2) << "thickness " << i.valueMm << " mm is " << std::setprecision(1) << z
          << " MAD from the median " << std::setprecision(2) << m << " mm of " << toString(kind);
        out.push_back({i.what, i.row, i.col, t.str()});
      }
    }
  }
  // The midrib thins towards the tip: a reading thicker than the one a row nearer the base
  // by more than a quarter is worth a second look.
  std::vector<const Item*> midrib;
  for (const Item& i : items)
    if (i.what == What::MidribThickness) midrib.push_back(&i);
  std::sort(midrib.begin(), midrib.end(), [](const Item* a, const Item* b) { return a->row < b->row; });
  for (std::size_t k = 0; k + 1 < midrib.size(); ++k)
    if (midrib[k]->valueMm > 1.25 * midrib[k + 1]->valueMm) {
      std::ostringstream t;
      t << std::fixed << std::setprecision(2) << "midrib " << midrib[k]->valueMm << " mm at row " << midrib[k]->row
        << " is thicker than " << midrib[k + 1]->valueMm << " mm at row " << midrib[k + 1]->row << " (nearer the base)";
      out.push_back({What::MidribThickness, midrib[k]->row, 0, t.str()});
    }
  return out;
}

void setCorrectionItem(Correction& c, const std::string& word, int node) {
  c.node = node;
  c.plantWhat.reset();
  try {
    c.what = whatFromString(word);
    return;
  } catch (const std::invalid_argument&) {
  }
  try {
    c.plantWhat = plantWhatFromString(word);
  } catch (const std::invalid_argument&) {
    throw std::invalid_argument(word +
                                " is not an item: a leaf's board, board_again, tip, marker, midrib_thickness, "
                                "vein_origin_thickness, point_thickness or edge_thickness; a plant's landmark, "
                                "landmark_again, collar, collar_diameter, point, reading or quick_point");
  }
  if (node > 0)
    throw std::invalid_argument("node " + std::to_string(node) +
                                " is a full leaf: its items are tip, marker and the thicknesses, not " + word);
}

namespace {

// A curator's correction of one item as stored: the old item, the event it replaces, the
// corrected one, why and who.
db::EventInput correctionEvent(const Item& old, const Item& fixed, std::int64_t seq, const std::string& reason,
                               const std::string& who) {
  json payload = detail::itemJson(old);
  payload["seq"] = seq;
  payload["corrected"] = detail::itemJson(fixed);
  payload["reason"] = reason;
  payload["who"] = who;
  db::EventInput ev;
  ev.kind = "corrected";
  ev.payloadJson = payload.dump();
  ev.raw = fixed.raw;
  ev.projection = detail::projectionOf(fixed);
  ev.retracts = seq;
  return ev;
}

}  // namespace

std::int64_t correct(db::EventStore& store, std::int64_t id, const Correction& given) {
  Correction c = given;
  c.who = store.signature(given.who);  // through a login: the login that writes it
  const db::SessionInfo info = infoOrThrow(store, id);
  if (info.kind == "plant") {
    if (!c.plantWhat && c.node <= 0)
      throw std::invalid_argument("session " + std::to_string(id) +
                                  " is a plant: name the plant's item (landmark, collar, collar_diameter, point, "
                                  "reading, quick_point) or a full leaf's item with its node");
    PlantCorrection p;
    p.node = c.node;
    p.leafWhat = c.what;
    if (c.plantWhat) p.what = *c.plantWhat;
    p.row = c.row;
    p.col = c.col;
    p.positionMm = c.positionMm;
    p.valueMm = c.valueMm;
    p.reason = c.reason;
    p.who = c.who;
    p.confirmAboveMm = c.confirmAboveMm;
    return correctPlantSession(store, id, p);
  }
  if (c.plantWhat || c.node > 0)
    throw std::invalid_argument("session " + std::to_string(id) +
                                " captured one leaf: a plant's item or a node does not apply (--what tip, marker, "
                                "or a thickness, with --row and --col)");
  detail::requireCorrectable(store, id, info.status, c.reason, c.who);
  const ReviewedSession r = openForReview(store, id);
  const Item* old = findItem(r.engine.items(), c.what, c.row, c.col);
  if (!old)
    throw std::invalid_argument(std::string("session ") + std::to_string(id) + " has no " + toString(c.what) +
                                (c.row ? " at row " + std::to_string(c.row) : "") +
                                (c.col ? " col " + std::to_string(c.col) : "") + " to correct");
  Item fixed = *old;
  fixed.flag.clear();
  if (isStylusItem(c.what)) {
    if (!c.positionMm || c.valueMm)
      throw std::invalid_argument("a marker is corrected with a position (x, y, z in mm)");
    for (double v : *c.positionMm)
      if (!std::isfinite(v) || std::abs(v) > model::kMaxCoordinateMm)
        throw std::invalid_argument("the corrected position must be finite numbers in mm within ±" +
                                    std::to_string(static_cast<int>(model::kMaxCoordinateMm)) +
                                    " mm of the transmitter");
    fixed.positionMm = *c.positionMm;
    // A corrected point is given in the first transmitter position's frame (as the review shows
    // it); a board point taken again stays in its own.
    if (c.what != What::BoardAgain) fixed.frame = 0;
    // An item is held where sessions show gives it (the engine places a point taken after a move
    // into the first frame as it takes it), so the move is between the two positions as they are.
    detail::requireConfirmedMove(old->positionMm, fixed.positionMm, c.confirmAboveMm, toString(c.what));
  } else {
    if (!c.valueMm || c.positionMm) throw std::invalid_argument("a thickness is corrected with a value in mm");
    if (!(*c.valueMm >= r.settings.minThicknessMm && *c.valueMm <= r.settings.maxThicknessMm)) {
      std::ostringstream t;
      t << "a thickness of " << *c.valueMm << " mm is outside this session's range " << r.settings.minThicknessMm << "–"
        << r.settings.maxThicknessMm << " mm: give the value in millimetres";
      throw std::invalid_argument(t.str());
    }
    fixed.valueMm = *c.valueMm;
  }
  fixed.raw = "corrected by " + c.who;
  std::vector<db::EventInput> events{correctionEvent(*old, fixed, r.seqs.at(detail::keyOf(*old)), c.reason, c.who)};
  // A board point (as first taken, or taken again after a move) places every point taken after a
  // move: each move is fitted again and its points moved with the new fit, each by its own
  // correction, all written together or not at all.
  if ((c.what == What::Board || c.what == What::BoardAgain) && r.engine.transmitterPositions() > 1) {
    std::vector<Item> after = r.engine.items();
    for (Item& i : after)
      if (detail::keyOf(i) == detail::keyOf(fixed)) i = fixed;
    const std::string because =
        std::string("placed again by its move's new fit (") + toString(c.what) + " " + std::to_string(c.col) +
        (c.what == What::BoardAgain ? " of move " + std::to_string(c.row) : "") + " corrected): " + c.reason;
    for (int move = 1; move < r.engine.transmitterPositions(); ++move) {
      if (c.what == What::BoardAgain && c.row != move) continue;
      const BoardMoveFit was = fitBoardMove(r.engine.items(), move, r.settings.relocationToleranceMm);
      const BoardMoveFit now = fitBoardMove(after, move, r.settings.relocationToleranceMm);
      if (was.refusal || now.refusal)
        throw std::invalid_argument("with this correction the transmitter's move " + std::to_string(move) +
                                    " no longer fits (" + *(now.refusal ? now.refusal : was.refusal) +
                                    "): check the position, nothing was written");
      if (was.toFirst == now.toFirst) continue;  // a fit the correction leaves as it was: its points stay
      for (const Item& i : r.engine.items()) {
        if (!isStylusItem(i.what) || i.what == What::BoardAgain || i.frame != move) continue;
        Item moved = i;
        moved.flag.clear();
        moved.raw = fixed.raw;
        moved.positionMm =
            detail::replaced(detail::isometryOf(was.toFirst), detail::isometryOf(now.toFirst), i.positionMm);
        events.push_back(correctionEvent(i, moved, r.seqs.at(detail::keyOf(i)), because, c.who));
      }
    }
  }
  // Written only if nobody added to the session since it was replayed here.
  events.front().follows = r.totalEvents;
  (void)store.ensureOperator(c.who, "curator");
  return store.appendAll(id, events);
}

std::int64_t review(db::EventStore& store, std::int64_t id, const std::string& status, const std::string& given,
                    const std::string& why) {
  const std::string who = store.signature(given);  // through a login: the login that writes it
  const db::SessionInfo info = infoOrThrow(store, id);
  if (status != "approved" && status != "rejected")
    throw std::invalid_argument("a review approves or rejects, not '" + status + "'");
  if (detail::isBlank(who)) throw std::invalid_argument("a curator signs every review: give the curator's name");
  if (status == "rejected" && detail::isBlank(why))
    throw std::invalid_argument("say what is wrong when rejecting (--why)");
  if (info.status == "approved" || info.status == "rejected")
    throw std::invalid_argument("session " + std::to_string(id) + " is already " + info.status);
  if (info.status != "complete")
    throw std::invalid_argument("session " + std::to_string(id) + " is " + info.status +
                                ": only a complete session can be " + status);
  requireChain(store, id, "reviewed");
  (void)store.ensureOperator(who, "curator");
  return store.setStatus(id, status, who, why);
}

const std::vector<std::string>& exportFormats() {
  static const std::vector<std::string> formats{"glb", "obj", "ply", "stl", "model", "markers", "csv"};
  return formats;
}

model::MarkerSet sessionMarkers(const ReviewedSession& r) {
  return toMarkerSet(r.engine.items(), r.settings, leafInfoOf(r.info));
}

namespace {

// A leaf taken across a move of the transmitter: its points before and after stand in frames
// related by a fit with a residual, which the interval's draws add to the digitizer's noise
// (the largest move's RMS; the plant's full leaves follow the same rule, plant_export.cpp).
void widenForMoves(const Engine& engine, const model::LeafModel& leaf, model::LeafMetrics& metrics) {
  if (engine.transmitterPositions() < 2 || !metrics.areaInterval) return;
  double rms = 0;
  for (int r = 1; r < engine.transmitterPositions(); ++r) rms = std::max(rms, engine.fitOf(r).fitRmsMm);
  model::AreaUncertaintyOptions options;
  options.blade = leaf.blade.kind;
  options.sigmaMm = std::hypot(options.sigmaMm, rms);
  metrics.areaInterval = model::areaUncertainty(leaf.markers, options);
}

}  // namespace

std::string leafTransmitterPositionsJson(const Engine& engine, bool withItems) {
  json out = json::array();
  for (int p = 0; p < engine.transmitterPositions(); ++p) {
    json items = json::array();
    for (const Item& i : engine.items())
      if (isStylusItem(i.what) && i.what != What::BoardAgain && i.frame == p)
        items.push_back(
            {{"what", toString(i.what)}, {"row", detail::nullable(i.row)}, {"col", detail::nullable(i.col)}});
    json t{{"position", p + 1}, {"points", items.size()}};
    if (p > 0) {
      const Decision fit = engine.fitOf(p);
      t["rms_mm"] = fit.fitRmsMm;
      t["worst_mm"] = fit.fitWorstMm;
      t["worst_point"] = fit.fitWorstPoint;
      if (fit.kind == Decision::Kind::Rejected) t["refusal"] = fit.reason;
    }
    if (withItems) t["items"] = std::move(items);
    out.push_back(std::move(t));
  }
  return out.dump();
}

LeafSummary summarize(const ReviewedSession& r) {
  const model::MarkerSet set = sessionMarkers(r);
  LeafSummary s{model::buildLeafModel(set, {}), {}};
  s.metrics = model::computeLeafMetrics(s.model, Eigen::Vector3d(0, 0, 1), 5.0);
  widenForMoves(r.engine, s.model, s.metrics);
  // Silhouette and STAR of the mesh an export writes (model build's default resolution).
  model::addSilhouette(s.metrics, model::meshLeaf(s.model, model::MeshResolution::preset("export")));
  return s;
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
  const model::LeafMesh mesh = model::meshLeaf(leaf, meshOptions);
  ExportResult result;
  result.metrics = model::computeLeafMetrics(leaf, Eigen::Vector3d(0, 0, 1), 5.0);
  if (reviewed) widenForMoves(reviewed->engine, leaf, result.metrics);
  model::addSilhouette(result.metrics, mesh);
  result.rows = set.rows.size();
  const model::ExportHeader header{info.id, request.frame, std::string("leafdig ") + kVersion};
  std::vector<std::pair<std::string, std::string>> files;  // path, bytes
  for (const std::string& f : formats) {
    if (f == "glb" || f == "obj" || f == "ply" || f == "stl") {
      files.emplace_back(base + "." + f, model::encodeMesh(mesh, model::meshFormatForPath(base + "." + f), header));
    } else if (f == "model") {
      std::string text = model::modelToJson(leaf, request.frame, result.metrics);
      if (reviewed && reviewed->engine.transmitterPositions() > 1) {
        // Taken across a move of the transmitter: which points came from which position, and
        // each move's fit (a leaf taken from one position: the file as it always was).
        json doc = json::parse(text);
        doc["transmitter_positions"] = json::parse(leafTransmitterPositionsJson(reviewed->engine, true));
        text = doc.dump(1) + "\n";
      }
      files.emplace_back(base + ".model.json", text);
    } else if (f == "markers") {
      files.emplace_back(base + ".markers.json", model::markersToJson(set));
    } else if (f == "csv") {
      // From the verified events (the tables agree with them, or verify refused above).
      db::Projected items = db::project(store.events(id));
      if (!itemPrefix.empty()) keepLeafItems(items, itemPrefix);
      std::ostringstream mk, th;
      mk << std::setprecision(17) << "session,seq,what,row,col,x_mm,y_mm,z_mm\n";
      for (const auto& x : items.markers)
        mk << id << "," << x.seq << "," << x.what << "," << (x.row ? std::to_string(*x.row) : "") << ","
           << (x.col ? std::to_string(*x.col) : "") << "," << x.positionMm[0] << "," << x.positionMm[1] << ","
           << x.positionMm[2] << "\n";
      th << std::setprecision(17) << "session,seq,what,row,col,thickness_mm,raw\n";
      for (const auto& x : items.thickness)
        th << id << "," << x.seq << "," << x.what << "," << (x.row ? std::to_string(*x.row) : "") << ","
           << (x.col ? std::to_string(*x.col) : "") << "," << x.valueMm << "," << csvText(x.raw) << "\n";
      files.emplace_back(base + ".markers.csv", mk.str());
      files.emplace_back(base + ".thickness.csv", th.str());
      // The leaf's numbers in one row (a spreadsheet of many sessions: concatenate these).
      const model::LeafMetrics& lm = result.metrics;
      std::ostringstream me;
      me << std::setprecision(17);
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

OrganLibrary organLibrary(const db::EventStore& store) {
  OrganLibrary out;
  for (const db::SessionInfo& info : store.sessions()) {
    if (info.kind != "leaf" || info.status != "approved") continue;
    try {
      const ReviewedSession r = openForReview(store, info.id);
      model::MarkerSet set = sessionMarkers(r);
      (void)model::buildLeafModel(set, {});  // a whole, valid leaf, or it is not offered
      out.leaves.push_back({"session " + std::to_string(info.id), std::move(set)});
    } catch (const std::exception& e) {
      out.skipped.push_back("session " + std::to_string(info.id) + ": " + e.what());
    }
  }
  return out;
}

}  // namespace leafdig::acquisition
