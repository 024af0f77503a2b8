#include "leafdig/acquisition/review/review.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <sstream>
#include <stdexcept>
#include <variant>

#include "leafdig/acquisition/session/plant_session.hpp"
#include "leafdig/acquisition/session/preview.hpp"
#include "leafdig/model/files.hpp"
#include "leafdig/model/io/csv_text.hpp"
#include "leafdig/model/io/mesh_export.hpp"
#include "leafdig/model/io/model_json.hpp"
#include "leafdig/model/leaf/markers_json.hpp"
#include "leafdig/model/limits.hpp"
#include "leafdig/version.hpp"
#include "protocol/item_json.hpp"
#include "protocol/rigid_map.hpp"
#include "review_checks.hpp"

namespace leafdig::acquisition {
namespace {

using detail::requireChain;
using nlohmann::json;

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

namespace {

ReviewedSession replayed(db::SessionInfo info, std::vector<db::Event> events, std::int64_t upToSeq) {
  ReviewedSession r{std::move(info), {}, Engine{}, {}, 0, 0};
  if (r.info.kind != "leaf")
    throw SessionError("session " + std::to_string(r.info.id) +
                       " captured a whole plant, not one leaf: `leafdig sessions export " + std::to_string(r.info.id) +
                       "` writes its files (`--node K` one full leaf's)");
  r.settings = CaptureSession::settingsFromJson(r.info.settingsJson);
  r.totalEvents = static_cast<std::int64_t>(events.size());
  if (upToSeq > 0) {
    events.erase(std::remove_if(events.begin(), events.end(), [&](const db::Event& e) { return e.seq > upToSeq; }),
                 events.end());
  }
  r.replayedEvents = static_cast<std::int64_t>(events.size());
  r.engine = CaptureSession::replay(r.settings, events, &r.seqs);
  return r;
}

}  // namespace

ReviewedSession openForReview(const db::EventStore& store, std::int64_t id, std::int64_t upToSeq) {
  db::SessionInfo info = detail::infoOrThrow(store, id);
  if (info.kind != "leaf") return replayed(std::move(info), {}, 0);  // the words a plant gets
  return replayed(std::move(info), store.events(id), upToSeq);
}

ReviewedSession reviewedFrom(db::SessionInfo info, const std::vector<db::Event>& events) {
  return replayed(std::move(info), events, 0);
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

std::int64_t review(db::EventStore& store, std::int64_t id, const std::string& status, const std::string& given,
                    const std::string& why) {
  const std::string who = store.signature(given);  // through a login: the login that writes it
  const db::SessionInfo info = detail::infoOrThrow(store, id);
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

std::int64_t reopen(db::EventStore& store, std::int64_t id, const std::string& given, const std::string& why) {
  const std::string who = store.signature(given);  // through a login: the login that writes it
  const db::SessionInfo info = detail::infoOrThrow(store, id);
  if (detail::isBlank(who)) throw std::invalid_argument("a curator signs every reopening: give the curator's name");
  if (detail::isBlank(why)) throw std::invalid_argument("say why the session is reopened (--why)");
  if (info.status != "approved" && info.status != "rejected")
    throw std::invalid_argument("session " + std::to_string(id) + " is " + info.status +
                                ": only an approved or rejected session is reopened");
  requireChain(store, id, "reopened");
  (void)store.ensureOperator(who, "curator");
  db::EventInput ev;
  ev.kind = "status";
  ev.payloadJson = json{{"status", "complete"}, {"who", who}, {"why", why}, {"reopens", info.status}}.dump();
  ev.setsStatus = "complete";
  ev.follows = info.headSeq;  // the decision it reopens is still the last event
  return store.appendAll(id, {ev});
}

model::MarkerSet sessionMarkers(const ReviewedSession& r) {
  return toMarkerSet(r.engine.items(), r.settings, leafInfoOf(r.info));
}

std::optional<FieldApplied> sessionField(const db::SessionInfo& info) {
  try {
    return fieldAppliedFromSettings(info.settingsJson, "session " + std::to_string(info.id));
  } catch (const model::InputError& e) {
    throw SessionError(e.what());
  }
}

std::optional<TipApplied> sessionTip(const db::SessionInfo& info) {
  try {
    return tipAppliedFromSettings(info.settingsJson, "session " + std::to_string(info.id));
  } catch (const model::InputError& e) {
    throw SessionError(e.what());
  }
}

void widenForCapture(const ReviewedSession& r, const model::LeafModel& leaf, model::LeafMetrics& metrics) {
  const Engine& engine = r.engine;
  const std::optional<FieldApplied> field = sessionField(r.info);
  if ((engine.transmitterPositions() < 2 && !field) || !metrics.areaInterval) return;
  double rms = 0;
  for (int p = 1; p < engine.transmitterPositions(); ++p) rms = std::max(rms, engine.fitOf(p).fitRmsMm);
  model::AreaUncertaintyOptions options;
  options.blade = leaf.blade.kind;
  options.sigmaMm = std::hypot(options.sigmaMm, rms);
  if (field) options.sigmaMm = std::hypot(options.sigmaMm, field->holdoutRmsMm);
  metrics.areaInterval = model::areaUncertainty(leaf.markers, options);
}

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
  widenForCapture(r, s.model, s.metrics);
  // Silhouette and STAR of the mesh an export writes (model build's default resolution).
  model::addSilhouette(s.metrics, model::meshLeaf(s.model, model::MeshResolution::preset("export")));
  return s;
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
