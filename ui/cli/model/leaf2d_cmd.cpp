#include "model/leaf2d_cmd.hpp"

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "leafdig/model/errors.hpp"
#include "leafdig/model/files.hpp"
#include "leafdig/model/io/mesh_export.hpp"
#include "leafdig/model/io/scan_json.hpp"
#include "leafdig/model/leaf2d/leaf2d.hpp"
#include "leafdig/model/leaf2d/leaf_scan.hpp"
#include "leafdig/version.hpp"
#include "model/model_build.hpp"

namespace leafdig::cli {

namespace m = leafdig::model;

bool isScanPath(const std::string& path) {
  const std::string ext = m::lowerExtension(path);
  return ext == ".png" || ext == ".tif" || ext == ".tiff" || ext == ".jpg" || ext == ".jpeg" || ext == ".bmp";
}

namespace {

void declareLeaf2dCommands(CLI::App& app, Leaf2dCommandOptions& o) {
  CLI::App* leaf2d = app.add_subcommand("leaf2d", "Leaves known only in 2-D: outlines and scans (seed 001)");
  leaf2d->require_subcommand(1);
  auto scanOptions = [&](CLI::App* c) {
    c->add_option("--dpi", o.dpi, "The scan's resolution, dots per inch (required for an image)");
    c->add_option("--petiole-width", o.petioleWidthMm,
                  "A part narrower than this (mm) and twice as long is the petiole, set apart (default 3; 0: none)");
  };
  CLI::App* build = leaf2d->add_subcommand(
      "build", "Outline (.json leafdig.outline/1, .csv x_mm,y_mm) or scan (.png .tif .jpg) -> curled 3-D blade");
  build->add_option("input", o.input, "Outline file or scan image")->required();
  scanOptions(build);
  build->add_option("--curl", o.curl, "Margin curl: parabola (default), sine, auto (most light), none")
      ->check(CLI::IsMember(wordsIn(model::kCurlKindNames)));
  build->add_option("--amplitude", o.amplitudeMm, "Curl amplitude A, mm (default 10 % of the leaf's width)");
  build->add_option("--light", o.light, "Light direction x,y,z in the leaf frame (default 0,0,1)");
  build->add_option("--rows", o.rows, "Cross-sections from tip to base for the bicubic B-spline (default 30)");
  build->add_option("--measured-area", o.measuredAreaMm2,
                    "The area the curled leaf keeps, mm^2 (default: the scan's or the outline's)");
  build->add_option("-o,--output", o.outputs, "Mesh file to write: .glb .obj .ply .stl (repeat for several)");
  build->add_option("--outline-out", o.outlineOut, "Write the outline used (leafdig.outline/1 JSON)");
  build->add_flag("--json", o.json, "Print areas, curl and counts as one JSON object");

  CLI::App* figure = leaf2d->add_subcommand("figure", "Draw the method on an outline or scan (docs/leaf2d.svg)");
  figure->add_option("input", o.input, "Outline file or scan image")->required();
  scanOptions(figure);
  figure->add_option("--amplitude", o.amplitudeMm, "Curl amplitude A, mm (default 10 % of the leaf's width)");
  figure->add_option("-o,--output", o.figure, "SVG file to write")->required();

  CLI::App* scan = leaf2d->add_subcommand("scan", "Segment a scan: the leaf's outline and area, as ImageJ would");
  scan->add_option("input", o.input, "Scan image (.png .tif .jpg .bmp), the leaf on a light background")->required();
  scanOptions(scan);
  scan->add_option("-o,--output", o.outlineOut, "Write the outline (leafdig.outline/1 JSON)");
  scan->add_flag("--json", o.json, "Print the areas and counts as one JSON object");
}

void printScan(const m::LeafScan& s) {
  std::cout << std::fixed << std::setprecision(1) << "  leaf area " << s.areaMm2 << " mm^2";
  if (s.holes) std::cout << " (" << s.holes << " hole(s), " << s.holesAreaMm2 << " mm^2, not counted)";
  std::cout << "\n";
  if (s.petioleFound)
    std::cout << "  petiole set apart: " << s.petioleAreaMm2 << " mm^2, not counted; the base is where it joins\n";
  if (s.otherObjects) std::cout << "  " << s.otherObjects << " other object(s) on the scan ignored (dust, labels)\n";
  if (s.touchesBorder)
    std::cout << "  warning: the leaf touches the image's edge; it may be cut off — rescan it whole\n";
  if (s.darkBackground) std::cout << "  the background is darker than the leaf (light box): read inverted\n";
}

m::LeafScan scanFrom(const Leaf2dCommandOptions& o) {
  if (!o.dpi) throw m::InputError(o.input + ": a scan needs its resolution: give --dpi (e.g. 300)");
  return m::scanLeaf(o.input, {*o.dpi, o.petioleWidthMm});
}

int runScan(const Leaf2dCommandOptions& o) {
  const auto t0 = std::chrono::steady_clock::now();
  const m::LeafScan scan = scanFrom(o);
  const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  if (!o.outlineOut.empty()) m::writeFileAtomically(o.outlineOut, m::outlineToJson(scan.outline));
  if (o.json) {
    nlohmann::json j = nlohmann::json::parse(m::scanToJson(scan, o.input, *o.dpi));
    j["input"] = o.input;
    j["outline"] = o.outlineOut.empty() ? nlohmann::json() : nlohmann::json(o.outlineOut);
    j["milliseconds"] = {{"scan", ms}};
    std::cout << j.dump(2) << "\n";
  } else {
    std::cout << o.input << " (" << scan.widthPx << " x " << scan.heightPx << " px at " << *o.dpi << " DPI):\n";
    printScan(scan);
    if (!o.outlineOut.empty()) std::cout << "  wrote " << o.outlineOut << "\n";
  }
  return 0;
}

m::Outline2d outlineFrom(const Leaf2dCommandOptions& o, std::optional<m::LeafScan>* scan) {
  if (isScanPath(o.input)) {
    m::LeafScan s = scanFrom(o);
    m::Outline2d outline = s.outline;
    if (scan) *scan = std::move(s);
    return outline;
  }
  if (o.dpi) throw m::InputError("--dpi is for scans; " + o.input + " is an outline in mm");
  return m::readOutlineFile(o.input);
}

int runFigure(const Leaf2dCommandOptions& o) {
  const m::Outline2d outline = outlineFrom(o, nullptr);
  double amplitude = 0.0;
  if (o.amplitudeMm) {
    amplitude = *o.amplitudeMm;
  } else {
    amplitude = 0.1 * m::buildLeaf2d(outline, {}).widthMm;
  }
  m::writeFileAtomically(o.figure, m::leaf2dFigureSvg(outline, amplitude));
  std::cout << "wrote " << o.figure << "\n";
  return 0;
}

int runBuild(const Leaf2dCommandOptions& o) {
  // Everything the user typed is checked before any work or any file is touched.
  std::vector<m::MeshFormat> formats;
  for (const std::string& out : o.outputs) formats.push_back(m::meshFormatForPath(out));
  m::Leaf2dOptions opt;
  opt.rows = o.rows;
  opt.curl = m::curlKindFromString(o.curl);
  opt.amplitudeMm = o.amplitudeMm;
  opt.light = parseLight(o.light);
  opt.measuredAreaMm2 = o.measuredAreaMm2;
  if (o.measuredAreaMm2 && !(*o.measuredAreaMm2 > 0.0))
    throw m::InputError("--measured-area must be a positive area in mm^2");

  const auto t0 = std::chrono::steady_clock::now();
  std::optional<m::LeafScan> scan;
  const m::Outline2d outline = outlineFrom(o, &scan);
  const auto t1 = std::chrono::steady_clock::now();
  const m::Leaf2dModel leaf = m::buildLeaf2d(outline, opt);
  const auto t2 = std::chrono::steady_clock::now();
  m::LeafMesh mesh;
  mesh.organs.push_back({"blade", m::OrganKind::Blade, leaf.mesh, 0});
  const std::string id = outline.id.empty() ? std::filesystem::path(o.input).stem().string() : outline.id;
  const m::ExportHeader header{id, "leaf2d", std::string("leafdig ") + leafdig::kVersion};
  std::vector<std::pair<std::string, std::string>> files;
  for (std::size_t i = 0; i < o.outputs.size(); ++i)
    files.emplace_back(o.outputs[i], m::encodeMesh(mesh, formats[i], header));
  if (!o.outlineOut.empty()) files.emplace_back(o.outlineOut, m::outlineToJson(outline));
  for (const auto& [path, bytes] : files) m::writeFileAtomically(path, bytes);

  const double readMs = std::chrono::duration<double, std::milli>(t1 - t0).count();
  const double buildMs = std::chrono::duration<double, std::milli>(t2 - t1).count();
  if (o.json) {
    nlohmann::json j = nlohmann::json::parse(m::leaf2dToJson(leaf));
    j["input"] = o.input;
    j["scan"] = scan ? nlohmann::json::parse(m::scanToJson(*scan, o.input, *o.dpi)) : nlohmann::json();
    j["outputs"] = o.outputs;
    j["milliseconds"] = {{"read", readMs}, {"build", buildMs}};
    std::cout << j.dump(2) << "\n";
    return 0;
  }
  std::cout << std::fixed << std::setprecision(1) << o.input << ":\n";
  if (scan) printScan(*scan);
  std::cout << "  length " << leaf.lengthMm << " mm, width " << leaf.widthMm << " mm\n"
            << "  outline area " << leaf.outlineAreaMm2 << " mm^2; flat B-spline leaf "
            << (leaf.trimmedToOutline ? "trimmed to the outline (its sinus or lobes) " : "") << leaf.flatModelAreaMm2
            << " mm^2\n"
            << "  curl " << m::toString(leaf.curl) << ", amplitude " << leaf.amplitudeMm << " mm";
  if (leaf.candidates.size() > 1) {
    std::cout << " (chosen for the most light of";
    for (const auto& c : leaf.candidates)
      std::cout << " " << m::toString(c.kind) << " " << c.projectedAreaMm2 << " mm^2";
    std::cout << ")";
  }
  std::cout << "\n  model area " << leaf.modelAreaMm2 << " mm^2 = measured " << leaf.measuredAreaMm2
            << " mm^2 (the area constraint; the margin drew in to " << std::setprecision(2) << 100.0 * leaf.inPlaneScale
            << " %)\n"
            << std::setprecision(1) << "  projected " << leaf.projectedAreaMm2 << " mm^2, silhouette "
            << leaf.silhouetteAreaMm2 << " mm^2\n"
            << "  " << leaf.mesh.triangles.size() << " triangles, built in " << std::setprecision(1) << buildMs
            << " ms\n";
  for (const auto& w : leaf.warnings) std::cout << "  warning (" << w.name << "): " << w.message << "\n";
  for (const auto& [path, bytes] : files) std::cout << "  wrote " << path << "\n";
  return 0;
}

}  // namespace

void addLeaf2dCommands(CLI::App& app, CommandTable& table) {
  auto o = std::make_shared<Leaf2dCommandOptions>();
  declareLeaf2dCommands(app, *o);
  CLI::App* leaf2d = app.get_subcommand("leaf2d");
  table.add(leaf2d->get_subcommand("build"), [o] { return runBuild(*o); });
  table.add(leaf2d->get_subcommand("scan"), [o] { return runScan(*o); });
  table.add(leaf2d->get_subcommand("figure"), [o] { return runFigure(*o); });
}

}  // namespace leafdig::cli
