#pragma once
// Blade surfaces through the marker grid (docs/method.md §4).
#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "leafdig/model/leaf/markers.hpp"
#include "leafdig/model/spline/bspline.hpp"
#include "leafdig/names/name_table.hpp"

namespace leafdig::model {

enum class BladeKind { Interp, Approx, Bezier, Nurbs };
// Its words in files, options and messages (the CLI's choices and the station's lists too).
inline constexpr NameTable<BladeKind, 4> kBladeKindNames{{{BladeKind::Interp, "interp"},
                                                          {BladeKind::Approx, "approx"},
                                                          {BladeKind::Bezier, "bezier"},
                                                          {BladeKind::Nurbs, "nurbs"}}};

[[nodiscard]] const char* toString(BladeKind kind);
// Throws InputError naming the accepted words.
[[nodiscard]] BladeKind bladeKindFromString(const std::string& word);

// A tensor-product (rational when weights are present) B-spline surface; u runs from the
// tip (u = 0) to the base, v from the right margin (v = 0) to the left margin.
struct BladeSurface {
  BladeKind kind = BladeKind::Interp;
  int degreeU = 3;
  int degreeV = 3;
  KnotVector knotsU;
  KnotVector knotsV;
  std::vector<std::vector<Eigen::Vector3d>> controlNet;  // [u index][v index]
  std::vector<std::vector<double>> weights;              // same shape, or empty
  // Parameters of the marker rows (u) and columns (v): the mesh places vertex rows and
  // columns on them so that every marker is a mesh vertex for `interp`.
  std::vector<double> rowParameters;
  std::vector<double> columnParameters;

  [[nodiscard]] Eigen::Vector3d evaluate(double u, double v) const;
};

// Points S(us[a], vs[b]) for every a, b: #us by #vs, evaluated by tensor products of
// precomputed basis rows (one row of control points per u, then per v).
using PointGrid = std::vector<std::vector<Eigen::Vector3d>>;
[[nodiscard]] PointGrid sampleSurface(const BladeSurface& surface, const std::vector<double>& us,
                                      const std::vector<double>& vs);

// interp: bicubic interpolation of every marker, averaged chord-length parameters (tip row
// skipped for v), natural ends in both directions. approx: markers as control points,
// cubic (degree min(3, N) in u), clamped uniform knots. bezier: degree N x 6. nurbs:
// approx with weights (`weights` [k][l] for the (N+1) x 7 grid; default all 1).
[[nodiscard]] BladeSurface buildBlade(const MarkerGrid& grid, BladeKind kind,
                                      const std::vector<std::vector<double>>* weights = nullptr);

// Averaged chord-length parameters (NURBS Book eq. 9.8-9.9) down the columns (u) and
// across the rows (v) of the grid; rows whose chords all vanish (the tip) are skipped.
[[nodiscard]] std::vector<double> averagedParametersU(const MarkerGrid& grid);
[[nodiscard]] std::vector<double> averagedParametersV(const MarkerGrid& grid);

}  // namespace leafdig::model
