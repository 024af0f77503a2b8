#include "model/model_build.hpp"

#include <algorithm>
#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "commands.hpp"
#include "leafdig/model/errors.hpp"
#include "leafdig/model/files.hpp"
#include "leafdig/model/io/leaf_build.hpp"
#include "leafdig/model/io/mesh_export.hpp"
#include "leafdig/model/io/model_json.hpp"
#include "leafdig/model/io/plant_export.hpp"
#include "leafdig/model/io/scan_json.hpp"
#include "leafdig/model/leaf/leaf_model.hpp"
#include "leafdig/model/leaf/markers_json.hpp"
#include "leafdig/model/leaf2d/leaf_scan.hpp"
#include "leafdig/model/mesh/mesh.hpp"
#include "leafdig/model/metrics/metrics.hpp"
#include "leafdig/model/plant/plant.hpp"
#include "leafdig/model/study/mesh_study.hpp"
#include "leafdig/version.hpp"

namespace leafdig::cli {

namespace m = leafdig::model;

namespace {

void declareModelBuild(CLI::App& model, ModelBuildOptions& o) {
  CLI::App* build =
      model.add_subcommand("build", "Build the BBSC veins and blade from a leafdig.markers/1 file and export them");
  build->add_option("markers", o.markersPath, "Marker file (leafdig.markers/1 JSON)")->required();
  build->add_option("-o,--output", o.outputs,
                    "Mesh file to write; the format follows the extension: .glb .obj .ply .stl "
                    "(repeat for several)");
  build->add_option("--model-json", o.modelJsonPath, "Write the leafdig.model/1 document here");
  build->add_option("--blade", o.blade, "Blade surface: interp (default), approx, bezier, nurbs")
      ->check(CLI::IsMember(wordsIn(model::kBladeKindNames)));
  build
      ->add_option("--resolution", o.resolution,
                   "Mesh resolution preset: paper (the seed's Table 1 counts), preview, export "
                   "(default)")
      ->check(CLI::IsMember({"paper", "preview", "export", "reference"}));
  build
      ->add_option("--caps", o.caps,
                   "Vein end caps: none or sphere (default: the preset's; paper "
                   "has none)")
      ->check(CLI::IsMember({"none", "sphere"}));
  build->add_option("--frame", o.frame, "Frame of the exports: digitizer (default) or leaf")
      ->check(CLI::IsMember({"digitizer", "leaf"}));
  build->add_option("--light", o.light,
                    "Light direction x,y,z in the export frame for the projected area (default "
                    "0,0,1)");
  build->add_option("--measured-area", o.measuredAreaMm2,
                    "Measured leaf area in mm^2 (leaf area meter or image); compared with the "
                    "model's (overrides leaf.measured_area_mm2 of the file)");
  build->add_option("--measured-area-scan", o.measuredAreaScan,
                    "A scan of the leaf (.png .tif .jpg, on a light background): its blade area, holes "
                    "filled and petiole set apart, is the measured area (needs --dpi)");
  build->add_option("--dpi", o.scanDpi, "The scan's resolution, dots per inch");
  build->add_option("--area-threshold", o.areaThresholdPercent,
                    "Flag a model/measured area difference above this percentage (default 5)");
  build->add_flag("--json", o.json, "Print metrics and mesh counts as one JSON object");
  addMeshChoice(*build, o.mesh);
}

}  // namespace

Eigen::Vector3d parseLight(const std::string& text) {
  std::stringstream in(text);
  Eigen::Vector3d d;
  char comma1 = 0;
  char comma2 = 0;
  in >> d.x() >> comma1 >> d.y() >> comma2 >> d.z();
  if (!in || comma1 != ',' || comma2 != ',' || !in.eof() || !d.allFinite() || d.cwiseAbs().maxCoeff() == 0.0) {
    throw m::InputError("--light \"" + text +
                        "\": expected three numbers x,y,z, not all zero, "
                        "e.g. --light 0,0,1");
  }
  // Only its direction counts: scaled so its largest component is 1 (1e200,0,0 would
  // overflow a norm and leave no light at all).
  return d / d.cwiseAbs().maxCoeff();
}

namespace {

// The same file named twice (an input as an output, or one output twice) would be read and
// overwritten: refused before anything is read or written.
bool sameFile(const std::string& a, const std::string& b) {
  std::error_code ec;
  if (std::filesystem::exists(a, ec) && std::filesystem::exists(b, ec)) return std::filesystem::equivalent(a, b, ec);
  return std::filesystem::weakly_canonical(a, ec) == std::filesystem::weakly_canonical(b, ec);
}

void refuseSameFile(const ModelBuildOptions& o) {
  std::vector<std::pair<std::string, std::string>> named;  // option, path
  named.emplace_back("the markers file", o.markersPath);
  if (!o.measuredAreaScan.empty()) named.emplace_back("--measured-area-scan", o.measuredAreaScan);
  const std::size_t inputs = named.size();
  for (const auto& out : o.outputs) named.emplace_back("-o", out);
  if (!o.modelJsonPath.empty()) named.emplace_back("--model-json", o.modelJsonPath);
  for (std::size_t i = 0; i < named.size(); ++i)
    for (std::size_t j = std::max(i + 1, inputs); j < named.size(); ++j)
      if (sameFile(named[i].second, named[j].second))
        throw m::InputError(named[j].first + " " + named[j].second + " is the same file as " + named[i].first +
                            (i < inputs ? ": it would overwrite the input" : ": it would be written twice") +
                            "; give another output path");
}

nlohmann::json countsJson(const m::MeshCounts& c) {
  return {{"vertices", c.vertices}, {"quads", c.quads}, {"triangles", c.triangles}};
}

}  // namespace

int runModelBuild(const ModelBuildOptions& o) {
  // Everything the user typed is checked before any work or any file is touched.
  // Meshes by encodeMesh; the simulation formats through the leaf as a plant of one leaf.
  refuseSameFile(o);
  std::vector<std::optional<m::MeshFormat>> formats;
  for (const std::string& out : o.outputs) {
    const m::PlantFormat f = m::plantFormatForPath(out);
    if (f == m::PlantFormat::Json) {
      throw m::InputError("output " + out + ": write the model document with --model-json");
    }
    const bool simulation = f == m::PlantFormat::Can || f == m::PlantFormat::Mtg || f == m::PlantFormat::Csv ||
                            f == m::PlantFormat::HeliosXml || f == m::PlantFormat::Vgx;
    formats.push_back(simulation ? std::nullopt : std::optional<m::MeshFormat>(m::meshFormatForPath(out)));
  }
  const Eigen::Vector3d light = parseLight(o.light);
  if (o.measuredAreaMm2 && !(*o.measuredAreaMm2 > 0.0)) {
    throw m::InputError("--measured-area must be a positive area in mm^2");
  }
  m::MeshResolution resolution = m::MeshResolution::preset(o.resolution);
  if (!o.caps.empty()) {
    resolution.caps = o.caps == "sphere" ? m::CapStyle::Sphere : m::CapStyle::None;
    if (resolution.caps == m::CapStyle::Sphere && resolution.capRings == 0) resolution.capRings = 3;
  }

  const m::MeshOptions meshOptions = meshOptionsFrom(o.mesh, resolution);

  if (!o.measuredAreaScan.empty() && o.measuredAreaMm2) {
    throw m::InputError("give --measured-area or --measured-area-scan, not both");
  }
  if (!o.measuredAreaScan.empty() && !o.scanDpi) {
    throw m::InputError("--measured-area-scan needs the scan's resolution: give --dpi (e.g. 300)");
  }
  if (o.scanDpi && o.measuredAreaScan.empty()) throw m::InputError("--dpi is for --measured-area-scan");

  m::MarkerSet markers = m::readMarkersFile(o.markersPath);
  if (o.measuredAreaMm2) markers.leaf.measuredAreaMm2 = o.measuredAreaMm2;
  std::optional<m::LeafScan> scan;
  if (!o.measuredAreaScan.empty()) {
    // The 3-D model has no holes: it is compared with the blade's area with holes filled.
    scan = m::scanLeaf(o.measuredAreaScan, {*o.scanDpi});
    markers.leaf.measuredAreaMm2 = scan->filledAreaMm2;
    // The scan's margin at the markers' spacing along it: the interval's margin term.
    markers.leaf.marginFromScan = m::MarginFromScan{m::marginFromOutline(scan->outline, m::marginSpacingMm(markers))};
  }
  const m::BuiltLeaf built = m::buildLeafAsModelBuild(markers, m::bladeKindFromString(o.blade), o.frame, meshOptions,
                                                      light, o.areaThresholdPercent);
  const m::LeafModel& leaf = built.model;
  const m::LeafMesh& mesh = built.mesh;
  const m::LeafMetrics& metrics = built.metrics;
  const m::ExportHeader header{leaf.markers.leaf.id, o.frame, std::string("leafdig ") + leafdig::kVersion};

  // Encode everything first, then write: a build error never leaves some files written.
  std::vector<std::pair<std::string, std::string>> files;
  std::optional<m::LeafAsPlant> alone;  // made when a simulation format is asked for
  for (std::size_t i = 0; i < o.outputs.size(); ++i) {
    if (formats[i]) {
      files.emplace_back(o.outputs[i], m::encodeMesh(mesh, *formats[i], header));
      continue;
    }
    if (!alone) alone = m::leafAsPlant(built, o.markersPath, light);
    for (auto& f :
         m::encodePlant(o.outputs[i], alone->plant, alone->mesh, alone->metrics, {m::CanUnit::Metre, header.generator}))
      files.emplace_back(f.path.string(), std::move(f.bytes));
  }
  if (!o.modelJsonPath.empty()) {
    files.emplace_back(o.modelJsonPath, m::modelToJson(leaf, o.frame, metrics));
  }
  for (const auto& [path, bytes] : files) m::writeFileAtomically(path, bytes);

  const m::MeshCounts veins = m::countVeins(mesh);
  const m::MeshCounts blade = m::countBlade(mesh);
  if (o.json) {
    nlohmann::json out;
    out["leaf"] = leaf.markers.leaf.id;
    out["rows"] = leaf.markers.rows.size();
    out["points"] = 7 * leaf.markers.rows.size() + 1;
    out["thickness_mode"] = m::toString(leaf.thickness.mode);
    out["blade"] = o.blade;
    out["resolution"] = resolution.name;
    out["frame"] = o.frame;
    out["metrics"] = nlohmann::json::parse(m::metricsToJson(metrics));
    if (scan) {
      out["measured_area_scan"] = nlohmann::json::parse(m::scanToJson(*scan, o.measuredAreaScan, *o.scanDpi));
    }
    out["mesh"] = measuredMeshReportJson(
        mesh, meshOptions, o.mesh.noMeasure, [&] { return m::MeshSubject(leaf); }, 100'000);
    out["mesh"]["veins"] = countsJson(veins);
    out["mesh"]["blade"] = countsJson(blade);
    nlohmann::json warnings = nlohmann::json::array();
    for (const auto& w : mesh.warnings) {
      warnings.push_back({{"organ", w.organ}, {"parameter", w.parameter}, {"message", w.message}});
    }
    out["warnings"] = warnings;
    nlohmann::json written = nlohmann::json::array();
    for (const auto& f : files) written.push_back(f.first);
    out["outputs"] = written;
    std::cout << out.dump() << "\n";
  } else {
    std::cout << "leaf " << (leaf.markers.leaf.id.empty() ? "(no id)" : leaf.markers.leaf.id) << ": "
              << leaf.markers.rows.size() << " rows, " << 7 * leaf.markers.rows.size() + 1 << " points, "
              << m::toString(leaf.thickness.mode) << " thickness mode\n"
              << "  veins: " << veins.vertices << " vertices, " << veins.quads << " quads, " << veins.triangles
              << " triangles\n"
              << "  blade: " << blade.vertices << " vertices, " << blade.quads << " quads, " << blade.triangles
              << " triangles (" << o.blade << ", " << m::toString(meshOptions.method) << ": "
              << m::describe(meshOptions) << ")\n"
              << "  blade area " << metrics.blade.areaMm2 << " mm^2, projected " << metrics.blade.projectedAreaMm2
              << " mm^2\n";
    if (metrics.areaInterval) {
      std::cout << "  blade area 95 % interval " << metrics.areaInterval->low95Mm2 << " – "
                << metrics.areaInterval->high95Mm2 << " mm^2 (digitizer accuracy " << metrics.areaInterval->sigmaMm
                << " mm, rows' interpolation)\n";
    }
    if (scan) {
      std::cout << "  scan " << o.measuredAreaScan << ": blade " << scan->filledAreaMm2 << " mm^2 (tissue "
                << scan->areaMm2 << " mm^2, " << scan->holes << " hole(s); petiole "
                << (scan->petioleFound ? "set apart" : "none found") << ")\n";
    }
    if (metrics.areaConstraint) {
      const auto& a = *metrics.areaConstraint;
      std::cout << "  measured area " << a.measuredMm2 << " mm^2: model differs by " << a.differencePercent << " %"
                << (a.exceeded ? " — ABOVE the threshold" : "") << "\n";
    }
    for (const auto& w : metrics.warnings) std::cout << "  warning (" << w.name << "): " << w.message << "\n";
    for (const auto& w : mesh.warnings) {
      std::cout << "  warning: " << w.organ << " at t=" << w.parameter << ": " << w.message << "\n";
    }
    for (const auto& f : files) std::cout << "  wrote " << f.first << "\n";
  }
  return 0;
}

void addModelCommands(CLI::App& app, CommandTable& table) {
  CLI::App* model = app.add_subcommand("model", "Build leaf models from marker files");
  model->require_subcommand(1);
  auto o = std::make_shared<ModelBuildOptions>();
  declareModelBuild(*model, *o);
  table.add(model->get_subcommand("build"), [o] { return runModelBuild(*o); });
}

}  // namespace leafdig::cli
