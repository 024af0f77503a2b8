// `leafdig plant import FILE --units cm -o tree.glb …`: a digitized plant from the archives (an
// AMAP / OpenAlea MTG file and its dressing file, or a HydroShoot digitizing table) drawn and
// exported as a leafdig plant (docs/plants.md, "Archives").
#include <filesystem>
#include <iostream>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "leafdig/model/archive/mtg_archive.hpp"
#include "leafdig/model/archive/plant_import.hpp"
#include "leafdig/model/errors.hpp"
#include "leafdig/model/files.hpp"
#include "leafdig/model/io/archive_export.hpp"
#include "leafdig/model/io/plant_export.hpp"
#include "leafdig/model/mesh/mesh_method.hpp"
#include "leafdig/version.hpp"
#include "model/mesh_choice.hpp"
#include "plant/plant_cmd.hpp"
#include "terminal_text.hpp"

namespace leafdig::cli {

namespace m = leafdig::model;

namespace {

struct ImportOptions {
  std::string input, drf, units, resolution = "export", canUnit = "m";
  int plant = 1;
  std::vector<std::string> outputs;
  bool json = false;
};

int runImport(const ImportOptions& o) {
  // Every output named before anything is read or written.
  for (const auto& out : o.outputs) (void)m::plantFormatForPath(out);
  if (o.units.empty() && m::lowerExtension(o.input) == ".mtg")
    throw m::InputError(o.input +
                        ": an MTG file does not say the unit of its coordinates: give --units mm, cm or m "
                        "(after the dressing file's LengthUnit; AMAP's stations mostly wrote cm)");
  const m::ImportedFile file = m::importMtgFile(o.input, o.drf, o.units, o.plant);
  const m::MtgArchive& archive = file.archive;
  const m::ImportedPlant& imported = file.plant;

  // Meshed only for the files that need it (a report or an MTG alone does not).
  bool meshes = false;
  for (const auto& out : o.outputs) {
    const m::PlantFormat f = m::plantFormatForPath(out);
    meshes = meshes || (f != m::PlantFormat::Mtg && f != m::PlantFormat::Csv);
  }
  const m::LeafMesh mesh =
      meshes ? m::meshPlant(imported.plant, m::MeshResolution::preset(o.resolution)) : m::LeafMesh{};
  const m::PlantMetrics metrics = m::computePlantMetrics(imported.plant, mesh, Eigen::Vector3d::UnitZ());
  const m::PlantExportOptions exportOptions{o.canUnit == "cm" ? m::CanUnit::Centimetre : m::CanUnit::Metre,
                                            std::string("leafdig ") + kVersion};
  // Encode everything first, then write: a failure never leaves some files written.
  const std::vector<std::filesystem::path> paths(o.outputs.begin(), o.outputs.end());
  const std::vector<m::EncodedFile> files =
      m::encodeImportedFiles(paths, imported, archive, mesh, metrics, exportOptions);
  for (const auto& f : files) m::writeFileAtomically(f.path, f.bytes);

  std::map<int, int> orders;
  std::size_t notDrawn = 0;
  for (const m::ImportedAxis& a : imported.axes) {
    ++orders[a.order];
    notDrawn += a.drawnPoints < 2 ? 1 : 0;
  }
  std::size_t triangles = 0;
  for (const auto& organ : mesh.organs) triangles += organ.mesh.triangles.size();
  if (o.json) {
    nlohmann::json classes = nlohmann::json::object(), byOrder = nlohmann::json::object();
    for (const auto& [symbol, count] : imported.perClass) classes[symbol] = count;
    for (const auto& [order, count] : orders) byOrder[std::to_string(order)] = count;
    nlohmann::json written = nlohmann::json::array();
    for (const auto& f : files) written.push_back(f.path.string());
    const auto point = [](const Eigen::Vector3d& p) { return nlohmann::json::array({p.x(), p.y(), p.z()}); };
    std::cout << nlohmann::json{{"source", o.input},
                                {"plant", imported.plantLabel},
                                {"units", file.unit},
                                {"vertices", imported.vertices},
                                {"plant_vertices", imported.plantVertices},
                                {"classes", classes},
                                {"points", imported.points},
                                {"without_point", imported.withoutPoint},
                                {"axes", imported.axes.size()},
                                {"axes_by_order", byOrder},
                                {"axes_not_drawn", notDrawn},
                                {"second_followers", imported.secondFollowers},
                                {"diameters_taken_from_elsewhere", imported.diametersMissing},
                                {"box_mm", {{"low", point(imported.low)}, {"high", point(imported.high)}}},
                                {"triangles", triangles},
                                {"notes", imported.notes},
                                {"outputs", written}}
                     .dump()
              << "\n";
    return 0;
  }
  const Eigen::Vector3d size = imported.high - imported.low;
  std::cout << "plant " << terminalText(imported.plantLabel) << " of " << terminalText(o.input) << ": "
            << imported.plantVertices << " entities, " << imported.points << " digitized points on "
            << imported.axes.size() << " axes (";
  bool first = true;
  for (const auto& [order, count] : orders) {
    std::cout << (first ? "" : ", ") << count << " of order " << order;
    first = false;
  }
  std::cout << "), " << static_cast<long long>(size.x()) << " × " << static_cast<long long>(size.y()) << " × "
            << static_cast<long long>(size.z()) << " mm, " << triangles << " triangles\n";
  if (notDrawn > 0) std::cout << "  " << notDrawn << " axes of a single point are not drawn\n";
  if (imported.withoutPoint > 0)
    std::cout << "  " << imported.withoutPoint
              << " entities have no coordinates, nor any entity below them (a range's inner entities): drawn "
              << "through, not as points\n";
  if (imported.secondFollowers > 0)
    std::cout << "  " << imported.secondFollowers << " entities follow one that already had a follower: drawn as "
              << "branches\n";
  for (const auto& f : files) std::cout << "  wrote " << f.path.string() << "\n";
  return 0;
}

}  // namespace

void addPlantImportCommand(CLI::App& plant, CommandTable& table) {
  auto o = std::make_shared<ImportOptions>();
  CLI::App* c = plant.add_subcommand(
      "import",
      "Import a digitized plant from the archives (an AMAP / OpenAlea MTG file, a HydroShoot digitizing table) and "
      "export it");
  c->add_option("input", o->input, "The archive's file (.mtg, or a HydroShoot table: Souche;tronc;…;X;Y;Z;Diam)")
      ->required();
  c->add_option("--drf", o->drf, "Its dressing file (.drf): LengthUnit, DiameterUnit, AlphaUnit");
  c->add_option("--units", o->units,
                "The unit of the file's coordinates after the dressing's LengthUnit: mm, cm, m (a HydroShoot table: cm "
                "unless given)")
      ->check(CLI::IsMember({"mm", "cm", "m"}));
  c->add_option("--plant", o->plant, "Which plant of the file (1, the first, by default)")
      ->check(CLI::Range(1, 1000000));
  c->add_option("-o,--output", o->outputs,
                "File to write, by extension: .glb .obj .ply .stl .can (+ .opt) .mtg .csv .json .xml (Helios) .vgx "
                "(VegeSTAR) (repeat; none: "
                "the report alone)");
  c->add_option("--resolution", o->resolution, kFileResolutionHelp)->check(CLI::IsMember(fileResolutionWords()));
  c->add_option("--can-unit", o->canUnit, "Unit of CARIBU .can geometry: m (default) or cm")
      ->check(CLI::IsMember({"m", "cm"}));
  c->add_flag("--json", o->json, "Print the entities, points, axes by order and outputs as JSON");
  table.add(c, [o] { return runImport(*o); });
}

}  // namespace leafdig::cli
