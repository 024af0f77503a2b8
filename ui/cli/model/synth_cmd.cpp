#include "model/synth_cmd.hpp"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <thread>

#include "commands.hpp"
#include "field_cmd.hpp"
#include "leafdig/model/errors.hpp"
#include "leafdig/model/files.hpp"
#include "leafdig/model/io/mesh_export.hpp"
#include "leafdig/model/leaf/markers_json.hpp"
#include "leafdig/model/leaf2d/leaf_scan.hpp"
#include "leafdig/model/study/accuracy.hpp"
#include "leafdig/version.hpp"
#include "model/model_build.hpp"

namespace leafdig::cli {

namespace m = leafdig::model;

void addSynthChoice(CLI::App& c, SynthChoice& s, const std::string& p) {
  c.add_option("--" + p + "shape", s.shape, "Leaf shape: oblong, elliptic, ovate, obovate or tobacco (default)")
      ->check(CLI::IsMember(wordsIn(model::kLeafShapeNames)));
  c.add_option("--" + p + "length", s.lengthMm, "Base-to-tip length, mm (default 500)");
  c.add_option("--" + p + "width", s.widthMm, "Width of the base rectangle, mm (default: length / the shape's aspect)");
  c.add_option("--" + p + "symmetry", s.symmetry, "S in (-0.45, 0.45): > 0 widest below the middle (ovate)");
  c.add_option("--" + p + "serration", s.serration, "Margin teeth: none (default), round, sharp, straight, acuminate")
      ->check(CLI::IsMember(wordsIn(model::kSerrationNames)));
  c.add_option("--" + p + "tooth-depth", s.toothDepthMm, "Tooth depth D, mm (default 1.5 % of the width)");
  c.add_option("--" + p + "teeth", s.teeth, "Teeth per side (default 20)");
  c.add_option("--" + p + "tooth-direction", s.toothDirection, "horizontal (default) or normal to the margin")
      ->check(CLI::IsMember(wordsIn(model::kToothDirectionNames)));
  c.add_option("--" + p + "width-term", s.widthTerms,
               "Sine-sum width deformation a,k[,phase]: the half-width times 1 + a sin(k φ + phase) (repeat)");
  c.add_option("--" + p + "asymmetry", s.asymmetry, "The left half narrower by this fraction (0..0.5)");
  c.add_option("--" + p + "tip-narrowing", s.tipNarrowing, "Gaussian narrowing at the tip (> 0 drawn out)");
  c.add_option("--" + p + "tip-extent", s.tipExtent, "Its extent, fraction of the length");
  c.add_option("--" + p + "base-narrowing", s.baseNarrowing, "Gaussian narrowing at the base");
  c.add_option("--" + p + "base-extent", s.baseExtent, "Its extent, fraction of the length");
  c.add_option("--" + p + "droop", s.droopDeg, "Midrib turn from base to tip, degrees, tip down (default 25)");
  c.add_option("--" + p + "cup", s.cupMm, "Margin rise at half the width, mm (default 12)");
  c.add_option("--" + p + "twist", s.twistDeg, "Roll of the blade at the tip, degrees (default 5)");
  c.add_option("--" + p + "wave", s.waveMm, "Margin wave amplitude, mm (tobacco 3, else 0)");
  c.add_option("--" + p + "wavelength", s.wavelengthMm, "Margin wave length, mm (tobacco 70, else 80)");
  c.add_option("--" + p + "rows", s.rows, "Marker rows, the last at the leaf base (default 12)");
  c.add_option("--" + p + "vein-angle-tip", s.veinAngleTipDeg, "Lateral vein angle at row 1, degrees (default 50)");
  c.add_option("--" + p + "vein-angle-base", s.veinAngleBaseDeg, "At the last row (default: the shape's, 55 to 75)");
}

m::SyntheticLeafSpec synthSpecFrom(const SynthChoice& c) {
  m::SyntheticLeafSpec s = m::defaultSyntheticSpec(m::leafShapeFromString(c.shape));
  m::OutlineSpec& o = s.outline;
  if (c.lengthMm) o.lengthMm = *c.lengthMm;
  o.widthMm = c.widthMm;
  o.symmetry = c.symmetry;
  const double width = o.widthMm.value_or(o.lengthMm / m::aspectRatio(o.shape));
  o.serration = m::serrationFromString(c.serration);
  if (o.serration == m::Serration::None) {
    if (c.toothDepthMm || c.teeth)
      throw m::InputError("--tooth-depth and --teeth need --serration (round, sharp, ...)");
  } else {
    o.toothDepthMm = c.toothDepthMm.value_or(0.015 * width);
    o.teethPerSide = c.teeth.value_or(20);
  }
  o.toothDirection = m::toothDirectionFromString(c.toothDirection);
  for (const std::string& term : c.widthTerms) {
    std::stringstream in(term);
    m::SineTerm t;
    char comma = 0;
    if (!(in >> t.amplitude >> comma >> t.frequency) || comma != ',')
      throw m::InputError("--width-term '" + term + "' must be a,k or a,k,phase (e.g. 0.05,3 or 0.05,3,1.57)");
    if (in >> comma) {
      if (comma != ',' || !(in >> t.phaseRad))
        throw m::InputError("--width-term '" + term + "' must be a,k or a,k,phase (e.g. 0.05,3,1.57)");
    }
    o.widthTerms.push_back(t);
  }
  if (c.asymmetry) o.asymmetry = *c.asymmetry;
  if (c.tipNarrowing) o.tipNarrowing = *c.tipNarrowing;
  if (c.tipExtent) o.tipExtent = *c.tipExtent;
  if (c.baseNarrowing) o.baseNarrowing = *c.baseNarrowing;
  if (c.baseExtent) o.baseExtent = *c.baseExtent;
  if (c.droopDeg) s.bend.droopDeg = *c.droopDeg;
  if (c.cupMm) s.bend.cupMm = *c.cupMm;
  if (c.twistDeg) s.bend.twistDeg = *c.twistDeg;
  if (c.waveMm) s.bend.waveMm = *c.waveMm;
  if (c.wavelengthMm) s.bend.wavelengthMm = *c.wavelengthMm;
  s.rows = c.rows;
  if (c.veinAngleTipDeg) s.veinAngleTipDeg = *c.veinAngleTipDeg;
  if (c.veinAngleBaseDeg) s.veinAngleBaseDeg = *c.veinAngleBaseDeg;
  if (!c.id.empty()) s.id = c.id;
  if (!c.plant.empty()) s.plant = c.plant;
  return s;
}

SynthChoice parseSynthSpec(const std::string& text) {
  SynthChoice c;
  std::stringstream in(text);
  std::string item;
  const auto number = [](const std::string& key, const std::string& value) {
    std::size_t used = 0;
    double v = 0.0;
    try {
      v = std::stod(value, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == 0 || used != value.size())
      throw m::InputError("synthetic leaf: " + key + "=" + value + " is not a number");
    return v;
  };
  while (std::getline(in, item, ',')) {
    const auto eq = item.find('=');
    if (eq == std::string::npos)
      throw m::InputError("synthetic leaf: '" + item + "' is not key=value (e.g. shape=ovate,rows=10)");
    const std::string key = item.substr(0, eq), value = item.substr(eq + 1);
    if (key == "shape")
      c.shape = value;
    else if (key == "serration")
      c.serration = value;
    else if (key == "tooth-direction")
      c.toothDirection = value;
    else if (key == "length")
      c.lengthMm = number(key, value);
    else if (key == "width")
      c.widthMm = number(key, value);
    else if (key == "symmetry")
      c.symmetry = number(key, value);
    else if (key == "tooth-depth")
      c.toothDepthMm = number(key, value);
    else if (key == "teeth")
      c.teeth = static_cast<int>(number(key, value));
    else if (key == "droop")
      c.droopDeg = number(key, value);
    else if (key == "cup")
      c.cupMm = number(key, value);
    else if (key == "twist")
      c.twistDeg = number(key, value);
    else if (key == "wave")
      c.waveMm = number(key, value);
    else if (key == "wavelength")
      c.wavelengthMm = number(key, value);
    else if (key == "rows")
      c.rows = static_cast<int>(number(key, value));
    else
      throw m::InputError("synthetic leaf: unknown key '" + key +
                          "': use shape, length, width, symmetry, serration, tooth-depth, teeth, tooth-direction, "
                          "droop, cup, twist, wave, wavelength, rows");
  }
  return c;
}

namespace {

void declareSynthCommands(CLI::App& app, SynthOptions& o) {
  CLI::App* synth =
      app.add_subcommand("synth", "Synthetic ground-truth leaves (seed 002) and plants for tests and studies");
  synth->require_subcommand(1);
  CLI::App* leaf = synth->add_subcommand(
      "leaf", "A 3-D leaf with a known area: markers by the protocol (with noise), the truth, the true surface");
  addSynthChoice(*leaf, o.choice, "");
  leaf->add_option("--noise", o.noiseMm, "Gaussian noise per marker coordinate, σ in mm (default 0)");
  leaf->add_option("--seed", o.seed, "Seed of the noise (default 1)")->check(seedText());
  leaf->add_option("--id", o.choice.id, "Leaf id (default SYN-<shape>-<seed>)");
  leaf->add_option("--plant", o.choice.plant, "Plant id (default P-synth)");
  leaf->add_option("--markers", o.markers, "Write the markers here (leafdig.markers/1)")->required();
  leaf->add_option("--truth", o.truth, "Write the truth here (leafdig.truth/1: exact area, veins, outline)")
      ->required();
  leaf->add_option("-o,--output", o.glb, "Write the true blade surface, finely meshed, as .glb (or .obj .ply .stl)");
  leaf->add_option("--svg", o.svg, "Draw the flat outline, veins and markers as SVG");
  leaf->add_flag("--json", o.json, "Print the leaf's figures as JSON");
  CLI::App* scan = synth->add_subcommand(
      "scan", "A flatbed scan of a synthetic leaf's flat blade (PNG) whose area is known exactly");
  addSynthChoice(*scan, o.choice, "");
  scan->add_option("--dpi", o.dpi, "Scan resolution, dots per inch (default 300)")->check(CLI::Range(10.0, 2400.0));
  scan->add_option("--petiole-length", o.petioleLengthMm, "Draw a 2.5 mm wide petiole this long at the base, mm");
  scan->add_option("-o,--output", o.scan, "Image to write: .png or .tif")->required();
  scan->add_option("--truth", o.truth, "Write the truth here (exact flat blade area, base, tip, page)");
  scan->add_flag("--json", o.json, "Print the truth as JSON");
  CLI::App* figure = synth->add_subcommand("figure", "Draw every shape and serration (docs/synthetic-shapes.svg)");
  figure->add_option("-o,--output", o.figure, "SVG file to write")->required();
  CLI::App* study = synth->add_subcommand(
      "study", "The accuracy study (docs/accuracy.md): area, midrib and veins of simulated captures against truth");
  study->add_option("-o,--output", o.study, "Markdown report to write; the CSV and SVG figures go beside it")
      ->required();
  study->add_flag("--quick", o.quick, "A small study (2 shapes, 3 row counts, 2 noise levels) for a quick look");
  study->add_option("--threads", o.threads, "Worker threads (default: every core)")->check(CLI::Range(0, 256));
  study->add_flag("--json", o.json, "Print a summary as JSON");
}

int runScan(const SynthOptions& o) {
  const m::SyntheticLeaf leaf(synthSpecFrom(o.choice));
  if (!(o.petioleLengthMm >= 0.0)) throw m::InputError("--petiole-length must be >= 0 mm");
  constexpr int kPerSide = 2000;
  std::vector<Eigen::Vector2d> outline = leaf.outline(kPerSide);  // right half base to tip, then left
  const Eigen::Vector2d base0 = outline.front();
  const Eigen::Vector2d tip0 = outline[kPerSide];
  const Eigen::Vector2d down = (base0 - tip0).normalized();
  std::vector<Eigen::Vector2d> petiole;
  if (o.petioleLengthMm > 0.0) {
    const Eigen::Vector2d side(-down.y(), down.x());
    const Eigen::Vector2d a = base0 - 1.0 * down;  // 1 mm into the blade: no gap at the joint
    const Eigen::Vector2d b = base0 + o.petioleLengthMm * down;
    petiole = {a + 1.25 * side, b + 1.25 * side, b - 1.25 * side, a - 1.25 * side};
  }
  Eigen::Vector2d lo = outline.front();
  Eigen::Vector2d hi = lo;
  for (const auto* poly : {&outline, &petiole}) {
    for (const auto& p : *poly) {
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
  }
  constexpr double kMarginMm = 20.0;
  const Eigen::Vector2d shift = Eigen::Vector2d(kMarginMm, kMarginMm) - lo;
  for (auto* poly : {&outline, &petiole}) {
    for (auto& p : *poly) p += shift;
  }
  const Eigen::Vector2d page = hi - lo + Eigen::Vector2d(2 * kMarginMm, 2 * kMarginMm);
  std::vector<std::vector<Eigen::Vector2d>> polygons{outline};
  if (!petiole.empty()) polygons.push_back(petiole);
  m::renderScan(polygons, {}, page, o.dpi, o.scan);
  const nlohmann::json truth = {{"format", "leafdig.scan-truth/1"},
                                {"units", "mm"},
                                {"area_mm2", leaf.flatArea()},
                                {"outline_polygon_area_mm2", m::polygonArea(outline)},
                                {"dpi", o.dpi},
                                {"page_mm", {page.x(), page.y()}},
                                {"base_mm", {base0.x() + shift.x(), base0.y() + shift.y()}},
                                {"tip_mm", {tip0.x() + shift.x(), tip0.y() + shift.y()}},
                                {"length_mm", (tip0 - base0).norm()},
                                {"petiole_length_mm", o.petioleLengthMm},
                                {"scan", o.scan}};
  if (!o.truth.empty()) m::writeFileAtomically(o.truth, truth.dump(2) + "\n");
  if (o.json) {
    std::cout << truth.dump(2) << "\n";
  } else {
    std::cout << std::fixed << std::setprecision(2) << "synthetic " << o.choice.shape << " leaf scanned at " << o.dpi
              << " DPI: blade area " << leaf.flatArea() << " mm^2 (exact)\n  wrote " << o.scan
              << (o.truth.empty() ? "" : ", " + o.truth) << "\n";
  }
  return 0;
}

int runLeaf(const SynthOptions& o) {
  SynthChoice choice = o.choice;
  if (choice.id.empty()) choice.id = "SYN-" + choice.shape + "-" + std::to_string(o.seed);
  const m::SyntheticLeaf leaf(synthSpecFrom(choice));
  const m::MarkerSet markers = leaf.markers(o.noiseMm, o.seed);
  // Everything is encoded before the first file is written.
  const std::string markersText = m::markersToJson(markers);
  const std::string truthText = m::truthToJson(leaf, o.noiseMm, o.seed);
  std::string glb, svg;
  if (!o.glb.empty()) {
    glb = m::encodeMesh(leaf.truthMesh(), m::meshFormatForPath(o.glb),
                        {choice.id, "leaf", std::string("leafdig ") + kVersion});
  }
  if (!o.svg.empty()) svg = m::figureSvg({m::figurePanel(leaf, choice.id)}, 1);
  m::writeFileAtomically(o.markers, markersText);
  m::writeFileAtomically(o.truth, truthText);
  if (!o.glb.empty()) m::writeFileAtomically(o.glb, glb);
  if (!o.svg.empty()) m::writeFileAtomically(o.svg, svg);
  double estimate = 0.0;
  const double area = leaf.area(&estimate);
  if (o.json) {
    nlohmann::json doc = {{"id", choice.id},
                          {"shape", choice.shape},
                          {"serration", choice.serration},
                          {"rows", leaf.spec().rows},
                          {"noise_mm", o.noiseMm},
                          {"seed", o.seed},
                          {"length_mm", leaf.spec().outline.lengthMm},
                          {"width_mm", leaf.widthMm()},
                          {"area_mm2", area},
                          {"area_relative_error", estimate},
                          {"flat_area_mm2", leaf.flatArea()},
                          {"markers", o.markers},
                          {"truth", o.truth}};
    if (!o.glb.empty()) doc["output"] = o.glb;
    std::cout << doc.dump(2) << "\n";
  } else {
    std::cout << "synthetic leaf " << choice.id << ": " << choice.shape << ", " << leaf.spec().rows << " rows, noise "
              << o.noiseMm << " mm (seed " << o.seed << ")\n"
              << "  exact area " << area << " mm² (relative error < " << std::max(estimate, 1e-12) << "), flat outline "
              << leaf.flatArea() << " mm²\n"
              << "  wrote " << o.markers << ", " << o.truth;
    if (!o.glb.empty()) std::cout << ", " << o.glb;
    if (!o.svg.empty()) std::cout << ", " << o.svg;
    std::cout << "\n";
  }
  return 0;
}

int runFigure(const SynthOptions& o) {
  std::vector<m::FigurePanel> panels;
  for (m::LeafShape shape : {m::LeafShape::Oblong, m::LeafShape::Elliptic, m::LeafShape::Ovate, m::LeafShape::Obovate,
                             m::LeafShape::Tobacco}) {
    m::SyntheticLeafSpec s = m::defaultSyntheticSpec(shape);
    s.outline.lengthMm = 300;
    s.rows = 8;
    panels.push_back(m::figurePanel(m::SyntheticLeaf(s), m::toString(shape)));
  }
  for (m::Serration kind :
       {m::Serration::Round, m::Serration::Sharp, m::Serration::Straight, m::Serration::Acuminate}) {
    m::SyntheticLeafSpec s = m::defaultSyntheticSpec(m::LeafShape::Elliptic);
    s.outline.lengthMm = 300;
    s.outline.serration = kind;
    s.outline.teethPerSide = 9;
    s.outline.toothDepthMm = 8;
    s.rows = 8;
    panels.push_back(m::figurePanel(m::SyntheticLeaf(s), std::string(m::toString(kind)) + " teeth"));
  }
  m::SyntheticLeafSpec s = m::defaultSyntheticSpec(m::LeafShape::Ovate);
  s.outline.lengthMm = 300;
  s.outline.serration = m::Serration::Acuminate;
  s.outline.teethPerSide = 12;
  s.outline.toothDepthMm = 6;
  s.outline.toothDirection = m::ToothDirection::Normal;
  s.outline.widthTerms = {{0.06, 5.0, 0.0}};
  s.rows = 8;
  panels.push_back(m::figurePanel(m::SyntheticLeaf(s), "ovate, normal teeth, sine term"));
  m::writeFileAtomically(o.figure, m::figureSvg(panels, 5));
  std::cout << "wrote " << o.figure << " (" << panels.size() << " leaves)\n";
  return 0;
}

}  // namespace

namespace {

int runStudy(const SynthOptions& o) {
  const std::filesystem::path report(o.study);
  if (report.extension() != ".md") {
    std::cerr << "error: the study report must be a Markdown file (.md), e.g. docs/accuracy.md\n";
    return 2;
  }
  const std::filesystem::path dir = report.has_parent_path() ? report.parent_path() : std::filesystem::path(".");
  if (!std::filesystem::is_directory(dir)) {
    std::cerr << "error: the folder " << dir.string() << " does not exist: create it or choose another -o\n";
    return 2;
  }
  const m::AccuracyPlan plan = o.quick ? m::AccuracyPlan::quick() : m::AccuracyPlan::full();
  const int threads = o.threads > 0 ? o.threads : static_cast<int>(std::max(1U, std::thread::hardware_concurrency()));
  const auto start = std::chrono::steady_clock::now();
  const bool tty = isatty(STDERR_FILENO) != 0;
  const std::vector<m::AccuracyResult> results =
      m::runAccuracyStudy(plan, threads, [&](std::size_t done, std::size_t total) {
        if (tty) std::cerr << "\rstudy: " << done << " / " << total << " captures" << std::flush;
      });
  if (tty) std::cerr << "\n";
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const std::string command = std::string("leafdig synth study") + (o.quick ? " --quick" : "") + " -o " +
                              (std::filesystem::path("docs") / report.filename()).string();
  const m::AccuracyReport r = m::accuracyReport(plan, results, command);
  std::filesystem::path csv = report;
  csv.replace_extension(".csv");
  // With the field study's leaves through a bent field (issue 50): the errors a clean field leaves out.
  m::writeFileAtomically(report.string(), r.markdown + (o.quick ? std::string() : fieldAccuracySection()));
  m::writeFileAtomically(csv.string(), r.csv);
  for (const auto& [name, svg] : r.figures) m::writeFileAtomically((dir / name).string(), svg);
  std::size_t checked = 0, inside = 0;
  for (const m::AccuracyResult& a : results) {
    checked += a.intervalChecked ? 1 : 0;
    inside += a.inInterval ? 1 : 0;
  }
  if (o.json) {
    nlohmann::json j;
    j["report"] = report.string();
    j["csv"] = csv.string();
    j["figures"] = nlohmann::json::array();
    for (const auto& f : r.figures) j["figures"].push_back((dir / f.first).string());
    j["reconstructions"] = results.size();
    j["seconds"] = seconds;
    j["threads"] = threads;
    j["interval_checked"] = checked;
    j["interval_holds_truth"] = inside;
    std::cout << j.dump(2) << "\n";
  } else {
    std::cout << "wrote " << report.string() << ", " << csv.string() << " and " << r.figures.size()
              << " figures: " << results.size() << " reconstructions in " << std::fixed << std::setprecision(1)
              << seconds << " s on " << threads << " threads\n";
  }
  return 0;
}

}  // namespace

void addSynthCommands(CLI::App& app, CommandTable& table) {
  auto o = std::make_shared<SynthOptions>();
  declareSynthCommands(app, *o);
  CLI::App* synth = app.get_subcommand("synth");
  table.add(synth->get_subcommand("leaf"), [o] { return runLeaf(*o); });
  table.add(synth->get_subcommand("scan"), [o] { return runScan(*o); });
  table.add(synth->get_subcommand("figure"), [o] { return runFigure(*o); });
  table.add(synth->get_subcommand("study"), [o] { return runStudy(*o); });
  addSynthPlantCommand(*synth, table);
}

}  // namespace leafdig::cli
