#pragma once
// Plant exports (docs/method.md §5, docs/plants.md "Formats"): meshes (GLB/OBJ/PLY/STL through encodeMesh), CARIBU
// `.can` + `.opt`, OpenAlea MTG, a CSV of organs and the `leafdig.plant-model/1` JSON.
// Every export keeps plant / leaf / organ identity: organ names `plant/leaf-<rank>/<organ>`
// and `plant/stem` (GLB nodes, OBJ groups, PLY organ_id + leaf_rank), CARIBU labels, MTG
// entities. Bytes are produced in memory; the caller writes them atomically.
#include <filesystem>
#include <string>
#include <vector>

#include "leafdig/model/io/mesh_export.hpp"
#include "leafdig/model/plant/plant.hpp"

namespace leafdig::model {

enum class PlantFormat { Glb, Obj, Ply, Stl, Can, Mtg, Csv, Json, HeliosXml, Vgx };

// From the extension (.glb .obj .ply .stl .can .mtg .csv .json, .xml Helios, .vgx VegeSTAR). Throws InputError.
[[nodiscard]] PlantFormat plantFormatForPath(const std::filesystem::path& path);

struct LeafLight {
  int rank = 0;
  double areaMm2 = 0.0;        // one-sided blade area (mesh triangles)
  double silhouetteMm2 = 0.0;  // displayed area for the light direction
  double star = 0.0;           // silhouette / area
  // The blade area's 95 % interval (areaUncertainty at the FASTRAK's accuracy), when
  // addAreaIntervals has run; the CSV's last two columns.
  std::optional<double> bladeAreaLow95Mm2, bladeAreaHigh95Mm2;
};

// Seed 001 / docs/method.md §6 on a plant: per leaf and for the whole plant (whose silhouette counts
// overlaps between leaves once). Blades only: the veins lie in the blade and the stem is not
// leaf area.
struct PlantMetrics {
  Eigen::Vector3d lightDirection = Eigen::Vector3d::UnitZ();
  std::vector<LeafLight> leaves;  // in the plant's leaf order
  double areaMm2 = 0.0;
  double silhouetteMm2 = 0.0;
  double star = 0.0;
};
[[nodiscard]] PlantMetrics computePlantMetrics(const Plant& plant, const LeafMesh& mesh,
                                               const Eigen::Vector3d& lightDirection);
// Fills each leaf's blade-area interval (about 12 ms a leaf: asked for by the CSV only).
void addAreaIntervals(const Plant& plant, PlantMetrics& metrics);

enum class CanUnit { Metre, Centimetre };

struct CanFile {
  std::string text;
  std::size_t triangles = 0;
  std::size_t dropped = 0;  // triangles of zero area once written at the file's precision
};
// CARIBU scene: `p 1 <label> 3 x1 y1 z1 x2 y2 z2 x3 y3 z3`, label = optical species 1, plant
// number (5 digits), leaf field = rank (000: the stem, opaque), element = organ index within
// the leaf (001 …); fixed notation to the micrometre (6 decimals in metres, 4 in
// centimetres), adaxial side first, a trailing newline. Throws InputError when a line's
// geometry would exceed canestrad's 124 characters (a plant wider than ±99 m).
[[nodiscard]] CanFile encodeCan(const LeafMesh& mesh, CanUnit unit, int plantNumber = 1);
// The optical file that goes beside it: one species (stem reflectance; upper and lower leaf
// reflectance and transmittance, PAR values of a green leaf) and a soil reflectance.
[[nodiscard]] std::string encodeCaribuOpt();

// OpenAlea MTG coding file: plant > internodes (stem segments between insertions) with a
// leaf branching from the internode below it (`/P1/I1`, `^<I2`, `+L1`), tab separated.
[[nodiscard]] std::string encodeMtg(const Plant& plant, const PlantMetrics& metrics);
// One row per organ (the stem, then each leaf).
[[nodiscard]] std::string encodePlantCsv(const Plant& plant, const PlantMetrics& metrics);
// `leafdig.plant-model/1`: every leaf's placement matrix and its leafdig.model/1 in the
// plant frame, the stem as a ball B-spline, the metrics.
[[nodiscard]] std::string encodePlantJson(const Plant& plant, const PlantMetrics& metrics);

// One glTF whose animation "growth" plays the series in 10 seconds: the stem's scale along
// its axis, each leaf's insertion point (translation) and its growth as a scale (width,
// length, length) of the full-grown leaf in its leaf frame; leaves not yet appeared are
// shrunk to nothing. `final` is the plant at full size, `states` the series (with times).
// A visual: each key lies within 0.5 mm of the exact state on the samples (the blade's
// chord-length parameters do not follow an anisotropic scale); the per-time files are exact.
[[nodiscard]] std::string encodeGrowthGlb(const Plant& final, const std::vector<Plant>& states, const MeshOptions& mesh,
                                          const std::string& generator);

// Every file for one requested output path: one file, or for `.can` the `.opt` beside it.
struct EncodedFile {
  std::filesystem::path path;
  std::string bytes;
};
struct PlantExportOptions {
  CanUnit canUnit = CanUnit::Metre;
  std::string generator;
};
[[nodiscard]] std::vector<EncodedFile> encodePlant(const std::filesystem::path& path, const Plant& plant,
                                                   const LeafMesh& mesh, const PlantMetrics& metrics,
                                                   const PlantExportOptions& options);
// Every file for several output paths, in the order of `paths`. The formats are independent,
// so they are encoded on up to `threads` threads at once (0: one per core of the machine);
// a plant written in eight formats then takes about as long as its slowest encoders. The
// first path (in order) whose encoding fails throws its error; nothing is written here.
[[nodiscard]] std::vector<EncodedFile> encodePlantFiles(const std::vector<std::filesystem::path>& paths,
                                                        const Plant& plant, const LeafMesh& mesh,
                                                        const PlantMetrics& metrics, const PlantExportOptions& options,
                                                        unsigned threads = 0);

}  // namespace leafdig::model
