#include "sessions_cmd.hpp"

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <exception>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iomanip>
#include <iostream>
#include <limits>
#include <map>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <thread>

#include "capture/capture_console.hpp"
#include "commands.hpp"
#include "leafdig/acquisition/review/correction.hpp"
#include "leafdig/acquisition/review/leaf_export.hpp"
#include "leafdig/acquisition/review/plant_export.hpp"
#include "leafdig/acquisition/review/review.hpp"
#include "leafdig/acquisition/run/capture_run.hpp"
#include "leafdig/acquisition/session/plant_session.hpp"
#include "leafdig/acquisition/session/session.hpp"
#include "leafdig/acquisition/session/session_log.hpp"
#include "leafdig/db/history.hpp"
#include "leafdig/db/lab.hpp"
#include "leafdig/db/store.hpp"
#include "leafdig/model/errors.hpp"
#include "leafdig/model/files.hpp"
#include "leafdig/model/io/mesh_export.hpp"
#include "leafdig/model/io/model_json.hpp"
#include "leafdig/model/leaf/markers_json.hpp"
#include "leafdig/model/limits.hpp"
#include "leafdig/model/metrics/metrics.hpp"
#include "leafdig/model/plant/plant_survey.hpp"
#include "leafdig/model/synth/synthetic_leaf.hpp"
#include "leafdig/version.hpp"
#include "model/mesh_choice.hpp"
#include "plant/plant_cmd.hpp"
#include "sessions_show.hpp"
#include "terminal_text.hpp"

namespace leafdig::cli {
namespace {

namespace acq = leafdig::acquisition;
namespace m = leafdig::model;
using nlohmann::json;

int runList(const db::EventStore& store, const SessionsOptions& o) {
  std::vector<db::SessionInfo> sessions;
  for (auto& s : store.sessions())
    if (listed(s, o)) sessions.push_back(std::move(s));
  if (o.json) {
    std::cout << sessionListJson(store, sessions).dump() << "\n";
    return 0;
  }
  // On the lab server each session also carries its station and the id it has there.
  const bool server = db::isServerUrl(o.db);
  // Columns as wide as their longest cell (a long project or plant name never runs into the
  // operator's), counted in characters, not UTF-8 bytes.
  std::vector<std::vector<std::string>> rows{
      {"id", server ? "station:id" : "", "status", "leaf", "operator", "events", "created (UTC)"}};
  for (const auto& s : sessions)
    rows.push_back({std::to_string(s.id),
                    server ? terminalText(s.station + ":" + std::to_string(s.stationSessionId)) : "",
                    terminalText(s.status),
                    terminalText(s.project + "/" + s.plant + "/" +
                                 (s.kind == "leaf" ? std::to_string(s.leafPosition) : std::string("(plant)"))),
                    terminalText(s.operatorName), std::to_string(s.headSeq), terminalText(s.createdUtc)});
  const auto width = [](const std::string& t) {
    return static_cast<std::size_t>(std::count_if(t.begin(), t.end(), [](char c) { return (c & 0xC0) != 0x80; }));
  };
  std::vector<std::size_t> widths(rows.front().size(), 0);
  for (const auto& r : rows)
    for (std::size_t c = 0; c < r.size(); ++c) widths[c] = std::max(widths[c], width(r[c]));
  for (const auto& r : rows) {
    std::string line;
    for (std::size_t c = 0; c < r.size(); ++c) {
      if (c == 1 && !server) continue;
      line += r[c];
      if (c + 1 < r.size()) line += std::string(widths[c] - width(r[c]) + 2, ' ');
    }
    std::cout << line << "\n";
  }
  if (sessions.empty())
    std::cout << "(no sessions"
              << (o.status.empty() && o.kind.empty() && o.plant.empty() && o.station.empty() && o.since.empty()
                      ? ""
                      : " that match")
              << " in " << terminalText(store.describe()) << ")\n";
  return 0;
}

int runVerify(const db::EventStore& store, const SessionsOptions& o) {
  std::vector<std::int64_t> ids;
  const bool all = o.all || o.id == 0;
  if (all)
    for (const auto& s : store.sessions()) ids.push_back(s.id);
  else
    ids.push_back(o.id);
  bool ok = true;
  json a = json::array();
  for (const auto id : ids) {
    db::ChainReport c;
    try {
      c = store.verify(id);
    } catch (const db::StoreError& e) {  // a damaged page under this session's events
      c.ok = false;
      c.problem = e.what();
    }
    ok = ok && c.ok;
    if (o.json)
      a.push_back({{"session", id},
                   {"chain_ok", c.ok},
                   {"events", c.events},
                   {"first_bad_seq", c.firstBadSeq ? json(*c.firstBadSeq) : json(nullptr)},
                   {"problem", c.problem},
                   {"genesis_form", c.genesisForm}});
    else
      std::cout << "session " << id << ": " << c.events << " events, "
                << (c.ok ? "chain OK"
                         : "CHAIN BROKEN at event " + std::to_string(c.firstBadSeq.value_or(0)) + ": " +
                               terminalText(c.problem))
                << (c.ok && c.genesisForm < 2
                        ? " (written before the station was in the chain: its station id is not covered)"
                        : "")
                << "\n";
  }
  // Every page of a station's file as well (opening for capture checks only what capture
  // touches); the lab server checks its own pages.
  const auto* file = dynamic_cast<const db::Store*>(&store);
  if (all && file) {
    const std::string pages = file->checkPages();
    if (pages != "ok") {
      ok = false;
      std::cerr << "leafdig: " << file->path() << " has damaged pages (" << pages
                << "): restore it from a backup; the file was not modified\n";
    } else if (!o.json) {
      std::cout << "pages: every page of " << file->path() << " checked, OK\n";
    }
  }
  if (o.json) std::cout << a.dump() << "\n";
  return ok ? 0 : 1;
}

// Who signs a review: in a station's file, --who; on the lab server, the login, or "--who
// (login)" (EventStore::signature; the server refuses any other signature: lab schema 11).
std::string signer(const db::EventStore& store, const std::string& who) {
  if (!store.login() && who.find_first_not_of(" \t\r\n\v\f") == std::string::npos)
    throw std::invalid_argument("a curator signs every review of a station's file: give --who NAME");
  return store.signature(who);
}

int runReview(db::EventStore& store, SessionsOptions o, const std::string& status) {
  o.who = signer(store, o.who);
  const auto seq = acq::review(store, o.id, status, o.who, o.why);
  if (o.json)
    std::cout << json{{"session", o.id}, {"status", status}, {"seq", seq}, {"who", o.who}}.dump() << "\n";
  else
    std::cout << "session " << o.id << " " << status << " by " << terminalText(o.who) << " (event " << seq << ")\n";
  return 0;
}

int runReopen(db::EventStore& store, SessionsOptions o) {
  o.who = signer(store, o.who);
  const auto was = store.session(o.id);
  const auto seq = acq::reopen(store, o.id, o.who, o.why);
  const std::string reopened = was ? was->status : std::string();
  if (o.json)
    std::cout
        << json{{"session", o.id}, {"status", "complete"}, {"reopens", reopened}, {"seq", seq}, {"who", o.who}}.dump()
        << "\n";
  else
    std::cout << "session " << o.id << " reopened by " << terminalText(o.who) << " (event " << seq << "): it was "
              << terminalText(reopened) << ", it is complete again — correct it, then approve or reject it\n";
  return 0;
}

int runCorrect(db::EventStore& store, SessionsOptions o) {
  o.who = signer(store, o.who);
  acq::Correction c;
  acq::setCorrectionItem(c, o.what, o.node);  // --what and --node
  c.row = o.row;
  c.col = o.col;
  c.reason = o.why;
  c.who = o.who;
  if (!o.position.empty()) {
    if (o.position.size() != 3) throw std::invalid_argument("--position takes x,y,z in mm");
    c.positionMm = acq::Vec3{o.position[0], o.position[1], o.position[2]};
  }
  if (o.value) c.valueMm = *o.value;
  c.confirmAboveMm = o.confirm ? std::numeric_limits<double>::infinity() : o.confirmAboveMm;
  const auto info = store.session(o.id);
  // A plant's points are read in the plant frame (exports, the survey): corrected in it too unless
  // told; a leaf's are the digitizer's.
  c.frame = !o.positionFrame.empty()        ? acq::positionFrameFromString(o.positionFrame)
            : info && info->kind == "plant" ? acq::PositionFrame::Plant
                                            : acq::PositionFrame::Digitizer;
  // What it changes, worked out before anything is written (any move: the guard is said below).
  acq::Correction unguarded = c;
  unguarded.confirmAboveMm = std::numeric_limits<double>::infinity();
  // A dry run says what the correction would change; the write works it out from the same single
  // read of the session it writes against (another curator's write in between: the store's
  // "moved on", nothing written).
  acq::CorrectionEffect effect;
  if (o.dryRun) effect = acq::previewCorrection(store, o.id, unguarded);
  const bool needsConfirm = effect.movedMm && *effect.movedMm > c.confirmAboveMm;
  const auto changesJson = [&effect] {
    json a = json::array();
    for (const auto& ch : effect.changes) a.push_back({{"what", ch.what}, {"before", ch.before}, {"after", ch.after}});
    return a;
  };
  const auto printChanges = [&effect] {
    for (const auto& ch : effect.changes) {
      std::cout << "  " << ch.what << ": " << std::fixed << std::setprecision(1) << ch.before << " → " << ch.after;
      if (ch.before != 0) std::cout << " (" << std::showpos << 100.0 * (ch.after - ch.before) / ch.before << " %)";
      std::cout << std::noshowpos << std::defaultfloat << "\n";
    }
  };
  if (o.dryRun) {
    if (o.json) {
      json j{{"session", o.id},          {"dry_run", true},         {"what", o.what},
             {"changes", changesJson()}, {"events", effect.events}, {"needs_confirm", needsConfirm}};
      if (effect.movedMm) j["moved_mm"] = *effect.movedMm;
      if (c.positionMm) j["frame"] = acq::toString(c.frame);
      std::cout << j.dump() << "\n";
    } else {
      std::cout << "session " << o.id << ": " << terminalText(o.what) << " would be corrected";
      if (effect.movedMm)
        std::cout << ", moving " << std::fixed << std::setprecision(1) << *effect.movedMm << " mm" << std::defaultfloat;
      if (effect.events > 1) std::cout << " (" << effect.events - 1 << " more points placed again by a refitted move)";
      std::cout << "; nothing written (--dry-run)\n";
      printChanges();
      if (needsConfirm)
        std::cout << "  more than the " << std::fixed << std::setprecision(1) << c.confirmAboveMm << std::defaultfloat
                  << " mm a correction moves unconfirmed: writing it needs --confirm\n";
    }
    return 0;
  }
  const std::int64_t head = info ? info->headSeq : 0;
  const auto seq = acq::correct(store, o.id, c, &effect);
  // What the correction changed, as the history says it: the first event it wrote is the item's
  // (the others, points a refitted move placed again).
  std::optional<db::ReviewEntry> done;
  for (const auto& r : db::reviewHistory(store.events(o.id, head + 1)))
    if (r.action == "corrected" && !done) done = r;
  if (o.json) {
    json j{{"session", o.id}, {"corrected", o.what}, {"seq", seq}, {"who", o.who}, {"changes", changesJson()}};
    if (c.positionMm) j["frame"] = acq::toString(c.frame);
    if (done)
      if (const auto moved = done->movedMm()) j["moved_mm"] = *moved;
    std::cout << j.dump() << "\n";
  } else {
    std::cout << "session " << o.id << ": " << terminalText(o.what) << " corrected by " << terminalText(o.who)
              << " (event " << seq << ")";
    if (done)
      if (const auto moved = done->movedMm())
        std::cout << ", moved " << std::fixed << std::setprecision(1) << *moved << " mm" << std::defaultfloat;
    if (c.positionMm && c.frame == acq::PositionFrame::Plant) std::cout << " (position given in the plant frame)";
    std::cout << "\n";
    printChanges();
  }
  return 0;
}

}  // namespace

int runExport(db::EventStore& store, const SessionsOptions& o) {
  const auto info = store.session(o.id);
  // Files of a session no curator approved say so where the person exporting sees it (issue 49).
  const auto warnIfUnapproved = [&] {
    if (!info || info->status == "approved" || !o.warnUnapproved) return;
    std::cerr << "leafdig: warning: session " << o.id << " is " << terminalText(info->status)
              << ", not approved by a curator: its numbers are as captured, unchecked (leafdig sessions show " << o.id
              << ")\n";
  };
  if (info && info->kind == "plant" && o.node == 0) {
    const acq::PlantExport p =
        acq::exportPlantSession(store, o.id, o.formats, o.out, {o.resolution, model::organChoiceFromString(o.organs)});
    if (o.json) {
      std::cout << json{{"session", o.id},
                        {"kind", "plant"},
                        {"status", info->status},
                        {"outputs", p.written},
                        {"notes", p.notes}}
                       .dump()
                << "\n";
    } else {
      std::cout << "plant session " << o.id << ": " << p.survey.nodes.size() << " nodes, " << p.survey.leaves.size()
                << " leaves\n";
      for (const auto& f : p.written) std::cout << "  wrote " << terminalText(f) << "\n";
      for (const auto& n : p.notes) std::cout << "  note: " << terminalText(n) << "\n";
    }
    warnIfUnapproved();
    return 0;
  }
  acq::ExportRequest request;
  request.formats = o.formats;
  request.frame = o.frame;
  request.blade = o.blade;
  request.resolution = o.resolution;
  request.organs = model::organChoiceFromString(o.organs);
  request.outDir = o.out;
  if (o.node != 0) request.node = o.node;
  const acq::ExportResult r = acq::exportSession(store, o.id, request);
  if (o.json) {
    std::cout << json{{"session", o.id},
                      {"status", info ? json(info->status) : json(nullptr)},
                      {"outputs", r.written},
                      {"metrics", json::parse(m::metricsToJson(r.metrics))}}
                     .dump()
              << "\n";
  } else {
    std::cout << "session " << o.id << ": " << r.rows << " rows, blade area " << std::fixed << std::setprecision(0)
              << r.metrics.blade.areaMm2 << " mm^2\n";
    for (const auto& p : r.written) std::cout << "  wrote " << terminalText(p) << "\n";
  }
  warnIfUnapproved();
  return 0;
}

namespace {

// Runs a `sessions` command on the store of --db (read-only unless it writes).
template <class Run>
int withStore(const SessionsOptions& o, bool writes, Run run) {
  const std::string path = stationDbPath(o.db);
  if (!db::isServerUrl(o.db) && !std::filesystem::exists(path))
    throw std::invalid_argument("no database at " + db::redactUrl(path) +
                                ": give --db FILE (capture creates one), or the lab server as postgresql://…");
  const std::unique_ptr<db::EventStore> store = db::openEventStore(path, !writes);
  return run(*store, o);
}

}  // namespace

CLI::App* addSessionsCommands(CLI::App& app, CommandTable& table) {
  auto o = std::make_shared<SessionsOptions>();
  CLI::App* sessions = app.add_subcommand("sessions", "List, inspect, verify, resume, review and export sessions");
  sessions->require_subcommand(1);
  CLI::App* list = sessions->add_subcommand("list", "All sessions in the database");
  CLI::App* show = sessions->add_subcommand("show", "One session: step, markers, readings, chain");
  CLI::App* verify = sessions->add_subcommand("verify", "Recompute the hash chain of a session (or all)");
  CLI::App* resume = sessions->add_subcommand("resume", "Continue an open session at its exact step");
  CLI::App* approve = sessions->add_subcommand("approve", "Curator: approve a complete session");
  CLI::App* reject = sessions->add_subcommand("reject", "Curator: reject a session, saying why");
  CLI::App* reopen = sessions->add_subcommand(
      "reopen", "Curator: reopen an approved or rejected session, saying why (it is complete again)");
  CLI::App* corr = sessions->add_subcommand("correct", "Curator: correct one marker or reading, saying why");
  CLI::App* exp = sessions->add_subcommand("export", "Export a session's leaf: meshes, model, markers, CSV");
  for (CLI::App* c : {list, show, verify, approve, reject, reopen, corr, exp}) {
    c->add_option("--db", o->db,
                  "SQLite file (default: the station's), or the lab server's postgresql:// URL (docs/lab.md)");
    c->add_flag("--json", o->json, "JSON output");
  }
  for (CLI::App* c : {show, approve, reject, reopen, corr, exp}) c->add_option("id", o->id, "Session id")->required();
  list->add_option("--status", o->status, "Only sessions of this status")
      ->check(CLI::IsMember(std::vector<std::string>(db::kSessionStatuses.begin(), db::kSessionStatuses.end())));
  list->add_option("--kind", o->kind, "Only leaves or only plants")
      ->check(CLI::IsMember(
          std::vector<std::string>{std::string(acq::kLeafCapture.word), std::string(acq::kPlantCapture.word)}));
  list->add_option("--plant", o->plant, "Only this plant's sessions");
  list->add_option("--station", o->station, "Only the sessions this station captured");
  list->add_option("--since", o->since, "Only sessions created on this day (YYYY-MM-DD, UTC) or later")
      ->check([](const std::string& day) {
        // Checked by hand: GCC 12's <regex> trips -Werror=maybe-uninitialized at -O2 (CI's ci build).
        bool isDay = day.size() == 10;
        for (std::size_t i = 0; isDay && i < day.size(); ++i)
          isDay = (i == 4 || i == 7) ? day[i] == '-' : (day[i] >= '0' && day[i] <= '9');
        return isDay ? std::string() : std::string("give a day as YYYY-MM-DD");
      });
  corr->add_option("--what", o->what,
                   "A leaf's board, board_again, tip, marker, midrib_thickness, vein_origin_thickness, "
                   "point_thickness, edge_thickness; a plant's landmark, landmark_again, collar, collar_diameter, "
                   "point, reading, quick_point (a board point or landmark after a move of the transmitter moves the "
                   "points of that move with it)")
      ->required();
  // 1-based when given (issue 47: --col 0 used to correct column 1); left out where none applies.
  corr->add_option("--row", o->row,
                   "Row (1-based; where it applies; board_again: the move); a plant's landmark or node number")
      ->check(CLI::Range(1, 100000));
  corr->add_option("--col", o->col,
                   "Column (1-based; where it applies; board: the board point); a plant item's part "
                   "(landmark_again: the move)")
      ->check(CLI::Range(1, 100000));
  corr->add_option("--node", o->node, "A plant session: the node whose full leaf holds the item");
  corr->add_option("--position", o->position, "Corrected marker position x,y,z in mm")->delimiter(',')->expected(3);
  corr->add_option("--value", o->value, "Corrected thickness (a plant: stem diameter) in mm");
  corr->add_option("--who", o->who,
                   "Curator's name (on the lab server stored as \"NAME (login)\"; left out: the login)");
  corr->add_option("--why", o->why, "Reason")->required();
  corr->add_flag("--confirm", o->confirm, "The point is to move further than --confirm-above: it is meant");
  corr->add_flag("--dry-run", o->dryRun,
                 "Show what the correction would change (the point's move, areas, heights, lengths) and write "
                 "nothing");
  corr->add_option("--frame", o->positionFrame,
                   "The frame of --position: plant (a plant session's default: as exports and the survey give it) "
                   "or digitizer (a leaf session's only frame)")
      ->check(CLI::IsMember({"plant", "digitizer"}));
  corr->add_option("--confirm-above", o->confirmAboveMm,
                   "A point that would move further than this many mm needs --confirm (default 20)")
      ->check(CLI::Range(0.0, 100000.0));
  verify->add_option("id", o->id, "Session id (default: all)");
  verify->add_flag("--all", o->all, "Every session");
  for (CLI::App* c : {approve, reject}) {
    c->add_option("--who", o->who,
                  "Curator's name (on the lab server stored as \"NAME (login)\"; left out: the login)");
    c->add_option("--why", o->why, "Reason (required to reject)");
  }
  reopen->add_option("--who", o->who,
                     "Curator's name (on the lab server stored as \"NAME (login)\"; left out: the login)");
  reopen->add_option("--why", o->why, "Why the decision no longer stands")->required();
  exp->add_option("--out", o->out, "Directory to write into")->required();
  exp->add_option("--format", o->formats,
                  "glb, obj, ply, stl, model, markers, csv (default: all); a plant session: mtg, csv, markers, json, "
                  "glb, obj, ply, stl, can, model, plan (default: all of these), xml (Helios), vgx (VegeSTAR)")
      ->delimiter(',');
  exp->add_option("--node", o->node,
                  "A plant session's full leaf alone, the one at this node (the leaf's formats: glb, obj, ply, stl, "
                  "model, markers, csv)")
      ->check(CLI::Range(1, 9999));
  exp->add_option("--frame", o->frame, "leaf (default) or digitizer")->check(CLI::IsMember({"leaf", "digitizer"}));
  exp->add_option("--blade", o->blade, "interp (default), approx, bezier, nurbs")
      ->check(CLI::IsMember(wordsIn(model::kBladeKindNames)));
  exp->add_option("--resolution", o->resolution, kFileResolutionHelp)->check(CLI::IsMember(fileResolutionWords()));
  exp->add_option("--organs", o->organs, kOrgansHelp)->check(CLI::IsMember(wordsIn(model::kOrganChoiceNames)));
  table.add(list, [o] { return withStore(*o, false, runList); });
  table.add(show, [o] { return withStore(*o, false, runShow); });
  table.add(verify, [o] { return withStore(*o, false, runVerify); });
  table.add(approve, [o] {
    return withStore(*o, true,
                     [](db::EventStore& store, const SessionsOptions& c) { return runReview(store, c, "approved"); });
  });
  table.add(reject, [o] {
    return withStore(*o, true,
                     [](db::EventStore& store, const SessionsOptions& c) { return runReview(store, c, "rejected"); });
  });
  table.add(reopen, [o] { return withStore(*o, true, runReopen); });
  table.add(corr, [o] { return withStore(*o, true, runCorrect); });
  table.add(
      exp, [o] { return withStore(*o, true, runExport); }, "cannot export: ");
  return resume;
}

}  // namespace leafdig::cli
