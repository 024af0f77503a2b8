#pragma once
// Leaves known only in 2-D (seed 001, docs/method.md §6): an outline in millimetres (a file, a scan,
// a leaf-area-meter image) becomes a flat bicubic B-spline leaf, its margin curls by the
// parabola-like or sine-like model, the interior follows by Laplacian (cotangent-weight)
// deformation, and the curled leaf keeps the measured area. docs/leaf2d.md has the formulas.
#include <Eigen/Core>
#include <array>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "leafdig/model/leaf/blade.hpp"
#include "leafdig/model/mesh/laplacian_deform.hpp"
#include "leafdig/model/mesh/mesh.hpp"
#include "leafdig/model/metrics/metrics.hpp"
#include "leafdig/names/name_table.hpp"

namespace leafdig::model {

inline constexpr const char* kOutlineFormat = "leafdig.outline/1";

// A leaf's flat outline: a closed polygon (the first point not repeated at the end), either
// orientation, millimetres. Base and tip are where the midrib meets the petiole and the
// leaf's apex; when absent they are found (findBaseAndTip).
struct Outline2d {
  std::vector<Eigen::Vector2d> pointsMm;
  std::optional<Eigen::Vector2d> baseMm;
  std::optional<Eigen::Vector2d> tipMm;
  std::optional<double> measuredAreaMm2;  // e.g. a leaf area meter's; else the polygon's
  std::string id;
};

// How far the outline runs outside and inside a smooth margin (its moving average over
// `spacingMm` of arc: the markers' spacing along the margin), as the 97.5th and 2.5th
// percentiles of its signed distance about their mean: the margin detail the markers of a
// capture cannot see between them, for the area interval (LeafInfo::marginFromScan). Throws
// InputError for an outline of fewer than 8 points or a spacing that is not positive.
[[nodiscard]] MarginSample marginFromOutline(const Outline2d& outline, double spacingMm);
// The same at the spacings a capture's rows give (5 to 80 mm), for when the markers are not
// taken yet (the station's set-up reads the scan before the capture).
[[nodiscard]] MarginFromScan marginProfile(const Outline2d& outline);

// `leafdig.outline/1` JSON ({"format", "units": "mm", "points": [[x, y], ...], optional
// "base", "tip", "measured_area_mm2", "id"}) or CSV (`x_mm,y_mm` rows, an optional header
// naming the columns; `#` comments), chosen by the extension (.json, .csv). Throws
// InputError naming the file, the line or key, and what to do (wrong units, fewer than 8
// points, no enclosed area, a base or tip off the outline by more than 5 mm).
[[nodiscard]] Outline2d readOutlineFile(const std::filesystem::path& path);
[[nodiscard]] Outline2d parseOutlineJson(const std::string& text, const std::string& source);
[[nodiscard]] Outline2d parseOutlineCsv(const std::string& text, const std::string& source);
[[nodiscard]] std::string outlineToJson(const Outline2d& outline);

// Shoelace area, always >= 0.
[[nodiscard]] double polygonArea(const std::vector<Eigen::Vector2d>& polygon);

// The given base and tip, or the farthest pair of outline points (the leaf's length); of the
// two ends the one where the leaf is narrower 5 % of the length inside is the tip.
[[nodiscard]] std::pair<Eigen::Vector2d, Eigen::Vector2d> findBaseAndTip(const Outline2d& outline);

enum class CurlKind { None, Parabola, Sine, Auto };
// Its words in files, options and messages (the CLI's choices and the station's lists too).
inline constexpr NameTable<CurlKind, 4> kCurlKindNames{
    {{CurlKind::Parabola, "parabola"}, {CurlKind::Sine, "sine"}, {CurlKind::Auto, "auto"}, {CurlKind::None, "none"}}};

[[nodiscard]] const char* toString(CurlKind kind);
// Throws InputError naming the accepted words.
[[nodiscard]] CurlKind curlKindFromString(const std::string& word);

// The seed's five margin heights, in units of the amplitude A, at the edge points
// t = 0, 1/4, 1/2, 3/4, 1 (base to tip): parabola-like (0, .75, 1, .75, 0), sine-like
// (0, 1, 0, 1, 0); all zero for None. Throws std::invalid_argument for Auto.
[[nodiscard]] std::array<double, 5> curlFeatureHeights(CurlKind kind);
// The margin height at t in [0, 1] (units of A): the natural cubic spline through the five.
[[nodiscard]] double curlHeight(CurlKind kind, double t);

struct Leaf2dOptions {
  int rows = 30;            // cross-sections from tip to base (both ends included)
  int segmentsPerRow = 3;   // mesh rows per section span
  int segmentsAcross = 24;  // mesh columns across the leaf
  CurlKind curl = CurlKind::Parabola;
  std::optional<double> amplitudeMm;  // default 10 % of the leaf's width
  Eigen::Vector3d light{0.0, 0.0, 1.0};
  std::optional<double> measuredAreaMm2;  // overrides the outline's
};

struct CurlCandidate {
  CurlKind kind;
  double inPlaneScale;      // the area constraint's contraction of x and y
  double areaMm2;           // after the constraint: the measured area
  double projectedAreaMm2;  // sum A_k |n_k . d|
};

struct Leaf2dModel {
  BladeSurface flatBlade;  // bicubic interpolation of the sections, leaf frame, z = 0
  // True when the sections span a sinus or lobes the outline does not have (a cordate base,
  // a lobed margin): the flat leaf is then that surface trimmed to the outline, i.e. the
  // outline's own region (the flat surface is the plane z = 0), meshed inside the outline.
  bool trimmedToOutline = false;
  Mesh mesh;  // the curled, area-constrained blade in the leaf frame (docs/method.md §5)
  CurlKind curl = CurlKind::None;
  double amplitudeMm = 0.0;
  double inPlaneScale = 1.0;
  double lengthMm = 0.0;  // base to tip
  double widthMm = 0.0;   // widest section
  double outlineAreaMm2 = 0.0;
  double flatModelAreaMm2 = 0.0;  // the flat B-spline leaf's (before the constraint)
  double measuredAreaMm2 = 0.0;   // what the constraint holds (the outline's when none given)
  double modelAreaMm2 = 0.0;
  double projectedAreaMm2 = 0.0;
  double silhouetteAreaMm2 = 0.0;
  std::vector<CurlCandidate> candidates;      // every curl tried (two for Auto)
  std::vector<std::uint32_t> marginVertices;  // right margin base to tip, then left tip to base
  std::vector<double> marginT;                // their t (arc length on the flat margin, 0 at the base)
  Eigen::Vector2d baseMm;                     // in the outline's coordinates
  Eigen::Vector2d tipMm;
  // Named warnings, e.g. "flat-leaf-differs-from-outline" when the flat leaf and the outline
  // still differ by more than 2 % in area (sections that miss detail; or a sinus filled
  // across because the outline could not be meshed as it is: the area constraint then draws
  // the whole leaf in).
  std::vector<Warning> warnings;
};

// Throws InputError for a degenerate outline or options out of range (rows < 6, amplitude < 0).
[[nodiscard]] Leaf2dModel buildLeaf2d(const Outline2d& outline, const Leaf2dOptions& options = {});

[[nodiscard]] std::string leaf2dToJson(const Leaf2dModel& model);

// An SVG of the method on `outline` (docs/leaf2d.svg): the flat leaf and its sections, the
// parabola-like and sine-like curls at `amplitudeMm` seen obliquely, the margin profiles.
[[nodiscard]] std::string leaf2dFigureSvg(const Outline2d& outline, double amplitudeMm);

}  // namespace leafdig::model
