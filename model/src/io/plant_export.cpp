#include "leafdig/model/io/plant_export.hpp"

#include <algorithm>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <sstream>

#include "fixed_text.hpp"
#include "io/mtg_text.hpp"
#include "json_text.hpp"
#include "leafdig/model/errors.hpp"
#include "leafdig/model/files.hpp"
#include "leafdig/model/io/csv_text.hpp"
#include "leafdig/model/io/model_json.hpp"
#include "leafdig/model/io/simulator_export.hpp"
#include "leafdig/model/metrics/metrics.hpp"
#include "parallel.hpp"

namespace leafdig::model {

namespace {

const Mesh* bladeOf(const LeafMesh& mesh, int rank) {
  for (const Organ& o : mesh.organs)
    if (o.leafRank == rank && o.kind == OrganKind::Blade) return &o.mesh;
  return nullptr;
}

using detail::mtgAlpha;
// Fixed notation with three decimals (the MTG's and the CSV's numbers).
std::string fixed3(double v) {
  return detail::mtgReal(v);
}

const LeafLight* lightOf(const PlantMetrics& m, int rank) {
  for (const LeafLight& l : m.leaves)
    if (l.rank == rank) return &l;
  return nullptr;
}

}  // namespace

PlantFormat plantFormatForPath(const std::filesystem::path& path) {
  const std::string ext = lowerExtension(path);
  if (ext == ".glb") return PlantFormat::Glb;
  if (ext == ".obj") return PlantFormat::Obj;
  if (ext == ".ply") return PlantFormat::Ply;
  if (ext == ".stl") return PlantFormat::Stl;
  if (ext == ".can") return PlantFormat::Can;
  if (ext == ".mtg") return PlantFormat::Mtg;
  if (ext == ".csv") return PlantFormat::Csv;
  if (ext == ".json") return PlantFormat::Json;
  if (ext == ".xml") return PlantFormat::HeliosXml;
  if (ext == ".vgx") return PlantFormat::Vgx;
  throw InputError(
      "output " + path.string() + ": unknown format \"" + ext +
      "\"; name the file .glb, .obj, .ply, .stl, .can, .mtg, .csv, .json, .xml (Helios) or .vgx (VegeSTAR)");
}

PlantMetrics computePlantMetrics(const Plant& plant, const LeafMesh& mesh, const Eigen::Vector3d& lightDirection) {
  PlantMetrics out;
  out.lightDirection = lightDirection.normalized();
  std::vector<const Mesh*> blades;
  for (const PlacedLeaf& leaf : plant.leaves) {
    blades.push_back(bladeOf(mesh, leaf.rank));
    LeafLight l;
    l.rank = leaf.rank;
    out.leaves.push_back(l);
  }
  std::vector<const Mesh*> all;
  for (const Mesh* b : blades)
    if (b != nullptr) all.push_back(b);
  // Each leaf's silhouette and the plant's are independent rasters: on every core, the
  // plant's (the largest) first.
  std::vector<std::size_t> order{blades.size()};
  for (std::size_t i = 0; i < blades.size(); ++i) order.push_back(i);
  detail::parallelFor(
      blades.size() + 1, 0,
      [&](std::size_t i) {
        if (i == blades.size()) {
          out.silhouetteMm2 = all.empty() ? 0.0 : silhouetteArea(all, out.lightDirection);
          return;
        }
        if (blades[i] == nullptr) return;
        // The leaf alone, as a lone leaf's metrics have it (leafSilhouette); the plant's own
        // raster keeps 2048 pixels.
        LeafLight& l = out.leaves[i];
        const LeafSilhouette alone = leafSilhouette(*blades[i], out.lightDirection);
        l.areaMm2 = alone.meshAreaMm2;
        l.silhouetteMm2 = alone.silhouetteMm2;
        l.star = alone.star;
      },
      order);
  for (const LeafLight& l : out.leaves) out.areaMm2 += l.areaMm2;
  out.star = out.areaMm2 > 0 ? out.silhouetteMm2 / out.areaMm2 : 0.0;
  return out;
}

CanFile encodeCan(const LeafMesh& mesh, CanUnit unit, int plantNumber) {
  if (plantNumber < 0 || plantNumber > 99999) throw InputError("a CARIBU plant number has 5 digits (0 to 99999)");
  const int decimals = unit == CanUnit::Metre ? 6 : 4;
  CanFile out;
  std::string text;
  std::size_t all = 0;
  for (const Organ& organ : mesh.organs) all += organ.mesh.triangles.size();
  text.reserve(112 * all);  // one allocation: a line is about 100 characters
  int lastRank = -1;
  int element = 0;
  for (const Organ& organ : mesh.organs) {
    if (organ.leafRank != lastRank) {
      lastRank = organ.leafRank;
      element = 0;
    }
    ++element;
    // The wood (leaf field 000: the stem and every axis) of a tree can have more than 999 axes
    // (an archive's walnut has 1 500): the 999th and later share element 999. A leaf's organs
    // stay one element each.
    if (organ.leafRank == 0) element = std::min(element, 999);
    if (organ.leafRank > 999 || element > 999) throw InputError("a CARIBU label has 3 digits for leaf and element");
    char label[32];
    std::snprintf(label, sizeof label, "1%05d%03d%03d", plantNumber, organ.leafRank, element);
    // Each vertex in micrometres once (a vertex is shared by about six triangles).
    std::vector<Eigen::Matrix<long long, 3, 1>> um(organ.mesh.positions.size());
    for (std::size_t i = 0; i < um.size(); ++i)
      for (int c = 0; c < 3; ++c) um[i][c] = std::llround(organ.mesh.positions[i][c] * 1000.0);  // mm → µm
    for (const auto& t : organ.mesh.triangles) {
      const std::array<const Eigen::Matrix<long long, 3, 1>*, 3> v{&um[t[0]], &um[t[1]], &um[t[2]]};
      const Eigen::Matrix<long long, 3, 1> n = (*v[1] - *v[0]).cross(*v[2] - *v[0]);
      if (n.isZero()) {  // collinear once written: CARIBU rejects it
        ++out.dropped;
        continue;
      }
      // A line is formatted in a buffer and appended once; the geometry's length is checked
      // in place. Nine numbers of at most 20 characters each fit.
      char line[256];
      char* w = line;
      for (const char c : std::string_view("p 1 ")) *w++ = c;
      for (const char* l = label; *l != '\0'; ++l) *w++ = *l;
      char* const geometryStart = w;
      *w++ = ' ';
      *w++ = '3';
      char* lastStart = w;
      for (const auto* p : v) {
        for (int c = 0; c < 3; ++c) {
          *w++ = ' ';
          lastStart = w;
          w = detail::writeScaled(w, (*p)[c], decimals);
        }
      }
      // canestrad copies the last number once more into its 125-byte buffer.
      const auto geometry = static_cast<std::size_t>(w - geometryStart);
      if (geometry + 1 + static_cast<std::size_t>(w - lastStart) > 124) {
        throw InputError(
            "CARIBU geometry line of " + std::to_string(geometry) + " characters exceeds canestrad's 124 (line " +
            std::string(line, std::min<std::ptrdiff_t>(40, w - line)) + "…): the plant is too large for this unit");
      }
      *w++ = '\n';
      text.append(line, static_cast<std::size_t>(w - line));
      ++out.triangles;
    }
  }
  out.text = std::move(text);
  return out;
}

std::string encodeCaribuOpt() {
  // n: species; s d: soil reflectance; e d <stem r> d <upper r> <upper t> d <lower r> <lower t>.
  return "n 1\ns d 0.20\ne d 0.10  d 0.10 0.05  d 0.10 0.05\n";
}

std::string encodeMtg(const Plant& plant, const PlantMetrics& metrics) {
  if (!plant.stem && plant.leaves.size() > 1) throw InputError("an MTG of leaves without a stem holds one leaf");
  static const std::vector<std::pair<const char*, const char*>> kFeatures{
      {"rank", "INT"},     {"leaf_id", "ALPHA"},    {"insertion_height", "REAL"},
      {"azimuth", "REAL"}, {"inclination", "REAL"}, {"length", "REAL"},
      {"width", "REAL"},   {"area", "REAL"},        {"silhouette", "REAL"},
      {"base_x", "REAL"},  {"base_y", "REAL"},      {"base_z", "REAL"},
      {"tip_x", "REAL"},   {"tip_y", "REAL"},       {"tip_z", "REAL"}};
  std::ostringstream out;
  out << "# leafdig plant " << mtgAlpha(plant.id) << (plant.time ? " at time " + fixed3(*plant.time) : std::string())
      << "\n# lengths mm, angles degrees, areas mm2, plant frame: origin at the stem base, +Z up the stem\n"
      << "# internodes: width is the stem diameter at mid-internode; leaves: length along the midrib, width the "
         "widest row\n";
  detail::writeMtgHeader(out, kFeatures);
  const auto line = [&out](int depth, const std::string& entity, std::vector<std::string> values) {
    detail::writeMtgLine(out, depth, entity, std::move(values));
  };
  std::vector<const PlacedLeaf*> order;
  for (const PlacedLeaf& l : plant.leaves) order.push_back(&l);
  std::stable_sort(order.begin(), order.end(),
                   [](const auto* a, const auto* b) { return a->insertionHeightMm < b->insertionHeightMm; });
  // Internodes between insertions, along the stem (digitized stems may curve).
  const auto internode = [&](int index, double from, double to) {
    const double h = plant.stemHeightMm > 0 ? plant.stemHeightMm : 1.0;
    const StemPoint a = stemPointAt(plant, from / h);
    const StemPoint b = stemPointAt(plant, to / h);
    const StemPoint mid = stemPointAt(plant, (from + to) / 2 / h);
    line(
        0, index == 1 ? "/P1/I1" : "^<I" + std::to_string(index),
        {"", "", fixed3(from), "", "", fixed3(to - from), fixed3(2 * mid.radius), "", "", fixed3(a.center.x()),
         fixed3(a.center.y()), fixed3(a.center.z()), fixed3(b.center.x()), fixed3(b.center.y()), fixed3(b.center.z())});
  };
  int index = 0;
  double below = 0.0;
  for (const PlacedLeaf* leaf : order) {
    // A leaf exported alone (no stem) is the plant's only component: /P1/L<rank>.
    const bool alone = !plant.stem;
    if (!alone) {
      internode(++index, below, leaf->insertionHeightMm);
      below = leaf->insertionHeightMm;
    }
    const LeafLight* light = lightOf(metrics, leaf->rank);
    line(alone ? 0 : 1, (alone ? "/P1/L" : "+L") + std::to_string(leaf->rank),
         {std::to_string(leaf->rank),
          mtgAlpha(leaf->model.markers.leaf.id.empty() ? leaf->source : leaf->model.markers.leaf.id),
          fixed3(leaf->insertionHeightMm), fixed3(leaf->azimuthDeg), fixed3(leaf->inclinationDeg),
          fixed3(leaf->lengthMm), fixed3(leaf->widthMm), fixed3(light ? light->areaMm2 : 0.0),
          fixed3(light ? light->silhouetteMm2 : 0.0), fixed3(leaf->base.x()), fixed3(leaf->base.y()),
          fixed3(leaf->base.z()), fixed3(leaf->tip.x()), fixed3(leaf->tip.y()), fixed3(leaf->tip.z())});
  }
  if (plant.stem && (plant.stemHeightMm > below || index == 0)) internode(++index, below, plant.stemHeightMm);
  return out.str();
}

void addAreaIntervals(const Plant& plant, PlantMetrics& metrics) {
  for (LeafLight& light : metrics.leaves) {
    for (const PlacedLeaf& l : plant.leaves) {
      if (l.rank != light.rank || !l.shapeDigitized) continue;
      AreaUncertaintyOptions options;
      options.blade = l.model.blade.kind;
      const AreaUncertainty u = areaUncertainty(l.model.markers, options);
      light.bladeAreaLow95Mm2 = u.low95Mm2;
      light.bladeAreaHigh95Mm2 = u.high95Mm2;
    }
  }
}

std::string encodePlantCsv(const Plant& plant, const PlantMetrics& metrics) {
  std::ostringstream out;
  out << "plant,organ,rank,leaf_id,source,insertion_height_mm,azimuth_deg,inclination_deg,roll_deg,scale,bend_deg,"
         "length_mm,width_mm,area_mm2,silhouette_mm2,star,base_x_mm,base_y_mm,base_z_mm,tip_x_mm,tip_y_mm,tip_z_mm,"
         "blade_area_low95_mm2,blade_area_high95_mm2\n";
  const std::string id = csvText(plant.id);
  if (plant.stem) {
    const Eigen::Vector3d apex = stemPointAt(plant, 1.0).center;
    out << id << ",stem,0,,,0.000,,,,,," << fixed3(plant.stemHeightMm) << "," << fixed3(plant.stemBaseDiameterMm)
        << ",,,,0.000,0.000,0.000," << fixed3(apex.x()) << "," << fixed3(apex.y()) << "," << fixed3(apex.z()) << ",,\n";
  }
  for (const PlacedLeaf& l : plant.leaves) {
    const LeafLight* light = lightOf(metrics, l.rank);
    out << id << ",leaf," << l.rank << "," << csvText(l.model.markers.leaf.id) << "," << csvText(l.source) << ","
        << fixed3(l.insertionHeightMm) << "," << fixed3(l.azimuthDeg) << "," << fixed3(l.inclinationDeg) << ","
        << fixed3(l.rollDeg) << "," << detail::formatNumber(l.scale) << "," << fixed3(l.bendDeg) << ","
        << fixed3(l.lengthMm) << "," << fixed3(l.widthMm) << "," << fixed3(light ? light->areaMm2 : 0.0) << ","
        << fixed3(light ? light->silhouetteMm2 : 0.0) << "," << (light ? detail::formatNumber(light->star) : "") << ","
        << fixed3(l.base.x()) << "," << fixed3(l.base.y()) << "," << fixed3(l.base.z()) << "," << fixed3(l.tip.x())
        << "," << fixed3(l.tip.y()) << "," << fixed3(l.tip.z()) << ","
        << (light && light->bladeAreaLow95Mm2 ? fixed3(*light->bladeAreaLow95Mm2) : "") << ","
        << (light && light->bladeAreaHigh95Mm2 ? fixed3(*light->bladeAreaHigh95Mm2) : "") << "\n";
  }
  return out.str();
}

std::string encodePlantJson(const Plant& plant, const PlantMetrics& metrics) {
  using json = nlohmann::json;
  json doc;
  doc["format"] = "leafdig.plant-model/1";
  doc["units"] = "mm";
  doc["frame"] = "plant: origin at the stem base, +Z up the stem axis";
  doc["id"] = plant.id;
  doc["time"] = plant.time ? json(*plant.time) : json(nullptr);
  doc["time_unit"] = plant.timeUnit.empty() ? json(nullptr) : json(plant.timeUnit);
  json balls = json::array();
  if (plant.stem) {
    for (const Ball& b : plant.stem->curve.dataBalls())
      balls.push_back({b.center.x(), b.center.y(), b.center.z(), b.radius});
    doc["stem"] = {{"height_mm", plant.stemHeightMm},
                   {"base_diameter_mm", plant.stemBaseDiameterMm},
                   {"top_diameter_mm", plant.stemTopDiameterMm},
                   {"data_balls", balls}};
  } else {
    doc["stem"] = nullptr;
  }
  json leaves = json::array();
  for (const PlacedLeaf& l : plant.leaves) {
    const LeafLight* light = lightOf(metrics, l.rank);
    json placement = json::array();  // row-major 4 x 4: shaped leaf frame → plant frame
    const Eigen::Matrix4d m = l.placement.matrix();
    for (int r = 0; r < 4; ++r) placement.push_back({m(r, 0), m(r, 1), m(r, 2), m(r, 3)});
    LeafMetrics lm{};
    lm.lightDirection = metrics.lightDirection;
    lm.blade.areaMm2 = light ? light->areaMm2 : 0.0;
    lm.blade.projectedAreaMm2 = 0.0;
    json leaf = {{"rank", l.rank},
                 {"source", l.source},
                 {"leaf_id", l.model.markers.leaf.id},
                 {"insertion_height_mm", l.insertionHeightMm},
                 {"azimuth_deg", l.azimuthDeg},
                 {"inclination_deg", l.inclinationDeg},
                 {"roll_deg", l.rollDeg},
                 {"scale", l.scale},
                 {"bend_deg", l.bendDeg},
                 {"length_factor", l.lengthFactor},
                 {"width_factor", l.widthFactor},
                 {"placement", placement},
                 {"base_mm", {l.base.x(), l.base.y(), l.base.z()}},
                 {"tip_mm", {l.tip.x(), l.tip.y(), l.tip.z()}},
                 {"length_mm", l.lengthMm},
                 {"width_mm", l.widthMm},
                 {"area_mm2", light ? light->areaMm2 : 0.0},
                 {"silhouette_mm2", light ? light->silhouetteMm2 : 0.0},
                 {"star", light ? light->star : 0.0}};
    leaf["model"] = json::parse(modelToJson(l.model, "plant", lm));
    leaves.push_back(std::move(leaf));
  }
  doc["leaves"] = std::move(leaves);
  doc["metrics"] = {
      {"light_direction", {metrics.lightDirection.x(), metrics.lightDirection.y(), metrics.lightDirection.z()}},
      {"area_mm2", metrics.areaMm2},
      {"silhouette_mm2", metrics.silhouetteMm2},
      {"star", metrics.star}};
  return detail::dumpFinite(doc) + "\n";
}

std::vector<EncodedFile> encodePlant(const std::filesystem::path& path, const Plant& plant, const LeafMesh& mesh,
                                     const PlantMetrics& metrics, const PlantExportOptions& options) {
  requireFiniteMesh(mesh);
  const ExportHeader header{plant.id, "plant", options.generator};
  switch (plantFormatForPath(path)) {
    case PlantFormat::Glb: return {{path, encodeMesh(mesh, MeshFormat::Glb, header)}};
    case PlantFormat::Obj: return {{path, encodeMesh(mesh, MeshFormat::Obj, header)}};
    case PlantFormat::Ply: return {{path, encodeMesh(mesh, MeshFormat::Ply, header)}};
    case PlantFormat::Stl: return {{path, encodeMesh(mesh, MeshFormat::Stl, header)}};
    case PlantFormat::Can: {
      std::filesystem::path opt = path;
      opt.replace_extension(".opt");
      return {{path, encodeCan(mesh, options.canUnit).text}, {opt, encodeCaribuOpt()}};
    }
    case PlantFormat::Mtg: return {{path, encodeMtg(plant, metrics)}};
    case PlantFormat::Csv: return {{path, encodePlantCsv(plant, metrics)}};
    case PlantFormat::Json: return {{path, encodePlantJson(plant, metrics)}};
    case PlantFormat::HeliosXml: return {{path, encodeHeliosXml(mesh, options.generator)}};
    case PlantFormat::Vgx: return {{path, encodeVgx(mesh)}};
  }
  return {};
}

std::vector<EncodedFile> encodePlantFiles(const std::vector<std::filesystem::path>& paths, const Plant& plant,
                                          const LeafMesh& mesh, const PlantMetrics& metrics,
                                          const PlantExportOptions& options, unsigned threads) {
  // The text formats of the meshes take longest: start them first so the threads finish
  // together (the order of the files returned does not change).
  const auto cost = [](const std::filesystem::path& p) {
    static const char* const kSlowestFirst[] = {".json", ".can", ".obj", ".glb", ".stl", ".ply"};
    const std::string ext = lowerExtension(p);
    for (std::size_t k = 0; k < std::size(kSlowestFirst); ++k)
      if (ext == kSlowestFirst[k]) return k;
    return std::size(kSlowestFirst);
  };
  std::vector<std::size_t> order(paths.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return cost(paths[a]) < cost(paths[b]); });
  std::vector<std::vector<EncodedFile>> encoded(paths.size());
  detail::parallelFor(
      paths.size(), threads, [&](std::size_t i) { encoded[i] = encodePlant(paths[i], plant, mesh, metrics, options); },
      order);
  std::vector<EncodedFile> files;
  for (auto& e : encoded)
    for (auto& f : e) files.push_back(std::move(f));
  return files;
}

}  // namespace leafdig::model
