// Station preview benchmarks, on a real window with real OpenGL (run under Xvfb with Mesa's
// llvmpipe in CI; any X display otherwise). Results and the command: docs/benchmarks.md.
//
//  - PreviewFrame: one frame of the live 3D preview on screen (update → paintGL → swap) with
//    a whole sample leaf meshed at the `export` resolution. Budget 16 ms.
//  - SnapshotToScreen: a snapshot handed to the preview on the UI thread (a queued call) until
//    the frame showing it has been swapped: upload + paint + swap. Budget: one frame (16.7 ms
//    at 60 Hz). The station window itself now takes snapshots from its locked slot every 5 ms
//    (StationWindow::takeSnapshot), which this does not include: up to 5 ms more.
//  - StartUp: `leafdig-station --simulate --quit-after-first-frame` from spawn to its first
//    preview frame on screen (the station prints the steady clock then). Budget 1 s.
//
// Latencies are per operation, reported as p50/p99/max counters in milliseconds, with the
// budget as a ratio (`p99_per_budget` ≤ 1 meets it).
#include <benchmark/benchmark.h>
#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <QApplication>
#include <QEventLoop>
#include <QMetaObject>
#include <QOpenGLContext>
#include <QTimer>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "latency_counters.hpp"
#include "leafdig/model/leaf/markers_json.hpp"
#include "leafdig/model/mesh/mesh_method.hpp"
#include "preview/preview_widget.hpp"

namespace {

namespace acq = leafdig::acquisition;
namespace m = leafdig::model;
namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

constexpr double kFrameBudgetMs = 16.0;
constexpr double kSixtyHzFrameMs = 1000.0 / 60.0;
constexpr double kStartUpBudgetMs = 1000.0;
constexpr int kPreviewWidth = 1024, kPreviewHeight = 768;

const char* const kSamples[] = {"lower-leaf-n10.markers.json", "upper-curved-leaf-n14.markers.json",
                                "upper-small-leaf-n17.markers.json"};

// A benchmark that could not measure what it claims fails the run (exit 1), so the CI smoke
// pass catches a blank preview or a station that never shows a frame.
bool g_failed = false;
void fail(benchmark::State& state, const std::string& why) {
  g_failed = true;
  state.SkipWithError(why.c_str());
}

double ms(Clock::duration d) {
  return std::chrono::duration<double, std::milli>(d).count();
}

// p50/p99/max of the operation, and p99 against its budget.
void reportAgainstBudget(benchmark::State& state, const std::vector<double>& ms, double budgetMs) {
  if (ms.empty()) return;
  state.counters["p99_per_budget"] = leafdig::bench::reportLatency(state, ms).p99 / budgetMs;
}

// A snapshot of a whole captured leaf: its markers as stylus items, and the preview's model
// meshed at `resolution` — the export mesh, one mesh for every zoom (the path before issue
// 26) — or, for "screen-space", the levels the capture loop now builds (acq::buildPreview:
// adaptive meshes within kPreviewLevelsMm), the view drawing the coarsest within half a pixel.
acq::Snapshot leafSnapshot(int sample, const std::string& resolution, int dropRows = 0) {
  m::MarkerSet markers = m::readMarkersFile(std::string(LEAFDIG_SOURCE_DIR) + "/data/samples/" + kSamples[sample]);
  markers.rows.resize(markers.rows.size() - static_cast<std::size_t>(dropRows));
  auto preview = std::make_shared<acq::Preview>();
  preview->model = m::buildLeafModel(markers);
  if (resolution == "screen-space") {
    for (const double e : acq::kPreviewLevelsMm) {
      m::MeshOptions o;
      o.method = m::MeshMethod::Adaptive;
      o.maxErrorMm = e;
      preview->levels.push_back({e, m::meshLeaf(preview->model, o)});
    }
    preview->mesh = preview->levels.back().mesh;
  } else {
    preview->mesh = m::meshLeaf(preview->model, m::MeshResolution::preset(resolution));
  }
  acq::Snapshot s;
  s.session = 1;
  s.items.push_back({acq::What::Tip, 0, 0, {markers.tipMm.x(), markers.tipMm.y(), markers.tipMm.z()}, 0, {}, {}});
  for (std::size_t r = 0; r < markers.rows.size(); ++r)
    for (std::size_t c = 0; c < markers.rows[r].pointsMm.size(); ++c) {
      const auto& p = markers.rows[r].pointsMm[c];
      s.items.push_back(
          {acq::What::Marker, static_cast<int>(r + 1), static_cast<int>(c + 1), {p.x(), p.y(), p.z()}, 0, {}, {}});
    }
  s.completeRows = static_cast<int>(markers.rows.size());
  s.preview = std::move(preview);
  return s;
}

std::size_t triangles(const m::LeafMesh& mesh) {
  std::size_t n = 0;
  for (const auto& o : mesh.organs) n += o.mesh.triangles.size();
  return n;
}
// What the view should draw of the snapshot at its zoom.
std::size_t triangles(const leafdig::station::PreviewWidget& w) {
  return w.meshForView() ? triangles(*w.meshForView()) : 0;
}

// A top-level preview window, shown and drawn once; counts swapped frames.
struct Window {
  leafdig::station::PreviewWidget widget;
  int swapped = 0;
  Window() {
    QObject::connect(&widget, &leafdig::station::PreviewWidget::frameSwapped, [this] { ++swapped; });
    widget.resize(kPreviewWidth, kPreviewHeight);
    widget.QWidget::show();
    waitForFrame(swapped);
  }
  // Runs the event loop (blocking, not spinning: llvmpipe needs both cores) until a frame
  // after `before` has been swapped.
  bool waitForFrame(int before) {
    if (swapped > before) return true;
    QEventLoop loop;
    QObject::connect(&widget, &leafdig::station::PreviewWidget::frameSwapped, &loop, &QEventLoop::quit);
    QTimer::singleShot(10000, &loop, &QEventLoop::quit);
    loop.exec();
    return swapped > before;
  }
};

void describe(benchmark::State& state, const Window& w, const acq::Snapshot& s, int sample, const char* path) {
  state.SetLabel(std::string(kSamples[sample]) + " " + path);
  state.counters["rows"] = s.completeRows;
  state.counters["drawn_triangles"] = static_cast<double>(w.widget.trianglesDrawn());
  state.counters["drawn_error_mm"] = w.widget.drawnErrorMm();
  state.counters["px_per_mm"] = w.widget.pixelsPerMm();
  state.counters["pixels"] = static_cast<double>(w.widget.width() * w.widget.height());
}

// Today's path (the export mesh at every zoom) and the screen-space levels, side by side in
// one run (issue 26: frame and snapshot → screen p99 ≤ 8 ms, half a frame).
void previewFrame(benchmark::State& state, const char* path) {
  const int sample = static_cast<int>(state.range(0));
  const acq::Snapshot s = leafSnapshot(sample, path);
  Window w;
  w.widget.show(s);
  w.waitForFrame(w.swapped);
  std::vector<double> frames, paints;
  for (auto _ : state) {
    const int before = w.swapped;
    const auto t0 = Clock::now();
    w.widget.redraw();
    if (!w.waitForFrame(before)) {
      fail(state, "no frame reached the screen within 10 s");
      break;
    }
    frames.push_back(ms(Clock::now() - t0));
    paints.push_back(w.widget.lastFrameMs());
  }
  if (w.widget.trianglesDrawn() != triangles(w.widget)) fail(state, "the preview did not draw the whole leaf");
  reportAgainstBudget(state, frames, kFrameBudgetMs);
  // Issue 26's target: half a frame, 8 ms.
  state.counters["p99_per_8ms"] = static_cast<double>(state.counters["p99_per_budget"]) * kFrameBudgetMs / 8.0;
  if (!paints.empty()) state.counters["paintGL_p50_ms"] = leafdig::bench::percentiles(paints).p50;
  describe(state, w, s, sample, path);
}
void BM_PreviewFrame(benchmark::State& state) {
  previewFrame(state, "export");
}
void BM_PreviewFrameScreenSpace(benchmark::State& state) {
  previewFrame(state, "screen-space");
}
BENCHMARK(BM_PreviewFrame)->DenseRange(0, 2)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_PreviewFrameScreenSpace)->DenseRange(0, 2)->Unit(benchmark::kMillisecond);

void snapshotToScreen(benchmark::State& state, const char* path) {
  const int sample = static_cast<int>(state.range(0));
  // Alternate a leaf and the same leaf one row shorter, so every snapshot changes the mesh.
  const acq::Snapshot snapshots[2] = {leafSnapshot(sample, path), leafSnapshot(sample, path, 1)};
  Window w;
  std::vector<double> latencies;
  std::size_t k = 0;
  for (auto _ : state) {
    const acq::Snapshot& s = snapshots[k++ % 2];
    const int before = w.swapped;
    const auto t0 = Clock::now();
    QMetaObject::invokeMethod(
        &w.widget, [&w, &s] { w.widget.show(s); }, Qt::QueuedConnection);
    if (!w.waitForFrame(before)) {
      fail(state, "no frame reached the screen within 10 s");
      break;
    }
    latencies.push_back(ms(Clock::now() - t0));
    if (w.widget.trianglesDrawn() != triangles(w.widget)) {
      fail(state, "the frame after a snapshot did not show it");
      break;
    }
  }
  reportAgainstBudget(state, latencies, kSixtyHzFrameMs);
  state.counters["p99_per_8ms"] = static_cast<double>(state.counters["p99_per_budget"]) * kSixtyHzFrameMs / 8.0;
  describe(state, w, snapshots[0], sample, path);
}
void BM_SnapshotToScreen(benchmark::State& state) {
  snapshotToScreen(state, "export");
}
void BM_SnapshotToScreenScreenSpace(benchmark::State& state) {
  snapshotToScreen(state, "screen-space");
}
BENCHMARK(BM_SnapshotToScreen)->Arg(2)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_SnapshotToScreenScreenSpace)->Arg(2)->Unit(benchmark::kMillisecond);

// Spawns the station and reads its "first_frame steady_ns N main_ms M" line.
struct FirstFrame {
  double spawnToFrameMs = -1, mainToFrameMs = -1, exitedMs = -1;
  std::string error;
};

FirstFrame failed(std::string why) {
  FirstFrame f;
  f.error = std::move(why);
  return f;
}

FirstFrame startStation(const fs::path& dir, int run) {
  FirstFrame out;
  int pipeFds[2];
  if (::pipe(pipeFds) != 0) return failed("pipe failed");
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, pipeFds[1], STDOUT_FILENO);
  posix_spawn_file_actions_addclose(&actions, pipeFds[0]);
  posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, (dir / "stderr.txt").c_str(), O_WRONLY | O_CREAT | O_APPEND,
                                   0644);
  const std::string db = (dir / ("station-" + std::to_string(run) + ".sqlite")).string();
  const std::string ini = (dir / "station.ini").string();
  std::vector<std::string> args = {LEAFDIG_STATION_EXE,       "--simulate", "--db", db, "--settings", ini,
                                   "--quit-after-first-frame"};
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  pid_t pid = 0;
  const auto t0 = Clock::now();
  const int rc = ::posix_spawn(&pid, argv[0], &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  ::close(pipeFds[1]);
  if (rc != 0) {
    ::close(pipeFds[0]);
    return failed(std::string("cannot start ") + LEAFDIG_STATION_EXE);
  }
  std::string text;
  char buf[512];
  for (ssize_t n; (n = ::read(pipeFds[0], buf, sizeof buf)) > 0;) text.append(buf, static_cast<std::size_t>(n));
  ::close(pipeFds[0]);
  int status = 0;
  ::waitpid(pid, &status, 0);
  out.exitedMs = ms(Clock::now() - t0);
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    out.error = "the station did not exit cleanly (" +
                (WIFSIGNALED(status) ? "signal " + std::to_string(WTERMSIG(status))
                                     : "exit status " + std::to_string(WEXITSTATUS(status))) +
                "; see " + (dir / "stderr.txt").string() + ")";
    return out;
  }
  long long steadyNs = 0;
  double mainMs = 0;
  const auto at = text.find("first_frame ");
  if (at == std::string::npos ||
      std::sscanf(text.c_str() + at, "first_frame steady_ns %lld main_ms %lf", &steadyNs, &mainMs) != 2) {
    out.error = "the station printed no first frame (see " + (dir / "stderr.txt").string() + ")";
    return out;
  }
  const Clock::time_point frame{std::chrono::nanoseconds(steadyNs)};
  out.spawnToFrameMs = ms(frame - t0);
  out.mainToFrameMs = mainMs;
  return out;
}

void BM_StartUp(benchmark::State& state) {
  const fs::path dir = fs::temp_directory_path() / ("leafdig-station-bench-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  std::vector<double> frames, mains, exits;
  int run = 0;
  for (auto _ : state) {
    const FirstFrame f = startStation(dir, run++);
    if (!f.error.empty()) {
      fail(state, f.error);
      break;
    }
    state.SetIterationTime(f.spawnToFrameMs / 1000.0);
    frames.push_back(f.spawnToFrameMs);
    mains.push_back(f.mainToFrameMs);
    exits.push_back(f.exitedMs);
  }
  reportAgainstBudget(state, frames, kStartUpBudgetMs);
  if (!mains.empty()) {
    state.counters["main_to_frame_p50_ms"] = leafdig::bench::percentiles(mains).p50;
    state.counters["spawn_to_exit_p50_ms"] = leafdig::bench::percentiles(exits).p50;
  }
  state.SetLabel("leafdig-station --simulate, fresh database each run");
  fs::remove_all(dir);
}
BENCHMARK(BM_StartUp)->Iterations(8)->UseManualTime()->Unit(benchmark::kMillisecond);

}  // namespace

int main(int argc, char** argv) {
  QApplication app(argc, argv);
  if (QGuiApplication::platformName() == "offscreen" || !QOpenGLContext().create()) {
    std::fprintf(stderr,
                 "leafdig_station_bench: needs a display with OpenGL (platform %s); run it under xvfb-run, e.g.\n"
                 "  xvfb-run -a -s '-screen 0 1920x1080x24' %s\n",
                 qPrintable(QGuiApplication::platformName()), argv[0]);
    return 2;
  }
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return g_failed ? 1 : 0;
}
