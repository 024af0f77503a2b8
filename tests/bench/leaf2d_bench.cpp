// 2-D leaves: scans and builds. Targets (issue 16): a 300-DPI A4 scan in <= 300 ms, a 2-D
// leaf build in <= 50 ms. Results and the command: docs/benchmarks.md.
#include <benchmark/benchmark.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <utility>

#include "leafdig/model/leaf2d/leaf2d.hpp"
#include "leafdig/model/leaf2d/leaf_scan.hpp"
#include "leafdig/model/synth/synthetic_leaf.hpp"

namespace {

namespace m = leafdig::model;
namespace fs = std::filesystem;

constexpr double kDpi = 300.0;
const Eigen::Vector2d kA4Mm(210.0, 297.0);

// A 250 mm tobacco leaf with a 30 mm petiole on an A4 page at 300 DPI (2481 x 3508 px),
// written once per process.
const fs::path& a4Scan() {
  static const fs::path path = [] {
    m::SyntheticLeafSpec spec = m::defaultSyntheticSpec(m::LeafShape::Tobacco);
    spec.outline.lengthMm = 230.0;
    const m::SyntheticLeaf leaf(spec);
    std::vector<Eigen::Vector2d> outline = leaf.outline(1500);
    const Eigen::Vector2d base = outline.front();
    const Eigen::Vector2d tip = outline[1500];
    const Eigen::Vector2d shift = Eigen::Vector2d(105.0, 45.0) - base;  // base low on the page, centred
    for (auto& p : outline) p += shift;
    const Eigen::Vector2d down = (base - tip).normalized();
    const Eigen::Vector2d side(-down.y(), down.x());
    const Eigen::Vector2d a = base + shift - down;
    const Eigen::Vector2d b = base + shift + 30.0 * down;
    const std::vector<Eigen::Vector2d> petiole{a + 1.25 * side, b + 1.25 * side, b - 1.25 * side, a - 1.25 * side};
    const fs::path p = fs::temp_directory_path() / ("leafdig-bench-a4-" + std::to_string(::getpid()) + ".png");
    m::renderScan({outline, petiole}, {}, kA4Mm, kDpi, p);
    return p;
  }();
  return path;
}

void BM_ScanA4Page(benchmark::State& state) {
  const fs::path& path = a4Scan();
  double area = 0.0;
  for (auto _ : state) {
    const m::LeafScan scan = m::scanLeaf(path, {kDpi, 3.0});
    area = scan.areaMm2;
    benchmark::DoNotOptimize(std::as_const(area));
  }
  state.SetLabel("decode PNG + segment, 2481 x 3508 px; target 300 ms");
  state.counters["area_mm2"] = area;
}
BENCHMARK(BM_ScanA4Page)->Unit(benchmark::kMillisecond);

void BM_Leaf2dBuild(benchmark::State& state) {
  const m::Outline2d outline = m::scanLeaf(a4Scan(), {kDpi, 3.0}).outline;
  m::Leaf2dOptions options;
  options.curl = state.range(0) == 0 ? m::CurlKind::Parabola : m::CurlKind::Auto;
  std::size_t triangles = 0;
  for (auto _ : state) {
    const m::Leaf2dModel leaf = m::buildLeaf2d(outline, options);
    triangles = leaf.mesh.triangles.size();
    benchmark::DoNotOptimize(std::as_const(triangles));
  }
  state.SetLabel(std::string(state.range(0) == 0 ? "parabola" : "auto (two curls)") +
                 ", scanned tobacco outline; target 50 ms");
  state.counters["outline_points"] = static_cast<double>(outline.pointsMm.size());
  state.counters["triangles"] = static_cast<double>(triangles);
}
BENCHMARK(BM_Leaf2dBuild)->DenseRange(0, 1)->Unit(benchmark::kMillisecond);

// A cordate leaf (a heart curve 96 x 66 mm, 400 points, the base at the sinus): the flat leaf
// trimmed to the outline, meshed by a constrained Delaunay triangulation.
void BM_Leaf2dBuildCordate(benchmark::State& state) {
  m::Outline2d outline;
  for (int i = 0; i < 400; ++i) {
    const double t = 2 * M_PI * i / 400;
    outline.pointsMm.emplace_back(48 * std::pow(std::sin(t), 3),
                                  3 * (13 * std::cos(t) - 5 * std::cos(2 * t) - 2 * std::cos(3 * t) - std::cos(4 * t)));
  }
  outline.baseMm = Eigen::Vector2d(0, 15);
  std::size_t triangles = 0;
  bool trimmed = false;
  for (auto _ : state) {
    const m::Leaf2dModel leaf = m::buildLeaf2d(outline);
    triangles = leaf.mesh.triangles.size();
    trimmed = leaf.trimmedToOutline;
    benchmark::DoNotOptimize(std::as_const(triangles));
  }
  if (!trimmed) state.SkipWithError("the cordate leaf was not trimmed to its outline");
  state.SetLabel("parabola, heart-shaped outline trimmed at its sinus; target 50 ms");
  state.counters["triangles"] = static_cast<double>(triangles);
}
BENCHMARK(BM_Leaf2dBuildCordate)->Unit(benchmark::kMillisecond);

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  std::error_code ec;
  fs::remove(a4Scan(), ec);
  return 0;
}
