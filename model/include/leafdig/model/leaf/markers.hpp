#pragma once
// The marker set of docs/method.md §1 and the thickness rule. All lengths in millimetres.
#include <Eigen/Core>
#include <array>
#include <optional>
#include <string>
#include <vector>

#include "leafdig/model/leaf/thickness_mode.hpp"
#include "leafdig/names/name_table.hpp"

namespace leafdig::model {

inline constexpr int kMarkersPerRow = 7;
inline constexpr int kMidribColumn = 3;  // 0-based index of the 4th marker

// One row i of markers: P_i1..P_i7 right to left, the 4th on the midrib, with the
// back-side caliper thicknesses (diameters, mm) taken for it.
struct MarkerRow {
  std::array<Eigen::Vector3d, kMarkersPerRow> pointsMm;
  std::optional<double> midribThicknessMm;                                // r_i4^1
  std::optional<double> veinOriginThicknessMm;                            // r_i4^2
  std::optional<double> edgeThicknessMm;                                  // per-row margin thickness
  std::array<std::optional<double>, kMarkersPerRow> measuredThicknessMm;  // overrides
};

// Margin teeth (seed 002's profiles; docs/synthetic-leaves.md): none, round, sharp, straight,
// acuminate. A technician declares the leaf's (set-up dialog, markers file), the synthetic
// leaves are made with one.
enum class Serration { None, Round, Sharp, Straight, Acuminate };
// Its words in files, options and messages (the CLI's choices and the station's lists too).
inline constexpr NameTable<Serration, 5> kSerrationNames{{{Serration::None, "none"},
                                                          {Serration::Round, "round"},
                                                          {Serration::Sharp, "sharp"},
                                                          {Serration::Straight, "straight"},
                                                          {Serration::Acuminate, "acuminate"}}};

[[nodiscard]] const char* toString(Serration serration);
// Throws InputError naming the accepted words.
[[nodiscard]] Serration serrationFromString(const std::string& word);
// The tooth profile in units of the tooth depth D at θ = n φ (n teeth per side), and its mean
// and largest value over a tooth: the margin between the markers lies between the profile's
// sinus (0) and tip (max), on average at the mean.
[[nodiscard]] double toothProfile(Serration serration, double theta);
struct ToothSpread {
  double mean = 0.0, max = 0.0;
};
[[nodiscard]] ToothSpread toothSpread(Serration serration);
// The default tooth depth when none is given: 1.5 % of the leaf's width (the synthetic
// leaves' default).
inline constexpr double kDefaultToothDepthFraction = 0.015;

// How far a leaf's true margin runs outside and inside a smooth margin through points taken
// on it `spacingMm` apart, measured on a scan of the leaf (marginFromOutline), at one spacing
// or several (the markers' spacing is known only once the leaf is captured).
struct MarginSample {
  double spacingMm = 0.0;
  double outsideMm = 0.0;  // the margin's reach beyond the smooth curve (its teeth' tips)
  double insideMm = 0.0;   // and within it (its sinuses)
};
using MarginFromScan = std::vector<MarginSample>;  // by spacing, increasing
// The sample at `spacingMm`, linearly between the scan's spacings (the nearest beyond them).
[[nodiscard]] MarginSample marginAt(const MarginFromScan& margin, double spacingMm);

struct LeafInfo {
  std::string id;
  std::string plant;
  std::optional<int> position;
  std::string type;
  std::optional<double> measuredAreaMm2;
  // The margin's detail that markers cannot see between them (the area interval's margin
  // term): the declared serration (absent: not declared; the interval says so), its tooth
  // depth (absent: kDefaultToothDepthFraction of the width), or what a scan showed.
  std::optional<Serration> serration;
  std::optional<double> toothDepthMm;
  std::optional<MarginFromScan> marginFromScan;
};

struct MarkerSet {
  LeafInfo leaf;
  Eigen::Vector3d tipMm = Eigen::Vector3d::Zero();
  std::vector<MarkerRow> rows;            // i = 1..N from tip to base
  std::optional<double> edgeThicknessMm;  // d, per leaf
  std::optional<ThicknessMode> mode;      // absent: inferred (see inferThicknessMode)
};

// Thickness (diameter, mm) of every marker after the thickness rule.
struct RowThickness {
  std::array<double, kMarkersPerRow> lateralMm;  // t_i1..t_i7; t_i4 = lateral vein origin
  double midribMm;                               // r_i4^1
};
struct LeafThickness {
  ThicknessMode mode;
  double tipMm;  // d (the tip is on the margin)
  std::vector<RowThickness> rows;
};

// The declared mode, or: no row has vein_origin_thickness -> small; every row has all 7
// measured thicknesses -> full; otherwise standard.
[[nodiscard]] ThicknessMode inferThicknessMode(const MarkerSet& markers);

// docs/method.md §1: t_1 = t_7 = d, t_2 = t_6 = (2d + r2)/3, t_3 = t_5 = (d + 2 r2)/3, t_4 = r2,
// midrib r1; small mode r2 := r1; a measured value replaces the interpolated one. A
// per-row edge thickness replaces d for that row. Throws InputError naming the row and
// the missing or invalid thickness.
[[nodiscard]] LeafThickness applyThicknessRule(const MarkerSet& markers);

// Geometry checks of docs/method.md §1 input: at least one row, finite coordinates, no coincident
// consecutive markers along any vein or the blade's columns. Throws InputError naming the
// row and point (numbered from 1 as in the spec) and what to do.
void validateMarkerGeometry(const MarkerSet& markers);

// The markers' mean spacing along the margin: the margin's length through them (tip to each
// row's ends, both sides) over its 2N segments.
[[nodiscard]] double marginSpacingMm(const MarkerSet& markers);

// The blade's grid Q_kl, k = 0..N (k = 0 is the tip repeated 7 times), l = 0..6.
using MarkerGrid = std::vector<std::array<Eigen::Vector3d, kMarkersPerRow>>;
[[nodiscard]] MarkerGrid markerGrid(const MarkerSet& markers);

}  // namespace leafdig::model
