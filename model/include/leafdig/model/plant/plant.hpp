#pragma once
// Whole plants (docs/method.md §9; seed 000 §3, seed 003 §2.4): a stem — a BBSC axis organ — carrying
// leaf models placed by insertion height, azimuth, inclination and roll; phyllotaxis by a
// divergence angle with seeded jitter; leaves drawn from an organ library with random-valued
// transforms inside the plan's ranges; logistic growth of stem and leaves over time.
//
// Plant frame: millimetres, origin at the stem base, +Z up the stem axis. A leaf is first
// put in its leaf frame (docs/method.md §5: origin P_N4, +Y to the tip, +Z adaxial), shaped there
// (scale, bend, growth), then moved rigidly to its insertion point on the stem surface.
//
// Every random draw comes from the plan's seed, through one generator per leaf (seeded by
// the plan seed and the leaf's rank), so the same plan and seed give the same plant on
// every machine, and adding a leaf does not change the draws of the others.
#include <Eigen/Geometry>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "leafdig/model/leaf/leaf_model.hpp"
#include "leafdig/model/mesh/mesh.hpp"
#include "leafdig/model/mesh/mesh_method.hpp"

namespace leafdig::model {

// 360° (1 - 1/φ): the divergence of most spiral phyllotaxes, tobacco's included.
inline constexpr double kGoldenAngleDeg = 137.50776405003785;
inline constexpr double kDefaultInclinationDeg = 55.0;

struct Range {
  double lo = 0.0;
  double hi = 0.0;
};

struct StemPlan {
  double heightMm = 0.0;  // along the stem (the digitized points' polyline when given)
  double baseDiameterMm = 0.0;
  double topDiameterMm = 0.0;
  // Digitized stem: centre points with caliper diameters (x, y, z, d in mm), base first. The
  // stem is then the BBSC through them, moved so that the first point is the origin (the
  // frame's +Z should be up); insertion heights are lengths along it.
  std::vector<Eigen::Vector4d> points;
};

struct LibraryRequest {
  std::string type;             // "lower", "upper", … as stored with the leaf; empty: any
  std::optional<int> position;  // a leaf position on its plant; absent: any
};

struct LeafPlan {
  int rank = 0;                                  // 1 at the stem base
  std::optional<std::filesystem::path> markers;  // a leafdig.markers/1 file (resolved), or
  std::optional<LibraryRequest> library;         // a draw from the organ library
  double insertionHeightMm = 0.0;                // on the stem axis, from its base
  std::optional<double> azimuthDeg;              // overrides the phyllotaxis
  std::optional<double> inclinationDeg;          // chord from the stem axis: 0 upright, 90 flat
  double rollDeg = 0.0;                          // about the chord, after inclination
  std::optional<double> scale;                   // overrides the library's scale range
  std::optional<double> bendDeg;                 // extra midrib bend, tip downwards
};

// The ranges random-valued transforms are drawn in (seed 003's "random-valued parameter
// transform"). A range lo == hi is a fixed value.
struct TransformRanges {
  Range scale{1.0, 1.0};
  Range bendDeg{0.0, 0.0};
  Range azimuthJitterDeg{0.0, 0.0};  // added to the phyllotaxis azimuth of library leaves
  std::optional<Range> inclinationDeg;
};

// Logistic growth (docs/plants.md): with τ the time since the organ appeared,
//   g(τ) = 1 / (1 + exp(-k (τ - τm)))
//   length(τ) = Lmax g(τ);  width(τ) = Wmax (w0 + (1 - w0) g(τ))   (0 < w0 < 1)
// so width changes by (1 - w0) Wmax while length changes by Lmax: width grows less. Leaf
// of rank n appears at (n - 1) × plastochron; the stem's height follows the same curve
// with its own k and τm from time 0, insertion heights scaling with it.
struct GrowthPlan {
  std::string timeUnit = "days";  // "days" or "degree_days" (thermal time)
  double plastochron = 0.0;
  double leafRate = 0.0;      // k
  double leafMidpoint = 0.0;  // τm
  double widthAtEmergence = 0.4;
  double stemRate = 0.0;
  double stemMidpoint = 0.0;
};

[[nodiscard]] double logistic(double rate, double midpoint, double tau);

struct PlantPlan {
  std::string id;
  std::uint64_t seed = 0;
  StemPlan stem;
  double divergenceDeg = kGoldenAngleDeg;
  double jitterDeg = 0.0;                // phyllotaxis jitter: uniform in [-jitter, +jitter]
  std::vector<LeafPlan> leaves;          // sorted by rank
  std::optional<std::string> libraryDb;  // resolved path of the store, when leaves draw from it
  TransformRanges ranges;
  std::optional<GrowthPlan> growth;
};

inline constexpr const char* kPlantPlanFormat = "leafdig.plant/1";

// The `leafdig.plant/1` plan (data/schema/leafdig.plant-1.schema.json). Relative paths are
// resolved against `baseDir`. Throws InputError naming the key and what to fix: a missing
// required key, a rank twice, an insertion above the stem, a range with lo > hi, …
[[nodiscard]] PlantPlan parsePlantPlan(std::string_view text, const std::string& source,
                                       const std::filesystem::path& baseDir);
[[nodiscard]] PlantPlan readPlantPlan(const std::filesystem::path& path);

// One leaf of the organ library: an approved capture with its leaf info (type, position).
struct LibraryLeaf {
  std::string source;  // "session 12", a file name: where it came from
  MarkerSet markers;
};

struct PlacedLeaf {
  int rank = 0;
  std::string source;
  double insertionHeightMm = 0.0;  // at this time
  double azimuthDeg = 0.0;
  double inclinationDeg = 0.0;
  double rollDeg = 0.0;
  double scale = 1.0;
  double bendDeg = 0.0;
  double lengthFactor = 1.0;  // growth: length / final length
  double widthFactor = 1.0;
  Eigen::Isometry3d placement = Eigen::Isometry3d::Identity();  // shaped leaf frame → plant
  LeafModel model;                                              // in the plant frame
  Eigen::Vector3d base = Eigen::Vector3d::Zero();               // P_N4, plant frame
  Eigen::Vector3d tip = Eigen::Vector3d::Zero();
  double lengthMm = 0.0;  // midrib length along the BBSC
  double widthMm = 0.0;   // widest row, across the markers
  // False for a leaf whose shape was not digitized (a quick leaf: a library shape stretched to
  // its length and width): the digitizer's area interval does not apply to it.
  bool shapeDigitized = true;
};

struct Plant {
  std::string id;
  std::optional<double> time;  // of a growth state
  std::string timeUnit;
  double stemHeightMm = 0.0;
  double stemBaseDiameterMm = 0.0;
  double stemTopDiameterMm = 0.0;
  std::optional<Vein> stem;        // name "stem"; absent for a leaf exported alone
  std::vector<PlacedLeaf> leaves;  // by rank; leaves not yet appeared are absent
  std::vector<Vein> branches;      // a plant digitized in place: "branch-<k>", the axis whose first node is k
};

// Resolves every leaf (its markers file, or a draw from `library`), draws the random
// transforms, and assembles the plant at its final size, or at `time` when the plan has
// growth. Throws InputError for a library draw nothing matches, a bad leaf file, a time
// without growth.
class PlantBuilder {
 public:
  PlantBuilder(PlantPlan plan, std::vector<LibraryLeaf> library);
  [[nodiscard]] Plant build(std::optional<double> time = std::nullopt) const;
  [[nodiscard]] const PlantPlan& plan() const { return plan_; }

 private:
  struct Resolved {
    LeafPlan plan;
    std::string source;
    MarkerSet leafFrameMarkers;  // the leaf in its own frame, before scale and bend
    double azimuthDeg, inclinationDeg, scale, bendDeg;
  };
  PlantPlan plan_;
  std::vector<Resolved> leaves_;
};

// A leaf alone as a plant of one leaf (rank `rank`) with no stem, in the leaf model's own
// frame: what `leafdig model build -o leaf.can -o leaf.mtg -o leaf.csv` writes. Its azimuth and
// inclination are those of its base-to-tip chord about +Z.
[[nodiscard]] Plant singleLeafPlant(const LeafModel& leaf, int rank, std::string source);

// The stem at `fraction` (0 base, 1 apex) of its length: centre, unit tangent, radius.
struct StemPoint {
  Eigen::Vector3d center;
  Eigen::Vector3d tangent;
  double radius = 0.0;
};
[[nodiscard]] StemPoint stemPointAt(const Plant& plant, double fraction);

// The midrib length (along the centre curve) and the widest row (P_i1 to P_i7).
[[nodiscard]] double midribLengthMm(const LeafModel& leaf);
[[nodiscard]] double bladeWidthMm(const MarkerSet& markers);

// Triangle meshes of every organ: "plant/stem", "plant/<branch>" for each branch, then
// "plant/leaf-<rank>/<organ>" in rank order, each organ carrying its leaf rank (0 for the stem
// and the branches).
[[nodiscard]] LeafMesh meshPlant(const Plant& plant, const MeshResolution& resolution);
// The same with any mesh method (uniform, seed, adaptive; mesh_method.hpp).
[[nodiscard]] LeafMesh meshPlant(const Plant& plant, const MeshOptions& options);

}  // namespace leafdig::model
