#include "model/mesh_cmd.hpp"

#include <filesystem>
#include <iomanip>
#include <iostream>

#include "commands.hpp"
#include "leafdig/model/errors.hpp"
#include "leafdig/model/files.hpp"
#include "leafdig/model/io/mesh_export.hpp"
#include "leafdig/model/leaf/leaf_model.hpp"
#include "leafdig/model/leaf/markers_json.hpp"
#include "leafdig/model/metrics/metrics.hpp"
#include "leafdig/model/plant/plant.hpp"
#include "leafdig/model/study/mesh_study.hpp"
#include "leafdig/version.hpp"
#include "model/model_build.hpp"

namespace leafdig::cli {

namespace m = leafdig::model;

namespace {

std::pair<CLI::App*, CLI::App*> declareMeshCommands(CLI::App& app, MeshCommandOptions& o) {
  CLI::App* mesh = app.add_subcommand("mesh", "Measure meshes: distances between meshes, the meshing study");
  mesh->require_subcommand(1);
  CLI::App* compare =
      mesh->add_subcommand("compare", "Symmetric Hausdorff distance, mean and RMS between two meshes (mm)");
  compare->add_option("a", o.a, "First mesh (.obj .ply .stl .glb)")->required();
  compare->add_option("b", o.b, "Second mesh (.obj .ply .stl .glb)")->required();
  compare->add_option("--samples", o.samples, "Area-weighted sample points per side, besides every vertex")
      ->check(CLI::Range(1000, 50'000'000));
  compare->add_option("--seed", o.seed, "Seed of the sample points (the same seed gives the same answer)")
      ->check(seedText());
  compare->add_flag("--json", o.json, "Print the result as JSON");
  CLI::App* study = mesh->add_subcommand(
      "study", "Mesh one leaf (or a plant) uniform, seed, adaptive and by meshoptimizer at the same error");
  study->add_option("markers", o.markers, "Leaf markers (leafdig.markers/1)");
  study->add_option("--plan", o.plan, "A plant plan (leafdig.plant/1) instead of one leaf");
  study->add_option("--max-error", o.maxErrorMm, "The error E every mesh must meet, mm")->required();
  study->add_option("--out", o.outDir, "Folder for reference.ply, uniform.ply, seed.ply, adaptive.ply, meshopt.ply")
      ->required();
  study
      ->add_option("--samples", o.studySamples,
                   "Sample points per side and part while searching (the final figures use twice as many)")
      ->check(CLI::Range(1000, 10'000'000));
  study->add_flag("--json", o.json, "Print the result as JSON");
  return {compare, study};
}

int runCompare(const MeshCommandOptions& o) {
  const m::TriangleSoup a = m::readMeshFile(o.a);
  const m::TriangleSoup b = m::readMeshFile(o.b);
  m::CompareOptions c;
  c.samples = o.samples;
  c.seed = o.seed;
  const m::MeshDistance d = m::compareMeshes(a, b, c);
  if (o.json) {
    nlohmann::json out = {{"a", {{"file", o.a}, {"triangles", d.trianglesA}, {"area_mm2", m::surfaceArea(a)}}},
                          {"b", {{"file", o.b}, {"triangles", d.trianglesB}, {"area_mm2", m::surfaceArea(b)}}},
                          {"hausdorff_mm", d.hausdorff},
                          {"a_to_b_mm", d.aToB.max},
                          {"b_to_a_mm", d.bToA.max},
                          {"mean_mm", d.mean},
                          {"rms_mm", d.rms},
                          {"samples", {{"a", d.aToB.samples}, {"b", d.bToA.samples}}},
                          {"seed", o.seed}};
    std::cout << out.dump() << "\n";
    return 0;
  }
  std::cout << "A " << o.a << ": " << d.trianglesA << " triangles\n"
            << "B " << o.b << ": " << d.trianglesB << " triangles\n"
            << "Hausdorff " << d.hausdorff << " mm (A to B " << d.aToB.max << " mm, B to A " << d.bToA.max
            << " mm), mean " << d.mean << " mm, RMS " << d.rms << " mm; " << d.aToB.samples << " + " << d.bToA.samples
            << " samples\n";
  return 0;
}

int runStudy(const MeshCommandOptions& o) {
  if (o.markers.empty() == o.plan.empty())
    throw m::InputError("give either a markers file or --plan PLAN (one leaf or one plant)");
  std::optional<m::MeshSubject> subject;
  if (!o.markers.empty()) {
    const m::LeafModel leaf = m::buildLeafModel(m::readMarkersFile(o.markers));
    subject.emplace(m::transformed(leaf, m::leafFrameFromDigitizer(leaf)));
  } else {
    const m::PlantPlan plan = m::readPlantPlan(o.plan);
    if (plan.libraryDb)
      throw m::InputError(o.plan + ": the study takes plans whose leaves are markers files (no library.db)");
    subject.emplace(m::PlantBuilder(plan, {}).build());
  }
  m::StudyOptions so;
  so.maxErrorMm = o.maxErrorMm;
  so.samplesPerPart = o.studySamples;
  const std::vector<m::StudyEntry> entries = m::runMeshStudy(*subject, so);
  const std::filesystem::path dir(o.outDir);
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) throw m::IoError("cannot create folder " + dir.string() + ": " + ec.message());
  const m::ExportHeader header{"", o.plan.empty() ? "leaf" : "plant", std::string("leafdig ") + kVersion};
  nlohmann::json meshes;
  const Eigen::Vector3d light = Eigen::Vector3d::UnitZ();
  auto silhouette = [&light](const m::LeafMesh& mesh) {
    std::vector<const m::Mesh*> parts;
    for (const auto& organ : mesh.organs) parts.push_back(&organ.mesh);
    return m::silhouetteArea(parts, light, 4096);
  };
  const double referenceSilhouette = silhouette(entries.front().mesh);
  for (const m::StudyEntry& e : entries) {
    const std::string file = e.name + ".ply";
    m::writeFileAtomically(dir / file, m::encodeMesh(e.mesh, m::MeshFormat::Ply, header));
    nlohmann::json parameters = nlohmann::json::object();
    for (const auto& [k, v] : e.parameterValues) parameters[k] = v;
    const bool reference = e.name == "reference";
    const double s = silhouette(e.mesh);
    meshes[e.name] = {{"file", file},
                      {"triangles", e.triangles},
                      {"hausdorff_mm", e.measured.hausdorff},
                      {"mean_mm", reference ? nlohmann::json(nullptr) : nlohmann::json(e.measured.mean)},
                      {"rms_mm", reference ? nlohmann::json(nullptr) : nlohmann::json(e.measured.rms)},
                      {"meets_error", e.meetsError},
                      {"silhouette_mm2", s},
                      {"silhouette_vs_reference_percent", 100.0 * (s - referenceSilhouette) / referenceSilhouette},
                      {"description", e.parameters},
                      {"parameters", parameters}};
  }
  if (o.json) {
    std::cout << nlohmann::json{{"max_error_mm", o.maxErrorMm}, {"meshes", meshes}}.dump() << "\n";
    return 0;
  }
  std::cout << "meshing study at E = " << o.maxErrorMm << " mm (" << (o.plan.empty() ? o.markers : o.plan)
            << "), files in " << dir.string() << "\n";
  std::cout << std::left << std::setw(10) << "mesh" << std::right << std::setw(10) << "triangles" << std::setw(14)
            << "Hausdorff mm" << std::setw(10) << "mean mm" << std::setw(10) << "RMS mm"
            << "  parameters\n";
  for (const m::StudyEntry& e : entries) {
    const bool reference = e.name == "reference";
    std::cout << std::left << std::setw(10) << e.name << std::right << std::setw(10) << e.triangles << std::setw(14)
              << std::setprecision(4) << e.measured.hausdorff << std::setw(10)
              << (reference ? std::string("-") : std::to_string(e.measured.mean).substr(0, 7)) << std::setw(10)
              << (reference ? std::string("-") : std::to_string(e.measured.rms).substr(0, 7)) << "  " << e.parameters
              << (reference || e.meetsError ? "" : "  (does NOT meet E)") << "\n";
  }
  return 0;
}

}  // namespace

void addMeshCommands(CLI::App& app, CommandTable& table) {
  auto o = std::make_shared<MeshCommandOptions>();
  const auto [compare, study] = declareMeshCommands(app, *o);
  table.add(compare, [o] { return runCompare(*o); });
  table.add(study, [o] { return runStudy(*o); });
}

}  // namespace leafdig::cli
