// Model rebuild and interpolation benchmarks. Results and the command that made them:
// docs/benchmarks.md.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <unsupported/Eigen/Splines>
#include <utility>

#include "leafdig/model/io/leaf_build.hpp"
#include "leafdig/model/leaf/leaf_model.hpp"
#include "leafdig/model/leaf/markers_json.hpp"
#include "leafdig/model/mesh/mesh.hpp"
#include "leafdig/model/metrics/metrics.hpp"
#include "leafdig/model/spline/interpolation.hpp"
#include "leafdig/model/synth/synthetic_leaf.hpp"

namespace {

namespace m = leafdig::model;

const char* const kSamples[] = {"lower-leaf-n10.markers.json", "upper-small-leaf-n17.markers.json",
                                "upper-curved-leaf-n14.markers.json"};

m::MarkerSet loadSample(int index) {
  return m::readMarkersFile(std::string(LEAFDIG_SOURCE_DIR) + "/data/samples/" + kSamples[index]);
}

// Markers -> veins + blade mesh: what a front end does after every accepted point.
void rebuild(benchmark::State& state, const char* preset) {
  const m::MarkerSet markers = loadSample(static_cast<int>(state.range(0)));
  const m::MeshResolution resolution = m::MeshResolution::preset(preset);
  std::size_t vertices = 0;
  for (auto _ : state) {
    const m::LeafModel leaf = m::buildLeafModel(markers);
    const m::LeafMesh mesh = m::meshLeaf(leaf, resolution);
    vertices = m::countVeins(mesh).vertices + m::countBlade(mesh).vertices;
    benchmark::DoNotOptimize(vertices);
  }
  state.SetLabel(std::string(kSamples[state.range(0)]) + " " + preset);
  state.counters["rows"] = static_cast<double>(markers.rows.size());
  state.counters["vertices"] = static_cast<double>(vertices);
}

void BM_RebuildPreview(benchmark::State& state) {
  rebuild(state, "preview");
}
void BM_RebuildPaper(benchmark::State& state) {
  rebuild(state, "paper");
}
void BM_RebuildExport(benchmark::State& state) {
  rebuild(state, "export");
}
BENCHMARK(BM_RebuildPreview)->DenseRange(0, 2)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_RebuildPaper)->DenseRange(0, 2)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_RebuildExport)->DenseRange(0, 2)->Unit(benchmark::kMicrosecond);

// What `model build --json` and Python's leafdig.build_leaf do for one leaf: the model, the export
// mesh, the metrics with the silhouette, the metrics document. The three samples in turn;
// tests/bench/python_bench.py builds the same leaves from Python and reports the ratio.
void BM_BuildLeafAsModelBuild(benchmark::State& state) {
  const m::MarkerSet samples[] = {loadSample(0), loadSample(1), loadSample(2)};
  m::MeshOptions options;
  options.resolution = m::MeshResolution::preset("export");
  std::size_t k = 0;
  for (auto _ : state) {
    const m::BuiltLeaf leaf =
        m::buildLeafAsModelBuild(samples[k++ % 3], m::BladeKind::Interp, "digitizer", options, {0, 0, 1}, 5.0);
    benchmark::DoNotOptimize(m::metricsToJson(leaf.metrics));
  }
  state.SetLabel("the three samples in turn, export mesh");
}
BENCHMARK(BM_BuildLeafAsModelBuild)->Unit(benchmark::kMillisecond);

void BM_ConvergedMetrics(benchmark::State& state) {
  const m::LeafModel leaf = m::buildLeafModel(loadSample(static_cast<int>(state.range(0))));
  for (auto _ : state) {
    benchmark::DoNotOptimize(m::computeLeafMetrics(leaf, {0, 0, 1}));
  }
  state.SetLabel(kSamples[state.range(0)]);
}
// The blade area's 95 % interval alone (64 Monte-Carlo draws and the row-drop estimate),
// the part of the metrics above that issue 16 added.
void BM_AreaInterval(benchmark::State& state) {
  const m::MarkerSet markers = loadSample(static_cast<int>(state.range(0)));
  double width = 0;
  for (auto _ : state) {
    const m::AreaUncertainty u = m::areaUncertainty(markers);
    width = u.halfWidthPercent();
    benchmark::DoNotOptimize(std::as_const(width));
  }
  state.SetLabel(kSamples[state.range(0)]);
  state.counters["half_width_percent"] = width;
}
BENCHMARK(BM_AreaInterval)->DenseRange(0, 2)->Unit(benchmark::kMillisecond);

BENCHMARK(BM_ConvergedMetrics)->DenseRange(0, 2)->Unit(benchmark::kMillisecond);

// A long leaf with `rows` rows (up to the 1 000 leafdig takes), 2.4 m at most, cupped: what a
// hostile or very patient capture hands `model build`. The whole of `model build --json`'s
// work (model, export mesh, metrics with the area interval): its time per row must not grow
// with the rows (issue 26: a dense product made 1 000 rows cost seconds, 4 000 ten times that).
m::MarkerSet longLeaf(int rows) {
  m::MarkerSet set;
  const double length = std::min(3.0 * rows, 2400.0);
  const double width = 0.3 * length;
  set.tipMm = {0, length + 5, 0};
  set.edgeThicknessMm = 0.3;
  for (int i = 1; i <= rows; ++i) {
    const double t = static_cast<double>(i) / rows;
    const double halfWidth = width / 2 * std::sin(3.14159265358979 * std::min(t, 0.98)) + 1;
    m::MarkerRow row;
    for (int j = 0; j < m::kMarkersPerRow; ++j) {
      const double across = (3 - j) / 3.0;
      row.pointsMm[static_cast<std::size_t>(j)] = {across * halfWidth, length * (1 - t) * 0.999 + 0.001 * length,
                                                   5 * std::sin(across * 1.3)};
    }
    row.midribThicknessMm = 2.0;
    row.veinOriginThicknessMm = 1.0;
    set.rows.push_back(row);
  }
  return set;
}
void BM_ManyRows(benchmark::State& state) {
  const m::MarkerSet markers = longLeaf(static_cast<int>(state.range(0)));
  const m::MeshResolution resolution = m::MeshResolution::preset("export");
  for (auto _ : state) {
    const m::LeafModel leaf = m::buildLeafModel(markers);
    const m::LeafMesh mesh = m::meshLeaf(leaf, resolution);
    benchmark::DoNotOptimize(m::computeLeafMetrics(leaf, {0, 0, 1}));
    benchmark::DoNotOptimize(mesh.organs.size());
  }
  state.counters["rows"] = static_cast<double>(markers.rows.size());
  // Seconds per row and iteration: flat across the row counts when the cost is linear.
  state.counters["s_per_row"] = benchmark::Counter(static_cast<double>(state.iterations()) * state.range(0),
                                                   benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_ManyRows)->Arg(125)->Arg(250)->Arg(500)->Arg(1000)->Unit(benchmark::kMillisecond);

// The contour of the 17-row leaf as 4-D data balls (2N + 1 = 35 points), and longer
// synthetic curves to show how each solver scales.
Eigen::MatrixXd interpolationData(int count) {
  Eigen::MatrixXd pts(count, 4);
  for (int k = 0; k < count; ++k) {
    const double t = 0.37 * k;
    pts.row(k) << 10 * k + 3 * std::sin(t), 20 * std::cos(0.5 * t), 5 * std::sin(0.3 * t), 1 + 0.2 * std::sin(t);
  }
  return pts;
}

void BM_InterpolateBandedNatural(benchmark::State& state) {
  const Eigen::MatrixXd pts = interpolationData(static_cast<int>(state.range(0)));
  for (auto _ : state) {
    const std::vector<double> params = m::chordLengthParameters(pts, 3);
    benchmark::DoNotOptimize(m::interpolateNaturalCubic(params, pts));
  }
}

void BM_InterpolateEigenSplineFitting(benchmark::State& state) {
  using Spline4 = Eigen::Spline<double, 4>;
  const Eigen::MatrixXd pts = interpolationData(static_cast<int>(state.range(0))).transpose();
  for (auto _ : state) {
    Eigen::RowVectorXd params;
    Eigen::ChordLengths(pts.topRows(3), params);
    benchmark::DoNotOptimize(Eigen::SplineFitting<Spline4>::Interpolate(pts, 3, params));
  }
}
BENCHMARK(BM_InterpolateBandedNatural)->Arg(4)->Arg(11)->Arg(35)->Arg(200)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_InterpolateEigenSplineFitting)->Arg(4)->Arg(11)->Arg(35)->Arg(200)->Unit(benchmark::kMicrosecond);

}  // namespace

// A synthetic ground-truth leaf (issue 16 target: ≤ 20 ms): the generator, the exact area
// (with its error estimate, i.e. both panel counts), the protocol's markers with noise and
// the truth file. Argument: 0 the tobacco default, 1 a serrated ovate leaf (60 sharp teeth
// per side, normal direction: the most panels the area integration meets).
void BM_SyntheticLeafAndTruth(benchmark::State& state) {
  m::SyntheticLeafSpec spec =
      m::defaultSyntheticSpec(state.range(0) == 0 ? m::LeafShape::Tobacco : m::LeafShape::Ovate);
  if (state.range(0) == 1) {
    spec.outline.lengthMm = 200;
    spec.outline.serration = m::Serration::Sharp;
    spec.outline.toothDepthMm = 2;
    spec.outline.teethPerSide = 60;
    spec.outline.toothDirection = m::ToothDirection::Normal;
  }
  spec.rows = 15;
  std::size_t bytes = 0;
  double area = 0;
  for (auto _ : state) {
    const m::SyntheticLeaf leaf(spec);
    double error = 0;
    area = leaf.area(&error);
    const m::MarkerSet markers = leaf.markers(0.5, 7);
    bytes = m::markersToJson(markers).size() + m::truthToJson(leaf, 0.5, 7).size();
    benchmark::DoNotOptimize(bytes);
  }
  state.SetLabel(state.range(0) == 0 ? "tobacco 500 mm" : "ovate 200 mm, 60 sharp teeth per side");
  state.counters["area_mm2"] = area;
  state.counters["bytes"] = static_cast<double>(bytes);
}
BENCHMARK(BM_SyntheticLeafAndTruth)->DenseRange(0, 1)->Unit(benchmark::kMillisecond);

BENCHMARK_MAIN();
