// Capture pipeline benchmarks on a real SQLite file (WAL, synchronous=FULL): event commit
// latency, stylus release -> committed -> snapshot with the rebuilt preview, replay speed,
// and opening a database that holds 10 000 leaves. Results: docs/benchmarks.md.
//
// Latencies are reported as p50/p99 counters (milliseconds) over every operation timed.
#include <benchmark/benchmark.h>
#include <sqlite3.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <random>

#include "latency_counters.hpp"
#include "leafdig/acquisition/review/correction.hpp"
#include "leafdig/acquisition/review/plant_export.hpp"
#include "leafdig/acquisition/review/review.hpp"
#include "leafdig/acquisition/session/plant_preview.hpp"
#include "leafdig/acquisition/session/plant_session.hpp"
#include "leafdig/acquisition/session/session.hpp"
#include "leafdig/acquisition/sim/truth.hpp"
#include "leafdig/devices/links/reference.hpp"
#include "leafdig/devices/pose.hpp"
#include "leafdig/model/leaf/markers_json.hpp"
#include "leafdig/model/plant/plant_protocol.hpp"
#include "leafdig/model/study/synthetic_plant.hpp"

namespace {

namespace acq = leafdig::acquisition;
namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;
constexpr std::int64_t kMs = 1'000'000;

fs::path scratch(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("leafdig-bench-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  return dir / name;
}

const leafdig::model::MarkerSet& leaf() {
  static const auto l = leafdig::model::readMarkersFile(std::string(LEAFDIG_SOURCE_DIR) +
                                                        "/data/samples/upper-small-leaf-n17.markers.json");
  return l;
}

acq::Vec3 at(int row, int col) {
  const auto& p = leaf().rows[static_cast<std::size_t>(row - 1)].pointsMm[static_cast<std::size_t>(col - 1)];
  return {p.x(), p.y(), p.z()};
}

std::int64_t newSession(leafdig::db::Store& store, int position) {
  acq::SessionSetup s;
  s.project = "bench";
  s.plant = "p";
  s.leafPosition = position;
  return acq::CaptureSession::create(store, s);
}

// Stylus samples of one press on p; returns the release sample (not yet fed).
// `stillSamples` of 8 ms before the button goes down (a second tap of a double press comes
// sooner than the engine's 0.5 s double-tap window: 10).
acq::StylusInput feedPress(acq::CaptureSession& s, std::int64_t& t, const acq::Vec3& p, std::mt19937& rng,
                           int stillSamples = 70) {
  std::normal_distribution<double> n(0.0, 0.1);
  for (int i = 0; i < stillSamples; ++i)
    (void)s.onStylus({t += 8 * kMs, {p[0] + n(rng), p[1] + n(rng), p[2] + n(rng)}, false, "ok", "01 x"});
  for (int i = 0; i < 25; ++i)
    (void)s.onStylus({t += 8 * kMs, {p[0] + n(rng), p[1] + n(rng), p[2] + n(rng)}, true, "ok", "01 x"});
  return {t += 8 * kMs, p, false, "ok", "01   12.3  45.6  7.8"};
}

// One event with its projection, appended and made durable (fsync) per call.
void BM_EventCommit(benchmark::State& state) {
  const fs::path path = scratch("commit.sqlite");
  fs::remove(path);
  leafdig::db::Store store(path.string());
  const auto id = newSession(store, 1);
  std::vector<double> ms;
  int k = 0;
  for (auto _ : state) {
    leafdig::db::EventInput ev;
    ev.kind = "accepted";
    ev.payloadJson = R"({"what":"marker","row":3,"col":5,"position_mm":[1.234,5.678,9.012]})";
    ev.raw = "01   1.234   5.678   9.012";
    ev.monoNs = ++k;
    leafdig::db::Projection p;
    p.row = 3;
    p.col = 5;
    p.what = "marker";
    ev.projection = p;
    const auto t0 = Clock::now();
    benchmark::DoNotOptimize(store.append(id, ev));
    ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
  }
  (void)leafdig::bench::reportLatency(state, ms);
}
BENCHMARK(BM_EventCommit)->Iterations(400)->Unit(benchmark::kMillisecond);

// The stylus release that completes a point: decision, commit (fsync), snapshot with the
// preview model and mesh rebuilt from every marker so far.
void BM_PressToSnapshot(benchmark::State& state) {
  const fs::path path = scratch("press.sqlite");
  fs::remove(path);
  leafdig::db::Store store(path.string());
  std::mt19937 rng(5);
  int position = 0;
  std::unique_ptr<acq::CaptureSession> s;
  std::int64_t t = 0;
  std::vector<double> ms;
  std::size_t points = 0;
  for (auto _ : state) {
    state.PauseTiming();
    if (!s || s->engine().step().what != acq::What::Marker ||
        s->engine().step().row > static_cast<int>(leaf().rows.size())) {
      s = std::make_unique<acq::CaptureSession>(store, newSession(store, ++position));
      const auto& tip = leaf().tipMm;
      (void)s->onStylus(feedPress(*s, t, {tip.x(), tip.y(), tip.z()}, rng));
    }
    const acq::Step step = s->engine().step();
    const acq::StylusInput release = feedPress(*s, t, at(step.row, step.col), rng);
    state.ResumeTiming();
    const auto t0 = Clock::now();
    const auto feedback = s->onStylus(release);
    const acq::Snapshot snap = s->snapshot(true);
    ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
    if (feedback.empty() || feedback[0].kind != acq::Feedback::Kind::Accepted) {
      state.SkipWithError(
          ("press not accepted: " + (feedback.empty() ? std::string("no decision") : feedback[0].text)).c_str());
      break;
    }
    points = snap.items.size();
    benchmark::DoNotOptimize(snap.preview->mesh.organs.size());
  }
  (void)leafdig::bench::reportLatency(state, ms);
  state.counters["points_in_last_snapshot"] = static_cast<double>(points);
}
BENCHMARK(BM_PressToSnapshot)->Iterations(240)->Unit(benchmark::kMillisecond);

// The reference receiver's cost per stylus sample (issue 29): pairing a stylus record with its
// cycle's reference record and taking it into the reference's frame, on the driver's thread,
// for 2 000 cycles of a pot turning 30°. Reported per stylus sample, to set beside the record
// period (1/60 s with two FASTRAK receivers) and the press → snapshot p99 above.
void BM_ReferenceFramePerSample(benchmark::State& state) {
  constexpr int kCycles = 2000;
  constexpr double kRad = 3.14159265358979323846 / 180.0;
  std::vector<leafdig::devices::StylusSample> records;
  for (int i = 0; i < kCycles; ++i) {
    const double a = 30.0 * i / kCycles * kRad;
    leafdig::devices::StylusSample stylus, reference;
    stylus.station = 1;
    stylus.positionMm = {150.0 * std::cos(a), 150.0 * std::sin(a), 40.0};
    stylus.orientationDeg = leafdig::devices::Vec3{10, -45, 0};
    stylus.raw = "01   12.30  45.60   7.80  10.00 -45.00   0.00 0\r\n";
    reference.station = 2;
    reference.positionMm = {-110.0 * std::cos(a), -110.0 * std::sin(a), -40.0};
    reference.orientationDeg = leafdig::devices::Vec3{35.0 + 30.0 * i / kCycles, 12, -8};
    reference.raw = stylus.raw;
    records.push_back(stylus);
    records.push_back(reference);
  }
  std::vector<leafdig::devices::StylusSample> out;
  out.reserve(kCycles);
  for (auto _ : state) {
    leafdig::devices::ReferenceFrame frame;
    out.clear();
    for (const auto& r : records) frame.push(r, out);
    if (out.size() != kCycles) state.SkipWithError("a stylus sample was not delivered");
    benchmark::DoNotOptimize(out.data());
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) * kCycles);
  state.counters["time_per_stylus_sample"] = benchmark::Counter(
      static_cast<double>(kCycles), benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_ReferenceFramePerSample)->Unit(benchmark::kMicrosecond);

// A plant digitized where it stands (issue 28's target: a 20-node plant, press → committed →
// plant preview updated, p99 within one frame of 16.7 ms): a synthetic plant of
// LEAFDIG_BENCH_PLANT_NODES nodes (default 20; every third leaf and the largest in full, 10 rows
// each, the others quick) taken through a PlantCaptureSession on a real SQLite file, every
// stylus press and caliper reading timed from its last sample to the decision committed
// (fsync) and the plant's preview rebuilt from the engine (acquisition/session/plant_preview.hpp's
// PlantPreviewer, as the station's preview thread keeps one). `preview_` counters: the rebuild alone.
void BM_PlantPressToPreview(benchmark::State& state) {
  namespace m = leafdig::model;
  m::SyntheticPlantSpec spec;
  spec.nodes = 20;
  if (const char* e = std::getenv("LEAFDIG_BENCH_PLANT_NODES")) spec.nodes = std::clamp(std::atoi(e), 2, 60);
  spec.seed = 3;
  const m::PlantMarkers plant = m::synthesizePlant(spec).markers;
  std::vector<double> total, preview;
  int full = 0, presses = 0;
  for (auto _ : state) {
    const fs::path path = scratch("plant.sqlite");
    fs::remove(path);
    leafdig::db::Store store(path.string());
    acq::PlantSessionSetup setup;
    setup.project = "bench";
    setup.plant = plant.plant;
    acq::PlantCaptureSession s(store, acq::PlantCaptureSession::create(store, setup));
    acq::PlantPreviewer previewer;  // as the station's preview thread keeps it
    std::int64_t t = 0;
    std::mt19937 rng(7);
    std::normal_distribution<double> n(0.0, 0.1);
    // Every sample of a press but the release fed; the release is what is timed.
    const auto pressOn = [&](const acq::Vec3& p, int heldSamples) {
      for (int i = 0; i < 70; ++i)
        (void)s.onStylus({t += 8 * kMs, {p[0] + n(rng), p[1] + n(rng), p[2] + n(rng)}, false, "ok", "01"});
      for (int i = 0; i < heldSamples; ++i)
        (void)s.onStylus({t += 8 * kMs, {p[0] + n(rng), p[1] + n(rng), p[2] + n(rng)}, true, "ok", "01"});
      return acq::StylusInput{t += 8 * kMs, p, false, "ok", "01", false};
    };
    for (int guard = 0; guard < 20000 && !s.engine().complete(); ++guard) {
      const acq::PlantStep step = s.engine().step();
      if (step.what == acq::PlantWhat::Point && step.part == 1 && step.index <= static_cast<int>(plant.nodes.size())) {
        const acq::LeafChoice wanted = acq::plantChoiceTruth(plant, step.index);
        if (!(s.engine().choiceFor(step.index) == wanted)) (void)s.chooseLeaf(step.index, wanted, t);
      }
      const bool reading = step.what == acq::PlantWhat::CollarDiameter || step.what == acq::PlantWhat::Reading ||
                           (step.what == acq::PlantWhat::Leaf && !acq::isStylusItem(step.leaf.what));
      const std::optional<acq::Vec3> point = reading ? std::nullopt : acq::plantPointTruth(plant, step);
      const bool endRows = step.what == acq::PlantWhat::Leaf && step.leaf.what == acq::What::Marker &&
                           step.leaf.col == 1 &&
                           step.leaf.row > static_cast<int>(acq::plantLeafTruth(plant, step.index)->rows.size());
      acq::StylusInput release{};
      if (!reading) release = pressOn(point && !endRows ? *point : acq::Vec3{0, 0, 0}, point && !endRows ? 25 : 190);
      const auto t0 = Clock::now();
      const acq::PlantFeedback f =
          reading ? s.onCaliper({t += 500 * kMs, acq::plantReadingTruth(plant, step), "+1.0\r"}) : s.onStylus(release);
      const auto t1 = Clock::now();
      const acq::PlantPreview p = previewer.build(s.engine());
      const auto t2 = Clock::now();
      if (f.decision.kind == acq::PlantDecision::Kind::Rejected ||
          f.decision.kind == acq::PlantDecision::Kind::Ignored) {
        state.SkipWithError(
            ("the plant's technician was refused at " + s.engine().prompt() + ": " + f.decision.reason).c_str());
        return;
      }
      benchmark::DoNotOptimize(p.mesh.organs.size());
      total.push_back(std::chrono::duration<double, std::milli>(t2 - t0).count());
      preview.push_back(std::chrono::duration<double, std::milli>(t2 - t1).count());
      ++presses;
      full = p.leaves;
    }
    if (!s.engine().complete()) {
      state.SkipWithError("the plant was not completed");
      return;
    }
  }
  const auto p = leafdig::bench::reportLatency(state, total);
  (void)leafdig::bench::reportLatency(state, preview, "preview_");
  state.counters["frames_p99"] = p.p99 / (1000.0 / 60.0);
  state.counters["inputs"] = presses / static_cast<double>(state.iterations());
  state.counters["leaves_at_end"] = full;
  state.counters["nodes"] = spec.nodes;
}
BENCHMARK(BM_PlantPressToPreview)->Iterations(1)->Unit(benchmark::kMillisecond);

// A complete 17-row session's events read back and replayed through the engine.
void BM_Replay(benchmark::State& state) {
  const fs::path path = scratch("replay.sqlite");
  fs::remove(path);
  leafdig::db::Store store(path.string());
  const auto id = newSession(store, 1);
  {
    acq::CaptureSession s(store, id);
    std::mt19937 rng(9);
    std::int64_t t = 0;
    const auto& tip = leaf().tipMm;
    (void)s.onStylus(feedPress(s, t, {tip.x(), tip.y(), tip.z()}, rng));
    for (int r = 1; r <= static_cast<int>(leaf().rows.size()); ++r)
      for (int c = 1; c <= 7; ++c) (void)s.onStylus(feedPress(s, t, at(r, c), rng));
  }
  const auto events = store.events(id);
  const auto settings = acq::Settings{};
  for (auto _ : state) {
    const acq::Engine e = acq::CaptureSession::replay(settings, events);
    benchmark::DoNotOptimize(e.items().size());
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(events.size()));
  state.counters["events"] = static_cast<double>(events.size());
}
BENCHMARK(BM_Replay)->Unit(benchmark::kMicrosecond);

// A plant of N nodes replayed from its events (issue 47, 21: it grew with N², 37 s at 4 000
// nodes): three landmarks, the collar, then per node its point, its stem reading and "no leaf".
// The time per event must not grow with N.
std::vector<leafdig::db::Event> plantEvents(int nodes) {
  std::vector<leafdig::db::Event> events;
  const auto add = [&](const std::string& kind, const nlohmann::json& payload) {
    leafdig::db::Event e;
    e.seq = static_cast<std::int64_t>(events.size()) + 1;
    e.kind = kind;
    e.payloadJson = payload.dump();
    events.push_back(std::move(e));
  };
  const auto point = [&](const char* what, int row, int col, double x, double y, double z) {
    add("accepted", {{"what", what},
                     {"row", row > 0 ? nlohmann::json(row) : nlohmann::json(nullptr)},
                     {"col", col > 0 ? nlohmann::json(col) : nlohmann::json(nullptr)},
                     {"position_mm", {x, y, z}}});
  };
  for (int k = 1; k <= 3; ++k) point("landmark", k, 0, 100 * std::cos(2.0944 * k), 100 * std::sin(2.0944 * k), 20);
  add("landmarks_ended", nlohmann::json::object());
  point("collar", 0, 0, 0, 0, 0);
  add("accepted", {{"what", "collar_diameter"}, {"row", nullptr}, {"col", nullptr}, {"value_mm", 14.0}});
  for (int n = 1; n <= nodes; ++n) {
    point("point", n, 1, 0.01 * n, 0, 2.0 * n);
    add("accepted", {{"what", "reading"}, {"row", n}, {"col", 1}, {"value_mm", 10.0}});
    add("leaf_chosen", {{"node", n}, {"kind", "none"}, {"state", "alive"}});
  }
  return events;
}

void BM_PlantReplay(benchmark::State& state) {
  const std::vector<leafdig::db::Event> events = plantEvents(static_cast<int>(state.range(0)));
  acq::PlantSessionSetup setup;
  setup.protocol = leafdig::model::defaultPlantProtocol();
  for (auto _ : state) {
    const acq::PlantEngine e = acq::PlantCaptureSession::replay(setup, events);
    benchmark::DoNotOptimize(e.items().size());
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(events.size()));
  state.counters["events"] = static_cast<double>(events.size());
}
BENCHMARK(BM_PlantReplay)->Arg(250)->Arg(500)->Arg(1000)->Unit(benchmark::kMillisecond);

// The same plant read from a station's file as `sessions show` and `export` read it: the
// chain checked, the events replayed and the plant surveyed.
void BM_PlantSurveyFromFile(benchmark::State& state) {
  const int nodes = static_cast<int>(state.range(0));
  const fs::path path = scratch("plant-" + std::to_string(nodes) + ".sqlite");
  fs::remove(path);
  leafdig::db::Store store(path.string());
  nlohmann::json settings{{"kind", "plant"}, {"engine", nlohmann::json::object()}};
  settings["protocol"] =
      nlohmann::json::parse(leafdig::model::plantProtocolToJson(leafdig::model::defaultPlantProtocol()));
  const auto id =
      store.createPlantSession(store.ensurePlant(store.ensureProject("bench"), "P-big"), store.ensureOperator("bench"),
                               "bench", "standard", "sequential", settings.dump());
  std::vector<leafdig::db::EventInput> inputs;
  for (const auto& e : plantEvents(nodes)) inputs.push_back(leafdig::db::changeOf(e));
  (void)store.appendAll(id, inputs);
  for (auto _ : state) {
    const acq::CapturedSurvey s = acq::capturedSurvey(store, id);
    benchmark::DoNotOptimize(s.survey.nodes.size());
  }
  state.counters["events"] = static_cast<double>(inputs.size());
}
BENCHMARK(BM_PlantSurveyFromFile)
    ->Arg(250)
    ->Arg(500)
    ->Arg(1000)
    ->Arg(2000)
    ->Iterations(2)
    ->Unit(benchmark::kMillisecond);

// Reading a session from the file and replaying it: what `sessions resume` does.
void BM_ReadAndReplay(benchmark::State& state) {
  const fs::path path = scratch("replay.sqlite");
  leafdig::db::Store store(path.string());
  for (auto _ : state) {
    const acq::Engine e = acq::CaptureSession::replay({}, store.events(1));
    benchmark::DoNotOptimize(e.items().size());
  }
}
BENCHMARK(BM_ReadAndReplay)->Unit(benchmark::kMicrosecond);

// One complete, realistic session as a technician leaves it and a curator approves it: the
// tip and 17 rows (with the operator's rejected inputs), the end of the rows, every
// thickness reading (midrib and vein origin per row, the margin), a correction, approval.
void captureCompleteSession(leafdig::db::Store& store, int position) {
  const auto id = newSession(store, position);
  {
    acq::CaptureSession s(store, id);
    std::mt19937 rng(3);
    std::int64_t t = 0;
    const auto& tip = leaf().tipMm;
    (void)s.onStylus(feedPress(s, t, {tip.x(), tip.y(), tip.z()}, rng));
    for (int r = 1; r <= static_cast<int>(leaf().rows.size()); ++r) {
      for (int c = 1; c <= 7; ++c) (void)s.onStylus(feedPress(s, t, at(r, c), rng));
      if (r == 3) (void)s.onStylus(feedPress(s, t, at(r, 7), rng, 10));  // a double press, rejected
    }
    (void)s.endRows(t += 500 * kMs);
    for (int r = 1; r <= static_cast<int>(leaf().rows.size()); ++r) {
      (void)s.onCaliper({t += 900 * kMs, 1.4 - 0.04 * r, "+0001.38\r\n"});
      (void)s.onCaliper({t += 900 * kMs, 0.7 - 0.02 * r, "+0000.68\r\n"});
    }
    (void)s.onCaliper({t += 900 * kMs, 0.24, "+0000.24\r\n"});
    if (!s.snapshot(false).complete) {
      std::fprintf(stderr, "bench fixture: the session did not complete (%s)\n", s.snapshot(false).prompt.c_str());
      std::exit(1);
    }
  }
  acq::Correction c;
  c.what = acq::What::MidribThickness;
  c.row = 2;
  c.col = 4;
  c.valueMm = 1.31;
  c.reason = "re-measured at the station";
  c.who = "curator";
  (void)acq::correct(store, id, c);
  (void)acq::review(store, id, "approved", "curator", "checked");
}

// A station database of LEAFDIG_BENCH_LEAVES leaves (default 10 000), each holding a copy of
// that session (events, markers, thickness readings) copied with SQL: the copies' hash
// chains are not valid (opening a file does not verify chains). Built once per run.
fs::path bigDatabase(int leaves) {
  const fs::path path = scratch("station-" + std::to_string(leaves) + ".sqlite");
  if (fs::exists(path)) return path;
  {
    leafdig::db::Store store(path.string());
    captureCompleteSession(store, 1);
  }
  sqlite3* db = nullptr;
  sqlite3_open(path.c_str(), &db);
  const std::string n = std::to_string(leaves);
  const std::string sql =
      "PRAGMA synchronous=OFF; BEGIN;"
      "WITH RECURSIVE k(i) AS (SELECT 2 UNION ALL SELECT i+1 FROM k WHERE i<" +
      n +
      ") "
      "INSERT INTO leaves(id, plant_id, position) SELECT i, 1, i FROM k;"
      "INSERT INTO sessions(id, kind, plant_id, leaf_id, operator_id, station, status, mode, capture_order, "
      "settings_json, created_utc, "
      "genesis_hash, head_seq, head_hash) SELECT l.id, s.kind, s.plant_id, l.id, s.operator_id, s.station, s.status, "
      "s.mode, "
      "s.capture_order, "
      "s.settings_json, s.created_utc, s.genesis_hash, s.head_seq, s.head_hash FROM leaves l, sessions s WHERE s.id=1 "
      "AND l.id>1;"
      "INSERT INTO events SELECT x.id, e.seq, e.utc, e.mono_ns, e.kind, e.payload_json, e.raw, e.prev_hash, e.hash "
      "FROM sessions x, events e WHERE e.session_id=1 AND x.id>1;"
      "INSERT INTO markers SELECT x.id, m.seq, m.what, m.row, m.col, m.x_mm, m.y_mm, m.z_mm "
      "FROM sessions x, markers m WHERE m.session_id=1 AND x.id>1;"
      "INSERT INTO thickness_readings SELECT x.id, t.seq, t.what, t.row, t.col, t.value_mm, t.raw "
      "FROM sessions x, thickness_readings t WHERE t.session_id=1 AND x.id>1;"
      "COMMIT;";
  char* err = nullptr;
  if (sqlite3_exec(db, sql.c_str(), nullptr, nullptr, &err) != SQLITE_OK) {
    // A fixture that is not what the benchmark says would measure something else: stop.
    std::fprintf(stderr, "bench fixture: %s (the station file of %d leaves was not built)\n", err ? err : "?", leaves);
    sqlite3_free(err);
    sqlite3_close(db);
    fs::remove(path);
    std::exit(1);
  }
  sqlite3_close(db);
  return path;
}

int benchLeaves() {
  const char* e = std::getenv("LEAFDIG_BENCH_LEAVES");
  return e ? std::max(2, std::atoi(e)) : 10000;
}

// range(0) = 1: opened for capture (checks the pages capture touches); 0: read-only
// (review tools).
void BM_OpenStationDatabase(benchmark::State& state) {
  const fs::path path = bigDatabase(benchLeaves());
  for (auto _ : state) {
    leafdig::db::Store store(path.string(), state.range(0) == 0);
    benchmark::DoNotOptimize(store.schemaVersion());
  }
  state.SetLabel(state.range(0) ? "writer" : "read-only");
  state.counters["leaves"] = benchLeaves();
  state.counters["file_MB"] = static_cast<double>(fs::file_size(path)) / 1e6;
}
BENCHMARK(BM_OpenStationDatabase)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

// What `leafdig capture` and the station do before the first prompt of a new leaf: open the
// file for writing, create the session and open it (its chain verified, replayed).
void BM_OpenForANewCapture(benchmark::State& state) {
  const fs::path path = bigDatabase(benchLeaves());
  int position = 100000;
  for (auto _ : state) {
    leafdig::db::Store store(path.string());
    acq::CaptureSession session(store, newSession(store, ++position));
    benchmark::DoNotOptimize(session.snapshot(false).step);
  }
}
BENCHMARK(BM_OpenForANewCapture)->Unit(benchmark::kMillisecond);

// The full page check that `sessions verify` runs (and opening for capture no longer does).
void BM_CheckEveryPage(benchmark::State& state) {
  const fs::path path = bigDatabase(benchLeaves());
  leafdig::db::Store store(path.string(), true);
  for (auto _ : state) benchmark::DoNotOptimize(store.checkPages());
  state.counters["file_MB"] = static_cast<double>(fs::file_size(path)) / 1e6;
}
BENCHMARK(BM_CheckEveryPage)->Iterations(3)->Unit(benchmark::kMillisecond);

void BM_OpenAndListSessions(benchmark::State& state) {
  const fs::path path = bigDatabase(benchLeaves());
  std::size_t n = 0;
  for (auto _ : state) {
    leafdig::db::Store store(path.string(), true);
    n = store.sessions().size();
    benchmark::DoNotOptimize(n);
  }
  state.counters["sessions"] = static_cast<double>(n);
  // (at least: BM_OpenForANewCapture adds sessions to the same file)
  if (n < static_cast<std::size_t>(benchLeaves())) state.SkipWithError("the station file does not hold every leaf");
}
BENCHMARK(BM_OpenAndListSessions)->Unit(benchmark::kMillisecond);

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  std::error_code ec;
  fs::remove_all(fs::temp_directory_path() / ("leafdig-bench-" + std::to_string(::getpid())), ec);
  return 0;
}
