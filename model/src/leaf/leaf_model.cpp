#include "leafdig/model/leaf/leaf_model.hpp"

#include <stdexcept>

#include "leafdig/model/errors.hpp"

namespace leafdig::model {

namespace {

Vein makeVein(std::string name, const std::vector<Ball>& balls) {
  try {
    return {name, BallBSplineCurve::interpolate(balls)};
  } catch (const std::invalid_argument& e) {
    // Geometry validation catches coincident markers first; this is the last guard.
    throw InputError(name + ": " + e.what() + "; re-digitize the markers of this vein");
  }
}

}  // namespace

LeafModel buildLeafModel(const MarkerSet& markers, const LeafModelOptions& options) {
  validateMarkerGeometry(markers);
  LeafModel model{markers, applyThicknessRule(markers), {}, {}};
  const LeafThickness& th = model.thickness;
  const int n = static_cast<int>(markers.rows.size());

  std::vector<Ball> midrib{{markers.tipMm, th.tipMm / 2}};
  for (int i = 0; i < n; ++i) {
    midrib.push_back({markers.rows[i].pointsMm[kMidribColumn], th.rows[i].midribMm / 2});
  }
  model.veins.push_back(makeVein("midrib", midrib));

  for (int i = 0; i < n; ++i) {
    const auto& pts = markers.rows[i].pointsMm;
    const auto& t = th.rows[i].lateralMm;
    const std::string prefix = "lateral-" + std::to_string(i + 1);
    std::vector<Ball> right;
    std::vector<Ball> left;
    for (int j = kMidribColumn; j >= 0; --j) right.push_back({pts[j], t[j] / 2});
    for (int j = kMidribColumn; j < kMarkersPerRow; ++j) left.push_back({pts[j], t[j] / 2});
    model.veins.push_back(makeVein(prefix + "-right", right));
    model.veins.push_back(makeVein(prefix + "-left", left));
  }

  std::vector<Ball> contour;
  for (int i = n - 1; i >= 0; --i) {
    contour.push_back({markers.rows[i].pointsMm[0], th.rows[i].lateralMm[0] / 2});
  }
  contour.push_back({markers.tipMm, th.tipMm / 2});
  for (int i = 0; i < n; ++i) {
    contour.push_back({markers.rows[i].pointsMm[6], th.rows[i].lateralMm[6] / 2});
  }
  model.veins.push_back(makeVein("contour", contour));

  model.blade = buildBlade(markerGrid(markers), options.blade, options.nurbsWeights);
  return model;
}

LeafModel transformed(const LeafModel& model, const Eigen::Isometry3d& transform) {
  LeafModel out = model;
  out.markers.tipMm = transform * model.markers.tipMm;
  for (MarkerRow& row : out.markers.rows) {
    for (Eigen::Vector3d& p : row.pointsMm) p = transform * p;
  }
  out.veins.clear();
  for (const Vein& vein : model.veins) {
    const BSplineCurve& s = vein.curve.spline();
    Eigen::MatrixXd control = s.controlPoints();
    for (Eigen::Index i = 0; i < control.rows(); ++i) {
      const Eigen::Vector3d p = control.row(i).head<3>().transpose();
      control.row(i).head<3>() = (transform * p).transpose();
    }
    std::vector<Ball> balls = vein.curve.dataBalls();
    for (Ball& b : balls) b.center = transform * b.center;
    out.veins.push_back({vein.name, BallBSplineCurve(BSplineCurve(s.degree(), s.knots(), control),
                                                     vein.curve.dataParameters(), balls)});
  }
  for (auto& row : out.blade.controlNet) {
    for (Eigen::Vector3d& p : row) p = transform * p;
  }
  return out;
}

}  // namespace leafdig::model
