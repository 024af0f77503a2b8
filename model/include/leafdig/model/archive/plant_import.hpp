#pragma once
// An archive's digitized plant as a leafdig plant (docs/plants.md, "Archives"): the MTG's
// entities with coordinates (XX YY ZZ) drawn as axes of any order — each a ball B-spline through
// its points with the entities' diameters — so that the plant meshes and exports as a built or
// captured one does (GLB, OBJ, PLY, STL, CARIBU, the plant model JSON).
//
// How the points are read (the rules a reader of docs/plants.md can check against a file):
// - a point is an entity with XX YY ZZ none of whose components has its own: the finest
//   digitized entity (an apple's E, a walnut's S or U);
// - a complex's coordinates (a walnut's A1, an apple's U94) are the base of its first component
//   when that component continues nothing: the axis starts there;
// - an entity's base is the top of the entity it follows or branches from ('<' or '+'), through
//   entities without coordinates (a range's inner entities) back to the nearest with one; an
//   entity with components stands for its last component on its '<' chain;
// - an axis is a chain of '<'; a '+' starts an axis one order higher (a second '<' from the same
//   entity, which AMAP forbids, also starts one, and is counted);
// - diameters: TopDia or TopDiameter (BottomDiameter for an axis' first ball), divided by the
//   dressing's DiameterUnit; lengths by its LengthUnit; an entity without a diameter takes the one
//   before it on its axis, an axis without one its bearer's at the insertion, a plant without any
//   kNoDiameterMm;
// - the file's origin and axes are kept (+Z up, as AMAP's stations wrote it), in millimetres.
#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "leafdig/model/archive/mtg_archive.hpp"
#include "leafdig/model/plant/plant.hpp"
#include "leafdig/model/spline/ball_bspline_curve.hpp"

namespace leafdig::model {

inline constexpr double kNoDiameterMm = 2.0;
// The largest coordinate and diameter an archive's plant may have (the tallest trees are about
// 120 m; a trunk about 10 m across): beyond them a unit is wrong, and the file is refused.
inline constexpr double kMaxArchiveCoordinateMm = 200'000.0;
inline constexpr double kMaxArchiveDiameterMm = 10'000.0;

struct ArchiveImportOptions {
  // Millimetres per length unit of the file once divided by the dressing's LengthUnit (cm: 10).
  double mmPerUnit = 10.0;
  MtgDressing dressing;
  int plant = 1;  // the n-th plant (scale-1 entity) of the file
};

struct ImportedAxis {
  int order = 1;              // 1 the trunk or stem
  int bearer = 0;             // the axis it branches from (its number, 1-based), 0 none
  std::vector<int> vertices;  // the archive's entities drawn on it, in order
  std::vector<Ball> balls;    // each one's point (mm) and radius as drawn, one per entity
  // Where it starts: the top of the entity it follows or branches from (baseVertex, an entity of
  // its bearer), or a complex's own coordinates (baseVertex -1); none for an axis that starts at
  // its first point.
  std::optional<Ball> base;
  int baseVertex = -1;
  std::size_t drawnPoints = 0;  // its distinct points (the base included); < 2: not drawn
};

struct ImportedPlant {
  Plant plant;  // the stem and the axes ("axis-<n>", n its number); no leaves
  std::string source, plantLabel;
  std::size_t vertices = 0;       // the file's entities, the root included (as OpenAlea counts them)
  std::size_t plantVertices = 0;  // those of the imported plant (its own entity and below)
  std::vector<std::pair<std::string, std::size_t>> perClass;  // the plant's entities by class
  std::size_t points = 0;                                     // entities drawn as points
  std::size_t withoutPoint = 0;  // entities of the plant with no coordinates of their own or below
  std::vector<ImportedAxis> axes;
  std::size_t secondFollowers = 0;   // '<' from an entity that already had one: drawn as a branch
  std::size_t diametersMissing = 0;  // entities drawn with a diameter taken from elsewhere
  Eigen::Vector3d low = Eigen::Vector3d::Zero(), high = Eigen::Vector3d::Zero();  // bounding box, mm
  std::vector<std::string> notes;  // what was read past (dressing keys, features not drawn)
};

// Throws InputError naming the file and what to do: no plant n, no coordinates at all, a
// diameter below zero.
[[nodiscard]] ImportedPlant importMtgPlant(const MtgArchive& archive, const ArchiveImportOptions& options);

// An archive read and its plant drawn: what `leafdig plant import` and Python's import_plant do.
// The file is an MTG (.mtg) or a HydroShoot digitizing table (by its header: hydroshoot_table.hpp).
// `drf` the MTG's dressing file (empty: none), `units` the coordinates' unit after its LengthUnit
// (mm, cm or m; an MTG does not say it, a HydroShoot table is in cm unless said). InputError in
// words for another file kind, another unit, and every refusal above.
struct ImportedFile {
  MtgArchive archive;
  ImportedPlant plant;
  std::string unit;  // the unit the coordinates were read in
};
[[nodiscard]] ImportedFile importMtgFile(const std::filesystem::path& path, const std::filesystem::path& drf,
                                         const std::string& units, int plant = 1);

}  // namespace leafdig::model
