#include "plant/plant_cmd.hpp"

#include <algorithm>
#include <charconv>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "commands.hpp"
#include "leafdig/acquisition/review/review.hpp"
#include "leafdig/db/store.hpp"
#include "leafdig/model/errors.hpp"
#include "leafdig/model/files.hpp"
#include "leafdig/model/io/plant_export.hpp"
#include "leafdig/model/plant/plant.hpp"
#include "leafdig/model/study/mesh_study.hpp"
#include "leafdig/version.hpp"
#include "model/model_build.hpp"

namespace leafdig::cli {

namespace m = leafdig::model;

namespace {

std::pair<CLI::App*, CLI::App*> declarePlantCommands(CLI::App& app, PlantOptions& o) {
  CLI::App* plant = app.add_subcommand("plant", "Assemble, grow, export and measure whole plants");
  plant->require_subcommand(1);
  CLI::App* build = plant->add_subcommand("build", "Build the plant of a leafdig.plant/1 plan and export it");
  CLI::App* grow = plant->add_subcommand("grow", "Export the plant's growth states at a series of times");
  for (CLI::App* c : {build, grow}) {
    c->add_option("plan", o.planPath, "Plant plan (leafdig.plant/1 JSON)")->required();
    c->add_option("--resolution", o.resolution, kFileResolutionHelp)->check(CLI::IsMember(fileResolutionWords()));
    c->add_option("--light", o.light, "Light direction x,y,z (plant frame, +Z up) for silhouette and STAR");
    c->add_option("--can-unit", o.canUnit, "Unit of CARIBU .can geometry: m (default) or cm")
        ->check(CLI::IsMember({"m", "cm"}));
    c->add_flag("--json", o.json, "Print leaves, azimuths, metrics, triangle counts and timings as JSON");
    addMeshChoice(*c, o.mesh);
  }
  build
      ->add_option("-o,--output", o.outputs,
                   "File to write, by extension: .glb .obj .ply .stl .can (+ .opt) .mtg .csv .json .xml (Helios) .vgx "
                   "(VegeSTAR) (repeat)")
      ->required();
  build->add_option("--organs", o.organs, kOrgansHelp)->check(CLI::IsMember(wordsIn(m::kOrganChoiceNames)));
  build->add_option("--time", o.time, "Build the growth state at this time (the plan's growth unit)");
  grow->add_option("--times", o.times, "Times start:end:step, e.g. 0:60:5")->required();
  grow->add_option("-o,--output", o.outputs,
                   "File pattern with {t} for the time, e.g. out/plant-{t}.glb (repeat for several formats); "
                   "with --animate one .glb")
      ->required();
  grow->add_flag("--animate", o.animate,
                 "Write one glTF whose animation plays the growth (the series in 10 s) instead of a file per time");
  return {build, grow};
}

std::vector<double> parseTimes(const std::string& text) {
  double a = 0, b = 0, step = 0;
  char c1 = 0, c2 = 0;
  std::stringstream in(text);
  in >> a >> c1 >> b >> c2 >> step;
  if (!in || c1 != ':' || c2 != ':' || !in.eof() || !(step > 0) || b < a || !std::isfinite(a) || !std::isfinite(b))
    throw m::InputError("--times \"" + text + "\": expected start:end:step with end ≥ start and step > 0, e.g. 0:60:5");
  std::vector<double> times;
  // Counted as a double first: 60 / 1e-300 states would overflow a long (and then write none).
  const double count = std::floor((b - a) / step + 1e-9);
  if (!(count <= 10000))
    throw m::InputError("--times \"" + text + "\" gives more than 10 000 states; use a larger step");
  const auto n = static_cast<long>(count);
  for (long i = 0; i <= n; ++i) times.push_back(a + static_cast<double>(i) * step);
  return times;
}

// A time in a file name: its shortest decimal form ("0", "5", "12.5").
std::string formatTime(double t) {
  char buffer[32];
  const auto r = std::to_chars(buffer, buffer + sizeof buffer, t);
  return std::string(buffer, r.ptr);
}

std::vector<m::LibraryLeaf> loadLibrary(const m::PlantPlan& plan) {
  if (!plan.libraryDb) return {};
  if (!std::filesystem::exists(*plan.libraryDb))
    throw m::InputError("library.db " + *plan.libraryDb +
                        " does not exist: name the station's database (leafdig capture writes it)");
  acquisition::OrganLibrary lib;
  try {
    db::Store store(*plan.libraryDb, true);
    lib = acquisition::organLibrary(store);
  } catch (const db::StoreError& e) {  // the same failure, said to be the library's
    throw db::StoreError(e.kind(), std::string("organ library: ") + e.what(), e.remedy());
  }
  for (const auto& s : lib.skipped) std::cerr << "leafdig: organ library: left out " << s << "\n";
  return std::move(lib.leaves);
}

nlohmann::json plantJson(const m::Plant& plant, const m::LeafMesh& mesh, const m::PlantMetrics& metrics) {
  nlohmann::json leaves = nlohmann::json::array();
  for (std::size_t i = 0; i < plant.leaves.size(); ++i) {
    const m::PlacedLeaf& l = plant.leaves[i];
    std::size_t triangles = 0;
    for (const auto& o : mesh.organs)
      if (o.leafRank == l.rank) triangles += o.mesh.triangles.size();
    leaves.push_back({{"rank", l.rank},
                      {"source", l.source},
                      {"insertion_height_mm", l.insertionHeightMm},
                      {"azimuth_deg", l.azimuthDeg},
                      {"inclination_deg", l.inclinationDeg},
                      {"scale", l.scale},
                      {"bend_deg", l.bendDeg},
                      {"length_mm", l.lengthMm},
                      {"width_mm", l.widthMm},
                      {"area_mm2", metrics.leaves[i].areaMm2},
                      {"silhouette_mm2", metrics.leaves[i].silhouetteMm2},
                      {"star", metrics.leaves[i].star},
                      {"triangles", triangles}});
  }
  std::size_t triangles = 0;
  for (const auto& o : mesh.organs) triangles += o.mesh.triangles.size();
  return {
      {"plant", plant.id},
      {"time", plant.time ? nlohmann::json(*plant.time) : nlohmann::json(nullptr)},
      {"stem_height_mm", plant.stemHeightMm},
      {"leaves", leaves},
      {"metrics", {{"area_mm2", metrics.areaMm2}, {"silhouette_mm2", metrics.silhouetteMm2}, {"star", metrics.star}}},
      {"triangles", triangles}};
}

int runPlant(const PlantOptions& o, bool grow) {
  using Clock = std::chrono::steady_clock;
  const auto ms = [](Clock::time_point a, Clock::time_point b) {
    return std::chrono::duration<double, std::milli>(b - a).count();
  };
  const auto t0 = Clock::now();
  // Everything the user typed is checked before any work or any file is touched.
  for (const auto& out : o.outputs) {
    (void)m::plantFormatForPath(out);
    if (grow && o.animate && m::plantFormatForPath(out) != m::PlantFormat::Glb)
      throw m::InputError("output " + out + ": --animate writes a glTF binary; name it .glb");
    if (grow && !o.animate && out.find("{t}") == std::string::npos)
      throw m::InputError("output " + out + ": a growth series needs {t} in the name, e.g. plant-{t}.glb");
  }
  const Eigen::Vector3d light = parseLight(o.light);
  const std::vector<double> times = grow ? parseTimes(o.times) : std::vector<double>{};
  const m::MeshOptions meshOptions = meshOptionsFrom(o.mesh, m::MeshResolution::preset(o.resolution));
  m::PlantPlan plan = m::readPlantPlan(o.planPath);
  if ((grow || o.time) && !plan.growth)
    throw m::InputError(o.planPath + ": the plan has no \"growth\"; add one to build growth states");
  const m::PlantBuilder builder(plan, loadLibrary(plan));
  const auto t1 = Clock::now();
  const m::PlantExportOptions exportOptions{o.canUnit == "cm" ? m::CanUnit::Centimetre : m::CanUnit::Metre,
                                            std::string("leafdig ") + kVersion};

  std::vector<std::optional<double>> states;
  if (grow)
    for (double t : times) states.emplace_back(t);
  else
    states.push_back(o.time);
  // Encode everything first, then write: a failure never leaves some files written.
  std::vector<m::EncodedFile> files;
  nlohmann::json reports = nlohmann::json::array();
  double buildMs = 0, meshMs = 0, metricsMs = 0, encodeMs = 0;
  std::vector<m::Plant> series;  // --animate: every state, for one glTF
  for (const auto& t : states) {
    const auto a = Clock::now();
    const m::Plant p = builder.build(t);
    if (o.animate) series.push_back(p);
    const auto b = Clock::now();
    const m::LeafMesh mesh = m::withOrgans(m::meshPlant(p, meshOptions), m::organChoiceFromString(o.organs));
    const auto c = Clock::now();
    m::PlantMetrics metrics = m::computePlantMetrics(p, mesh, light);
    // The CSV's blade-area intervals (about 12 ms a leaf): for a single plant, not for every
    // state of a growth series, whose leaves are scaled copies of the same markers.
    const bool csv = std::any_of(o.outputs.begin(), o.outputs.end(), [](const std::string& out) {
      return std::filesystem::path(out).extension() == ".csv";
    });
    if (csv && states.size() == 1) m::addAreaIntervals(p, metrics);
    const auto d = Clock::now();
    std::vector<std::filesystem::path> paths;
    for (const auto& out : o.outputs) {
      if (o.animate) break;
      std::string path = out;
      if (t) {
        const auto at = path.find("{t}");
        if (at != std::string::npos) path.replace(at, 3, formatTime(*t));
      }
      paths.emplace_back(path);
    }
    for (auto& f : m::encodePlantFiles(paths, p, mesh, metrics, exportOptions)) files.push_back(std::move(f));
    const auto e = Clock::now();
    buildMs += ms(a, b);
    meshMs += ms(b, c);
    metricsMs += ms(c, d);
    encodeMs += ms(d, e);
    nlohmann::json report = plantJson(p, mesh, metrics);
    if (o.json) {
      report["mesh"] = measuredMeshReportJson(
          mesh, meshOptions, o.mesh.noMeasure, [&] { return m::MeshSubject(p); }, 50'000);
    }
    reports.push_back(std::move(report));
  }
  if (o.animate) {
    const auto a = Clock::now();
    const m::Plant full = builder.build();
    for (const auto& out : o.outputs)
      files.push_back({out, m::encodeGrowthGlb(full, series, meshOptions, exportOptions.generator)});
    encodeMs += ms(a, Clock::now());
  }
  const auto t2 = Clock::now();
  for (const auto& f : files) {
    // A series usually goes into a folder of its own: make it (only now, after every
    // state was built and encoded).
    std::error_code ec;
    if (f.path.has_parent_path()) std::filesystem::create_directories(f.path.parent_path(), ec);
    if (ec) throw m::IoError("cannot create folder " + f.path.parent_path().string() + ": " + ec.message());
    m::writeFileAtomically(f.path, f.bytes);
  }
  const auto t3 = Clock::now();

  if (o.json) {
    nlohmann::json out;
    out["plan"] = o.planPath;
    out["states"] = reports;
    nlohmann::json written = nlohmann::json::array();
    for (const auto& f : files) written.push_back(f.path.string());
    out["outputs"] = written;
    out["timings_ms"] = {{"plan_and_leaves", ms(t0, t1)}, {"build", buildMs},   {"mesh", meshMs},
                         {"metrics", metricsMs},          {"encode", encodeMs}, {"write", ms(t2, t3)}};
    std::cout << out.dump() << "\n";
  } else {
    for (const auto& r : reports) {
      std::cout << "plant " << r["plant"].get<std::string>();
      if (!r["time"].is_null()) std::cout << " at t=" << r["time"].get<double>();
      std::cout << ": stem " << r["stem_height_mm"].get<double>() << " mm, " << r["leaves"].size() << " leaves, "
                << r["triangles"].get<std::size_t>() << " triangles; leaf area "
                << r["metrics"]["area_mm2"].get<double>() << " mm^2, silhouette "
                << r["metrics"]["silhouette_mm2"].get<double>() << " mm^2, STAR " << r["metrics"]["star"].get<double>()
                << "\n";
      if (!grow)
        for (const auto& l : r["leaves"])
          std::cout << "  leaf " << l["rank"].get<int>() << " (" << l["source"].get<std::string>() << "): at "
                    << l["insertion_height_mm"].get<double>() << " mm, azimuth " << l["azimuth_deg"].get<double>()
                    << " deg, inclination " << l["inclination_deg"].get<double>() << " deg, length "
                    << l["length_mm"].get<double>() << " mm\n";
    }
    for (const auto& f : files) std::cout << "  wrote " << f.path.string() << "\n";
  }
  return 0;
}

}  // namespace

void addPlantCommands(CLI::App& app, CommandTable& table) {
  auto o = std::make_shared<PlantOptions>();
  const auto [build, grow] = declarePlantCommands(app, *o);
  table.add(build, [o] { return runPlant(*o, false); });
  table.add(grow, [o] { return runPlant(*o, true); });
  addPlantMeasureCommand(*app.get_subcommand("plant"), table);
  addPlantImportCommand(*app.get_subcommand("plant"), table);
  addPlantProtocolCommand(*app.get_subcommand("plant"), table);
  addPlantCaptureCommand(*app.get_subcommand("plant"), table);
  addPlantSurveysCommand(*app.get_subcommand("plant"), table);
}

}  // namespace leafdig::cli
