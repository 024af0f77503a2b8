#pragma once
// Synthetic ground-truth leaves (docs/method.md §8, seed 002; formulas in docs/synthetic-leaves.md).
//
// A flat outline from the seed's deformed base rectangle — a shape profile (oblong,
// elliptic, ovate, obovate, tobacco), sine-sum width deformations, Gaussian tip and base
// deformations and margin serrations (round, sharp, straight, acuminate) — is bent into 3-D
// by a smooth map (midrib droop, cupping, twist, wavy margin). Its area is integrated
// exactly (Green's theorem over the outline, Gauss-Legendre on panels split at every kink)
// to better than 1e-9 relative. Markers are placed by the protocol (docs/method.md §1: rows from tip
// to base along straight lateral veins, the last row at the leaf base) and sampled with
// Gaussian noise from a counter-based generator, so a spec and seed give the same file on
// every machine.
//
// Frames: the flat outline has the leaf base at the origin and the tip at (0, L); +x is the
// right half seen from the adaxial side with the tip up. The 3-D leaf is in the leaf frame
// of docs/method.md §5 (origin at the base, +Y towards the tip, +Z adaxial).
#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "leafdig/model/leaf/markers.hpp"
#include "leafdig/model/mesh/mesh.hpp"
#include "leafdig/names/name_table.hpp"

namespace leafdig::model {

enum class LeafShape { Oblong, Elliptic, Ovate, Obovate, Tobacco };
// Its words in files, options and messages (the CLI's choices and the station's lists too).
inline constexpr NameTable<LeafShape, 5> kLeafShapeNames{{{LeafShape::Oblong, "oblong"},
                                                          {LeafShape::Elliptic, "elliptic"},
                                                          {LeafShape::Ovate, "ovate"},
                                                          {LeafShape::Obovate, "obovate"},
                                                          {LeafShape::Tobacco, "tobacco"}}};

// Serration (none, round, sharp, straight, acuminate) and its profile: markers.hpp.
// Teeth pushed out horizontally (the seed's T_y = 0) or along the margin's outward normal.
enum class ToothDirection { Horizontal, Normal };
// Its words in files, options and messages (the CLI's choices and the station's lists too).
inline constexpr NameTable<ToothDirection, 2> kToothDirectionNames{
    {{ToothDirection::Horizontal, "horizontal"}, {ToothDirection::Normal, "normal"}}};

[[nodiscard]] const char* toString(LeafShape shape);
[[nodiscard]] const char* toString(ToothDirection direction);
// Throw InputError naming the accepted words.
[[nodiscard]] LeafShape leafShapeFromString(const std::string& word);
[[nodiscard]] ToothDirection toothDirectionFromString(const std::string& word);

// Length-to-width ratio of the base rectangle: oblong 3, elliptic 1.5, ovate, obovate and
// tobacco 2.
[[nodiscard]] double aspectRatio(LeafShape shape);

// One term of the width deformation: the half-width is multiplied by 1 + Σ a sin(k φ + p).
struct SineTerm {
  double amplitude = 0.0;  // fraction of the half-width
  double frequency = 1.0;  // k, per half outline (φ from base 0 to tip π)
  double phaseRad = 0.0;
};

struct OutlineSpec {
  LeafShape shape = LeafShape::Tobacco;
  double lengthMm = 500.0;           // base to tip
  std::optional<double> widthMm;     // the base rectangle's width; absent: length / aspect
  std::optional<double> symmetry;    // S: > 0 widest below the middle; absent: the shape's
  std::vector<SineTerm> widthTerms;  // sine-sum deformation of the half-width
  double asymmetry = 0.0;            // the left half is narrower by this fraction
  double tipNarrowing = 0.0;         // g_t: Gaussian narrowing at the tip (> 0 drawn out)
  double tipExtent = 0.15;           // its σ, as a fraction of the length
  double baseNarrowing = 0.0;        // g_b: Gaussian narrowing at the base (> 0 attenuate)
  double baseExtent = 0.12;
  Serration serration = Serration::None;
  double toothDepthMm = 0.0;  // D: depth of a round or sharp tooth (straight and acuminate reach 2D)
  int teethPerSide = 0;       // n teeth along each half margin
  ToothDirection toothDirection = ToothDirection::Horizontal;
};

struct BendSpec {
  double droopDeg = 25.0;  // total turn of the midrib from base to tip, tip downwards
  double cupMm = 12.0;     // rise of the margin above the midrib's plane at half the width
  double twistDeg = 5.0;   // roll of the blade about the midrib at the tip
  double waveMm = 0.0;     // amplitude of the margin wave (grows with the square of |x|)
  double wavelengthMm = 80.0;
};

struct SyntheticLeafSpec {
  OutlineSpec outline;
  BendSpec bend;
  int rows = 12;                   // N marker rows, the last at the leaf base
  double veinAngleTipDeg = 50.0;   // lateral vein angle to the midrib at row 1
  double veinAngleBaseDeg = 40.0;  // at row N (the shape's default: oblong 70, elliptic and ovate 75,
                                   // obovate 60, tobacco 55)
  std::string id = "SYN-1";
  std::string plant = "P-synth";
  std::string type = "synthetic";
};

// The shape's defaults (tobacco: S 0.1, tip narrowing 0.6 over 0.25 L, base narrowing 0.5
// over 0.2 L, wavy margin 3 mm every 70 mm); parameters given explicitly in `spec` win.
[[nodiscard]] SyntheticLeafSpec defaultSyntheticSpec(LeafShape shape);

// One lateral vein of the truth: its flat segment from the midrib to the margin and the
// 3-D polyline it bends into.
struct TruthVein {
  int row = 0;    // 1..N from the tip
  int side = +1;  // +1 right (markers j = 1..3), -1 left (j = 5..7)
  Eigen::Vector2d flatStart, flatEnd;
  std::vector<Eigen::Vector3d> points;
};

class SyntheticLeaf {
 public:
  // Throws InputError naming the parameter that makes no leaf (a length that is not
  // positive, teeth deeper than the leaf is wide, rows outside 2..60, ...).
  explicit SyntheticLeaf(SyntheticLeafSpec spec);

  [[nodiscard]] const SyntheticLeafSpec& spec() const { return spec_; }
  [[nodiscard]] double widthMm() const { return width_; }

  // Flat outline point of one half (side +1 right, -1 left) at φ in [0, π] (base to tip).
  [[nodiscard]] Eigen::Vector2d outlinePoint(int side, double phi) const;
  // The closed flat outline, counter-clockwise: the right half base to tip, then the left
  // half tip to base (base and tip once each), `perSide` segments per half.
  [[nodiscard]] std::vector<Eigen::Vector2d> outline(int perSide) const;
  // φ where the outline has a kink (tooth notches and crests), both ends included.
  [[nodiscard]] std::vector<double> breakpoints() const;

  // The bending map: a flat point (x, y) to the 3-D leaf frame.
  [[nodiscard]] Eigen::Vector3d surfacePoint(const Eigen::Vector2d& flat) const;

  // Exact areas (mm²): the flat outline, and the 3-D blade (∬ |Φx × Φy| over the outline).
  // `errorEstimate` receives |A(2m panels) − A(m panels)| / A. The 3-D area is integrated
  // once, by the constructor.
  [[nodiscard]] double flatArea() const;
  [[nodiscard]] double area(double* errorEstimate = nullptr) const;
  [[nodiscard]] double midribLengthMm() const { return spec_.outline.lengthMm; }

  // Markers by the protocol, exact (noise 0) or with Gaussian noise of σ mm per coordinate,
  // rounded to 0.01 mm; thicknesses as a tobacco leaf's, rounded to 0.001 mm.
  // `leaf.measured_area_mm2` is the exact area (what a leaf area meter reads of the leaf
  // pressed flat), rounded to 1 mm².
  [[nodiscard]] MarkerSet markers(double noiseMm = 0.0, std::uint64_t seed = 1) const;
  [[nodiscard]] std::vector<TruthVein> veins(int pointsPerVein = 33) const;
  [[nodiscard]] std::vector<Eigen::Vector3d> midrib(int points = 129) const;

  // The true blade alone, `alongPerSide` × `across` quads per half (normals from the map),
  // as a one-organ LeafMesh named "blade".
  [[nodiscard]] LeafMesh truthMesh(int alongPerSide = 600, int across = 40) const;

 private:
  [[nodiscard]] Eigen::Vector2d baseOutline(int side, double phi, Eigen::Vector2d* tangent = nullptr) const;
  [[nodiscard]] double jacobian(double x, double y) const;
  [[nodiscard]] double greenArea(int panelsPerInterval, bool flat) const;
  [[nodiscard]] std::vector<Eigen::Vector2d> marginSamples(int side) const;
  [[nodiscard]] double veinLength(int side, double y0, double angleRad,
                                  const std::vector<Eigen::Vector2d>& margin) const;

  SyntheticLeafSpec spec_;
  double width_ = 0.0;
  double symmetry_ = 0.0;
  double area_ = 0.0;  // computed once by the constructor
  double areaError_ = 0.0;
};

// The shape a quick leaf of a plant takes when the organ library has none of its type
// (model/plant/surveyed_plant.hpp): the tobacco shape's defaults, 12 rows, exact markers, built
// once per process.
[[nodiscard]] const MarkerSet& sampleLeafShape();
inline constexpr const char* kSampleShapeSource = "built-in sample shape (synthetic tobacco leaf)";

// leafdig.truth/1 JSON (docs/synthetic-leaves.md): spec, exact areas, midrib length, the
// flat outline, the exact marker positions and the true veins.
[[nodiscard]] std::string truthToJson(const SyntheticLeaf& leaf, double noiseMm, std::uint64_t seed);

// An SVG drawing of flat outlines side by side with captions (the figure of the docs).
struct FigurePanel {
  std::string caption;
  std::vector<Eigen::Vector2d> outline;
  std::vector<std::array<Eigen::Vector2d, 2>> veins;  // drawn thin
  std::vector<Eigen::Vector2d> markers;               // drawn as dots
};
[[nodiscard]] std::string figureSvg(const std::vector<FigurePanel>& panels, int columns);
// One panel for a leaf: its outline, flat veins and flat marker positions.
[[nodiscard]] FigurePanel figurePanel(const SyntheticLeaf& leaf, const std::string& caption);

}  // namespace leafdig::model
