// Whole-plant benchmarks (issue 14 targets): a 20-leaf plant from the captured sample leaves,
// build + every export; a 60-step growth series; the plant's silhouette. Results and the
// command: docs/benchmarks.md.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <future>

#include "leafdig/model/archive/mtg_archive.hpp"
#include "leafdig/model/archive/plant_import.hpp"
#include "leafdig/model/files.hpp"
#include "leafdig/model/io/archive_export.hpp"
#include "leafdig/model/io/plant_export.hpp"
#include "leafdig/model/io/survey_export.hpp"
#include "leafdig/model/metrics/metrics.hpp"
#include "leafdig/model/plant/plant.hpp"
#include "leafdig/model/plant/surveyed_plant.hpp"
#include "leafdig/model/study/synthetic_plant.hpp"
#include "leafdig/model/synth/synthetic_leaf.hpp"

namespace {

namespace m = leafdig::model;

// 20 leaves cycling over the three samples, 40 mm apart from 60 mm up a 900 mm stem,
// golden-angle phyllotaxis with 5° jitter, inclinations from 75° (low) to 30° (top).
m::PlantPlan twentyLeafPlan(bool growth) {
  const char* const samples[] = {"lower-leaf-n10.markers.json", "upper-curved-leaf-n14.markers.json",
                                 "upper-small-leaf-n17.markers.json"};
  m::PlantPlan plan;
  plan.id = "bench-20";
  plan.seed = 7;
  plan.stem = {900.0, 24.0, 8.0, {}};
  plan.jitterDeg = 5.0;
  for (int k = 1; k <= 20; ++k) {
    m::LeafPlan leaf;
    leaf.rank = k;
    leaf.markers = std::string(LEAFDIG_SOURCE_DIR) + "/data/samples/" + samples[(k - 1) * 3 / 20];
    leaf.insertionHeightMm = 60.0 + 40.0 * (k - 1);
    leaf.inclinationDeg = 75.0 - 45.0 * (k - 1) / 19.0;
    leaf.scale = 1.0 - 0.4 * (k - 1) / 19.0;
    plan.leaves.push_back(leaf);
  }
  if (growth) plan.growth = m::GrowthPlan{"days", 2.0, 0.3, 12.0, 0.4, 0.12, 30.0};
  return plan;
}

const m::PlantBuilder& builder() {
  static const m::PlantBuilder b(twentyLeafPlan(true), {});
  return b;
}

const char* const kPresets[] = {"preview", "export", "adaptive 0.2 mm"};

// Arg 0, 1: the uniform presets; 2: adaptive meshing at E = 0.2 mm (about the preview's own
// distance to the exact surface, docs/meshing.md).
m::MeshOptions meshOptions(std::int64_t arg) {
  m::MeshOptions o;
  if (arg == 2) {
    o.method = m::MeshMethod::Adaptive;
    o.maxErrorMm = 0.2;
  } else {
    o.resolution = m::MeshResolution::preset(kPresets[arg]);
  }
  return o;
}

// Assembly, meshes, metrics and all eight exports (.glb .obj .ply .stl .can+.opt .mtg .csv
// .json) encoded in memory, as `leafdig plant build` does (formats and silhouettes on every
// core); writing to disk is left out (it measures the disk).
void BM_PlantBuildAndAllExports(benchmark::State& state) {
  const m::MeshOptions resolution = meshOptions(state.range(0));
  const m::PlantExportOptions options{m::CanUnit::Metre, "bench"};
  std::size_t bytes = 0, triangles = 0;
  (void)builder();  // the plan read and the leaves resolved once: BM_PlantResolveLeaves
  for (auto _ : state) {
    const m::Plant plant = builder().build();
    const m::LeafMesh mesh = m::meshPlant(plant, resolution);
    const m::PlantMetrics metrics = m::computePlantMetrics(plant, mesh, Eigen::Vector3d::UnitZ());
    bytes = 0;
    for (const auto& f : m::encodePlantFiles({"p.glb", "p.obj", "p.ply", "p.stl", "p.can", "p.mtg", "p.csv", "p.json"},
                                             plant, mesh, metrics, options))
      bytes += f.bytes.size();
    triangles = 0;
    for (const auto& o : mesh.organs) triangles += o.mesh.triangles.size();
    benchmark::DoNotOptimize(bytes);
  }
  state.SetLabel(kPresets[state.range(0)]);
  state.counters["triangles"] = static_cast<double>(triangles);
  state.counters["MB"] = static_cast<double>(bytes) / 1e6;
}
BENCHMARK(BM_PlantBuildAndAllExports)->DenseRange(0, 2)->Unit(benchmark::kMillisecond);

// Reading the plan's 20 leaf files and putting each leaf in its leaf frame (once per plan).
void BM_PlantResolveLeaves(benchmark::State& state) {
  const m::PlantPlan plan = twentyLeafPlan(true);
  for (auto _ : state) benchmark::DoNotOptimize(m::PlantBuilder(plan, {}));
}
BENCHMARK(BM_PlantResolveLeaves)->Unit(benchmark::kMillisecond);

// The stages alone.
void BM_PlantAssemble(benchmark::State& state) {
  for (auto _ : state) benchmark::DoNotOptimize(builder().build());
}
BENCHMARK(BM_PlantAssemble)->Unit(benchmark::kMillisecond);

void BM_PlantMesh(benchmark::State& state) {
  const m::Plant plant = builder().build();
  const m::MeshOptions resolution = meshOptions(state.range(0));
  for (auto _ : state) benchmark::DoNotOptimize(m::meshPlant(plant, resolution));
  state.SetLabel(kPresets[state.range(0)]);
}
BENCHMARK(BM_PlantMesh)->DenseRange(0, 2)->Unit(benchmark::kMillisecond);

void BM_PlantEncode(benchmark::State& state) {
  static const char* const kExts[] = {".glb", ".obj", ".ply", ".stl", ".can", ".mtg", ".csv", ".json"};
  const m::Plant plant = builder().build();
  const m::LeafMesh mesh = m::meshPlant(plant, m::MeshResolution::preset("preview"));
  const m::PlantMetrics metrics = m::computePlantMetrics(plant, mesh, Eigen::Vector3d::UnitZ());
  const m::PlantExportOptions options{m::CanUnit::Metre, "bench"};
  const char* ext = kExts[state.range(0)];
  for (auto _ : state) benchmark::DoNotOptimize(m::encodePlant(std::string("p") + ext, plant, mesh, metrics, options));
  state.SetLabel(std::string(ext) + " (preview)");
}
BENCHMARK(BM_PlantEncode)->DenseRange(0, 7)->Unit(benchmark::kMillisecond);

// Silhouette of the whole plant (union of the 20 blades' projections), light from above.
void BM_PlantSilhouette(benchmark::State& state) {
  const m::Plant plant = builder().build();
  const m::LeafMesh mesh = m::meshPlant(plant, m::MeshResolution::preset(kPresets[state.range(0)]));
  std::vector<const m::Mesh*> blades;
  for (const auto& o : mesh.organs)
    if (o.kind == m::OrganKind::Blade) blades.push_back(&o.mesh);
  double area = 0;
  for (auto _ : state) {
    area = m::silhouetteArea(blades, Eigen::Vector3d::UnitZ());
    benchmark::DoNotOptimize(area);
  }
  state.SetLabel(std::string(kPresets[state.range(0)]) + " blades");
  state.counters["silhouette_m2"] = area / 1e6;
}
BENCHMARK(BM_PlantSilhouette)->DenseRange(0, 1)->Unit(benchmark::kMillisecond);

// Per-leaf areas and silhouettes, and the plant's.
void BM_PlantMetrics(benchmark::State& state) {
  const m::Plant plant = builder().build();
  const m::LeafMesh mesh = m::meshPlant(plant, m::MeshResolution::preset(kPresets[state.range(0)]));
  for (auto _ : state) benchmark::DoNotOptimize(m::computePlantMetrics(plant, mesh, Eigen::Vector3d::UnitZ()));
  state.SetLabel(kPresets[state.range(0)]);
}
BENCHMARK(BM_PlantMetrics)->DenseRange(0, 1)->Unit(benchmark::kMillisecond);

// `leafdig plant grow --times 0:59:1 -o plant-{t}.glb`: 60 states built, meshed (preview)
// and encoded as GLB, with their metrics.
void BM_GrowthSeries60(benchmark::State& state) {
  const m::PlantExportOptions options{m::CanUnit::Metre, "bench"};
  std::size_t bytes = 0;
  (void)builder();
  for (auto _ : state) {
    bytes = 0;
    for (int t = 0; t < 60; ++t) {
      const m::Plant plant = builder().build(static_cast<double>(t));
      const m::LeafMesh mesh = m::meshPlant(plant, m::MeshResolution::preset("preview"));
      const m::PlantMetrics metrics = m::computePlantMetrics(plant, mesh, Eigen::Vector3d::UnitZ());
      for (const auto& f : m::encodePlant("p.glb", plant, mesh, metrics, options)) bytes += f.bytes.size();
    }
    benchmark::DoNotOptimize(bytes);
  }
  state.counters["MB"] = static_cast<double>(bytes) / 1e6;
}
BENCHMARK(BM_GrowthSeries60)->Unit(benchmark::kMillisecond);

// A plant digitized in place (issue 28's target: a 20-node plant with 7 full leaves exported in
// ≤ 200 ms): a synthetic plant of 20 nodes (every third leaf in full, and the largest: 7 full,
// 12 quick from the built-in shape), surveyed and its MTG and CSV encoded (arg 0: `sessions
// export --format mtg,csv,json` after the replay, not included); arg 1, 2:
// also made a model, meshed at the preview (1) or export (2, `sessions export`'s) preset and
// its GLB and CARIBU files encoded. Writing is left out.
void BM_SurveyedPlantExport(benchmark::State& state) {
  m::SyntheticPlantSpec spec;
  spec.nodes = 20;
  spec.seed = 3;
  spec.date = m::SurveyDate{2026, 6, 12};
  const m::PlantMarkers markers = m::synthesizePlant(spec).markers;
  const std::vector<std::filesystem::path> paths{"p.can"};  // the GLB is the survey's (one node per MTG entity)
  const m::PlantExportOptions options{m::CanUnit::Metre, "bench"};
  const m::LibraryLeaf sample{m::kSampleShapeSource, m::sampleLeafShape()};  // built once, as in the CLI
  int full = 0;
  // Where the time goes, per stage (ms per iteration), beside the total.
  double surveyMs = 0, modelMs = 0, meshMs = 0, metricsMs = 0, encodeMs = 0;
  using Clock = std::chrono::steady_clock;
  const auto since = [](Clock::time_point t) {
    return std::chrono::duration<double, std::milli>(Clock::now() - t).count();
  };
  const bool model = state.range(0) > 0;
  m::MeshOptions meshOptions;
  meshOptions.resolution = m::MeshResolution::preset(state.range(0) == 1 ? "preview" : "export");
  for (auto _ : state) {
    auto t = Clock::now();
    const m::PlantSurvey survey = m::surveyPlant(markers);
    surveyMs += since(t);
    t = Clock::now();
    benchmark::DoNotOptimize(m::encodeSurveyMtg(survey, *spec.date));
    benchmark::DoNotOptimize(m::encodeSurveyCsv(survey, *spec.date));
    benchmark::DoNotOptimize(m::plantSurveyToJson(survey));
    encodeMs += since(t);
    full = static_cast<int>(std::count_if(survey.leaves.begin(), survey.leaves.end(),
                                          [](const m::SurveyedLeaf& l) { return l.kind == m::LeafKind::Full; }));
    if (!model) continue;
    t = Clock::now();
    const m::Plant plant = m::surveyedPlant(survey, {}, sample);
    modelMs += since(t);
    t = Clock::now();
    const m::LeafMesh mesh = m::meshPlant(plant, meshOptions);
    meshMs += since(t);
    t = Clock::now();
    const m::PlantMetrics metrics = m::computePlantMetrics(plant, mesh, Eigen::Vector3d::UnitZ());
    metricsMs += since(t);
    t = Clock::now();
    // As `sessions export` does: the survey's GLB beside the model's other formats.
    auto glb =
        std::async(std::launch::async, [&] { return m::encodeSurveyGlb(survey, *spec.date, mesh, options.generator); });
    benchmark::DoNotOptimize(m::encodePlantFiles(paths, plant, mesh, metrics, options));
    benchmark::DoNotOptimize(glb.get());
    encodeMs += since(t);
  }
  const double n = static_cast<double>(state.iterations());
  state.counters["survey_ms"] = surveyMs / n;
  state.counters["model_ms"] = modelMs / n;
  state.counters["mesh_ms"] = meshMs / n;
  state.counters["metrics_ms"] = metricsMs / n;
  state.counters["encode_ms"] = encodeMs / n;
  state.counters["full_leaves"] = full;
  state.counters["nodes"] = spec.nodes;
}
BENCHMARK(BM_SurveyedPlantExport)->DenseRange(0, 2)->Unit(benchmark::kMillisecond);

// An archive's tree (issue 51): OpenAlea's walnut (tests/data/archives/noylum2.mtg, 8 303
// entities, 6 426 points on 1 875 axes): read as OpenAlea reads it, drawn, meshed at preview,
// written as MTG and GLB — `leafdig plant import noylum2.mtg --units cm --resolution preview`.
void BM_ArchiveWalnutImport(benchmark::State& state) {
  const std::string text = m::readFile(std::string(LEAFDIG_SOURCE_DIR) + "/tests/data/archives/noylum2.mtg");
  using Clock = std::chrono::steady_clock;
  const auto since = [](Clock::time_point t) {
    return std::chrono::duration<double, std::milli>(Clock::now() - t).count();
  };
  double readMs = 0, drawMs = 0, meshMs = 0, encodeMs = 0;
  std::size_t triangles = 0;
  for (auto _ : state) {
    auto t = Clock::now();
    const m::MtgArchive archive = m::parseMtgArchive(text, "noylum2.mtg");
    readMs += since(t);
    t = Clock::now();
    m::ArchiveImportOptions o;
    o.mmPerUnit = 10;
    o.dressing.diameterUnit = 10;
    const m::ImportedPlant imported = m::importMtgPlant(archive, o);
    drawMs += since(t);
    t = Clock::now();
    const m::LeafMesh mesh = m::meshPlant(imported.plant, m::MeshResolution::preset("preview"));
    meshMs += since(t);
    t = Clock::now();
    const m::PlantMetrics metrics = m::computePlantMetrics(imported.plant, mesh, Eigen::Vector3d::UnitZ());
    benchmark::DoNotOptimize(
        m::encodeImportedFiles({"w.mtg", "w.glb"}, imported, archive, mesh, metrics, {m::CanUnit::Metre, "bench"}));
    encodeMs += since(t);
    triangles = 0;
    for (const auto& organ : mesh.organs) triangles += organ.mesh.triangles.size();
  }
  const double n = static_cast<double>(state.iterations());
  state.counters["read_ms"] = readMs / n;
  state.counters["draw_ms"] = drawMs / n;
  state.counters["mesh_ms"] = meshMs / n;
  state.counters["encode_ms"] = encodeMs / n;
  state.counters["triangles"] = static_cast<double>(triangles);
}
BENCHMARK(BM_ArchiveWalnutImport)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
