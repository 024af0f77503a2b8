#pragma once
// Leaf assembly of docs/method.md §3–5: veins as BBSCs plus the blade, and the leaf frame.
#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "leafdig/model/leaf/blade.hpp"
#include "leafdig/model/leaf/markers.hpp"
#include "leafdig/model/spline/ball_bspline_curve.hpp"

namespace leafdig::model {

struct Vein {
  std::string name;  // "midrib" | "lateral-<i>-right" | "lateral-<i>-left" | "contour"
  BallBSplineCurve curve;
};

struct LeafModel {
  MarkerSet markers;  // in the model's frame
  LeafThickness thickness;
  std::vector<Vein> veins;  // midrib, lateral-1-right, lateral-1-left, ..., contour
  BladeSurface blade;
};

struct LeafModelOptions {
  BladeKind blade = BladeKind::Interp;
  const std::vector<std::vector<double>>* nurbsWeights = nullptr;
};

// Validates the markers (geometry and thickness rule), then builds every vein and the
// blade. Throws InputError naming the row and point at fault; nothing partial is returned.
//   midrib: T, P_14 .. P_N4, radii d/2, r_14^1/2 .. r_N4^1/2
//   lateral-i-right: P_i4, P_i3, P_i2, P_i1; lateral-i-left: P_i4, P_i5, P_i6, P_i7
//   contour: P_N1 .. P_11, T, P_17 .. P_N7, radius d/2 (or per-row edge thickness / 2)
[[nodiscard]] LeafModel buildLeafModel(const MarkerSet& markers, const LeafModelOptions& options = {});

// The leaf frame (leafFrameFromDigitizer) is in mesh/mesh.hpp: it measures the blade's mean
// normal on a mesh.

// The same leaf under a rigid transform. B-splines are affine invariant, so transforming
// control points is exact; radii are unchanged.
[[nodiscard]] LeafModel transformed(const LeafModel& model, const Eigen::Isometry3d& transform);

}  // namespace leafdig::model
