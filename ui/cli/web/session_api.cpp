#include "session_api.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <stdexcept>
#include <vector>

#include "leafdig/acquisition/review/correction.hpp"
#include "leafdig/acquisition/review/leaf_export.hpp"
#include "leafdig/acquisition/review/plant_export.hpp"
#include "leafdig/acquisition/review/review.hpp"
#include "leafdig/acquisition/session/session_log.hpp"
#include "leafdig/model/errors.hpp"
#include "leafdig/model/mesh/mesh_method.hpp"
#include "leafdig/model/metrics/metrics.hpp"
#include "sessions_show.hpp"

namespace leafdig::cli::web::detail {

namespace acq = leafdig::acquisition;
using nlohmann::json;

HttpResponse jsonAnswer(int status, const json& body) {
  HttpResponse r;
  r.status = status;
  r.body = body.dump(-1, ' ', false, json::error_handler_t::replace);
  return r;
}

HttpResponse problem(int status, const std::string& error, const std::string& whatToDo) {
  return jsonAnswer(status, json{{"error", error}, {"what_to_do", whatToDo}});
}

std::optional<std::string> textField(const json& body, const char* key) {
  if (!body.contains(key) || !body.at(key).is_string()) return std::nullopt;
  return body.at(key).get<std::string>();
}

// A leaf's numbers for its curator: the metrics with the 95 % area interval (as `model build
// --json` gives them; null with the reason while the capture is not a whole leaf) and the
// flags the station's review shows.
HttpResponse leafReview(const db::EventStore& store, std::int64_t id) {
  if (store.session(id)->kind == acq::kPlantCapture.word)
    return problem(400, "a plant's numbers are its survey", "read GET /api/sessions/" + std::to_string(id));
  const acq::ReviewedSession r = acq::openForReview(store, id);
  json out{{"metrics", nullptr}, {"metrics_problem", nullptr}, {"flags", json::array()}};
  try {
    out["metrics"] = json::parse(model::metricsToJson(acq::summarize(r).metrics));
  } catch (const model::InputError& e) {
    out["metrics_problem"] = e.what();
  }
  for (const acq::ReviewFlag& f : acq::reviewFlags(r.engine.items()))
    out["flags"].push_back({{"what", acq::toString(f.what)}, {"row", f.row}, {"col", f.col}, {"text", f.text}});
  return jsonAnswer(200, out);
}

HttpResponse plantSurveys(const db::EventStore& store, std::int64_t id) {
  const std::optional<db::SessionInfo> info = store.session(id);
  if (info->kind != acq::kPlantCapture.word)
    return problem(400, "a leaf's session has no surveys", "ask a plant session's: GET /api/sessions?kind=plant");
  return jsonAnswer(200, plantSurveysJson(store, info->plant));
}

namespace {

// A whole number of a body, in range, or why not.
std::optional<std::int64_t> wholeField(const json& body, const char* key, std::int64_t low, std::int64_t high) {
  if (!body.contains(key) || !body.at(key).is_number_integer()) return std::nullopt;
  const std::int64_t v = body.at(key).get<std::int64_t>();
  return v < low || v > high ? std::nullopt : std::optional<std::int64_t>(v);
}

}  // namespace

// POST /api/sessions/ID/correct: one item corrected as `sessions correct` does it, with a
// dry run that says what it would change (the move, the areas, a plant's heights and lengths)
// and a write that refuses when the session moved on since the curator saw that
// (`seen_head`) or when the point moves further than kConfirmMoveAboveMm unconfirmed.
HttpResponse correction(db::EventStore& store, std::int64_t id, const json& body) {
  const auto fail = [](const std::string& what) {
    return problem(400, what,
                   "send {\"what\", \"row\", \"col\", \"position_mm\": [x, y, z] or \"value_mm\", \"why\", "
                   "\"dry_run\"?, \"seen_head\"?, \"confirm\"?, \"frame\"?} (docs/web.md)");
  };
  const auto word = textField(body, "what");
  const auto why = textField(body, "why");
  if (!word || word->empty() || word->size() > 64) return fail("a correction names its item (what)");
  if (!why || why->find_first_not_of(" \t\r\n") == std::string::npos || why->size() > kLongestReason)
    return fail("a correction needs a reason (why)");
  acq::Correction c;
  // A plant's full-leaf item as `sessions show` names it ("node3.marker") is node 3's "marker".
  std::string item = *word;
  int node = 0;
  if (const std::size_t dot = item.find('.'); item.rfind("node", 0) == 0 && dot != std::string::npos && dot > 4 &&
                                              item.find_first_not_of("0123456789", 4) == dot && dot - 4 <= 3) {
    node = std::stoi(item.substr(4, dot - 4));
    item = item.substr(dot + 1);
  }
  const std::optional<db::SessionInfo> info = store.session(id);
  if (info->status != "complete")
    return problem(409, "a " + info->status + " session takes no correction: only a complete one does",
                   info->status == "approved" || info->status == "rejected" ? "reopen it first, saying why"
                                                                            : "wait until its capture is complete");
  try {
    acq::setCorrectionItem(c, item, node);
  } catch (const std::invalid_argument& e) {
    return fail(e.what());
  }
  for (const char* key : {"row", "col"})
    if (body.contains(key) && !body.at(key).is_null()) {
      const auto v = wholeField(body, key, 0, 100000);
      if (!v) return fail(std::string(key) + " is a whole number from 0");
      (std::string(key) == "row" ? c.row : c.col) = static_cast<int>(*v);
    }
  if (body.contains("position_mm")) {
    const json& p = body.at("position_mm");
    if (!p.is_array() || p.size() != 3 || !std::all_of(p.begin(), p.end(), [](const json& v) {
          return v.is_number() && std::isfinite(v.get<double>()) && std::abs(v.get<double>()) < 1e6;
        }))
      return fail("position_mm is three finite numbers (mm)");
    c.positionMm = acq::Vec3{p[0].get<double>(), p[1].get<double>(), p[2].get<double>()};
  }
  if (body.contains("value_mm")) {
    const json& v = body.at("value_mm");
    if (!v.is_number() || !std::isfinite(v.get<double>())) return fail("value_mm is a finite number (mm)");
    c.valueMm = v.get<double>();
  }
  const bool plant = info->kind == acq::kPlantCapture.word;
  const std::string frame = textField(body, "frame").value_or(plant ? "plant" : "digitizer");
  if (frame != "plant" && frame != "digitizer") return fail("frame is plant or digitizer");
  c.frame = acq::positionFrameFromString(frame);
  c.reason = *why;
  c.who = store.signature("");
  const bool confirmed = body.contains("confirm") && body.at("confirm").is_boolean() && body.at("confirm").get<bool>();
  c.confirmAboveMm = confirmed ? std::numeric_limits<double>::infinity() : acq::kConfirmMoveAboveMm;
  if (body.contains("seen_head")) {
    const auto head = wholeField(body, "seen_head", 1, std::numeric_limits<std::int64_t>::max());
    if (!head) return fail("seen_head is the event number the dry run gave (head)");
    c.seenHead = *head;
  }
  const auto changesJson = [](const acq::CorrectionEffect& effect) {
    json a = json::array();
    for (const auto& ch : effect.changes) a.push_back({{"what", ch.what}, {"before", ch.before}, {"after", ch.after}});
    return a;
  };
  if (body.contains("dry_run") && body.at("dry_run").is_boolean() && body.at("dry_run").get<bool>()) {
    acq::Correction unguarded = c;
    unguarded.confirmAboveMm = std::numeric_limits<double>::infinity();
    acq::CorrectionEffect effect;
    try {
      effect = acq::previewCorrection(store, id, unguarded);
    } catch (const std::invalid_argument& e) {
      return fail(e.what());  // the item, its value or its frame (the session's state was checked above)
    }
    json out{{"dry_run", true},
             {"changes", changesJson(effect)},
             {"events", effect.events},
             {"head", effect.head},
             {"frame", acq::toString(c.frame)},
             {"moved_mm", effect.movedMm ? json(*effect.movedMm) : json(nullptr)},
             {"needs_confirm", effect.movedMm && *effect.movedMm > acq::kConfirmMoveAboveMm},
             {"confirm_above_mm", acq::kConfirmMoveAboveMm}};
    return jsonAnswer(200, out);
  }
  acq::CorrectionEffect effect;
  try {
    (void)acq::correct(store, id, c, &effect);
  } catch (const acq::UnconfirmedMove& e) {
    return jsonAnswer(409,
                      json{{"error", e.what()},
                           {"what_to_do", "check the position; if it is right, send it again with \"confirm\": true"},
                           {"moved_mm", e.moveMm()},
                           {"needs_confirm", true}});
  } catch (const std::invalid_argument& e) {
    return fail(e.what());
  }
  json out = sessionJson(store, id);
  out["changes"] = changesJson(effect);
  return jsonAnswer(200, out);
}

// A file of a session as `sessions export` writes it, one format per request: written into a
// directory of its own (the exporters write whole files atomically), read back, removed.
HttpResponse exportFile(db::EventStore& store, std::int64_t id, const HttpRequest& request) {
  const auto param = [&](const char* key, const std::string& otherwise) {
    const auto it = request.query.find(key);
    return it == request.query.end() ? otherwise : it->second;
  };
  const bool plant = store.session(id)->kind == acq::kPlantCapture.word;
  std::vector<std::string> formats = plant ? acq::plantExportFormats() : acq::exportFormats();
  if (plant)  // Helios and VegeSTAR too: one file each, asked for by name here as everywhere
    formats.insert(formats.end(), acq::plantRequestedFormats().begin(), acq::plantRequestedFormats().end());
  const std::string format = param("format", "");
  const std::string resolution = param("resolution", "export");
  const std::string frame = param("frame", "leaf");
  const auto join = [](const auto& words) {
    std::string out;
    for (const auto& w : words) out += (out.empty() ? "" : ", ") + std::string(w);
    return out;
  };
  if (std::find(formats.begin(), formats.end(), format) == formats.end())
    return problem(400, "no export format '" + format + "' for a " + (plant ? "plant" : "leaf"),
                   "give format= one of " + join(formats));
  if (std::find(model::kFileResolutionNames.begin(), model::kFileResolutionNames.end(), resolution) ==
      model::kFileResolutionNames.end())
    return problem(400, "no resolution '" + resolution + "'",
                   "give resolution= one of " + join(model::kFileResolutionNames));
  if (frame != "leaf" && frame != "digitizer")
    return problem(400, "no frame '" + frame + "'", "give frame=leaf or frame=digitizer (a leaf's files)");
  char dirTemplate[] = "/tmp/leafdig-web-XXXXXX";
  if (::mkdtemp(dirTemplate) == nullptr) throw std::runtime_error("cannot make a directory for an export in /tmp");
  const std::filesystem::path dir = dirTemplate;
  std::vector<std::string> written;
  try {
    if (plant) {
      written =
          acq::exportPlantSession(store, id, {format}, dir.string(), {resolution, model::OrganChoice::All}).written;
    } else {
      acq::ExportRequest r;
      r.formats = {format};
      r.resolution = resolution;
      r.frame = frame;
      r.outDir = dir.string();
      written = acq::exportSession(store, id, r).written;
    }
  } catch (...) {
    std::error_code ignored;
    std::filesystem::remove_all(dir, ignored);
    throw;
  }
  HttpResponse out;
  if (written.size() != 1) {
    out = problem(400, "format " + format + " writes " + std::to_string(written.size()) + " files",
                  "the web review gives one file per format: use leafdig sessions export for this one");
  } else {
    std::ifstream in(written.front(), std::ios::binary);
    out.body.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    const std::string name = std::filesystem::path(written.front()).filename().string();
    out.contentType = format == "glb"                                                  ? "model/gltf-binary"
                      : (format == "json" || format == "model" || format == "markers") ? "application/json"
                      : format == "xml"                                                ? "application/xml"
                                                                                       : "text/plain; charset=utf-8";
    out.headers.emplace_back("Content-Disposition", "attachment; filename=\"" + name + "\"");
  }
  std::error_code ignored;
  std::filesystem::remove_all(dir, ignored);
  return out;
}

}  // namespace leafdig::cli::web::detail
