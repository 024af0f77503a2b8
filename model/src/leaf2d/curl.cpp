// The curl of a 2-D leaf across its width (docs/method.md, "Leaves known only in 2-D"): the named profiles,
// their five feature heights and the natural cubic spline through them.
#include <Eigen/Core>
#include <algorithm>
#include <stdexcept>

#include "leafdig/model/errors.hpp"
#include "leafdig/model/leaf2d/leaf2d.hpp"
#include "leafdig/model/spline/interpolation.hpp"
#include "leafdig/names/name_table.hpp"

namespace leafdig::model {

const char* toString(CurlKind kind) {
  return nameIn(kCurlKindNames, kind);
}

CurlKind curlKindFromString(const std::string& word) {
  return parseName(kCurlKindNames, word, "curl");
}

std::array<double, 5> curlFeatureHeights(CurlKind kind) {
  switch (kind) {
    case CurlKind::None: return {0, 0, 0, 0, 0};
    case CurlKind::Parabola: return {0, 0.75, 1, 0.75, 0};
    case CurlKind::Sine: return {0, 1, 0, 1, 0};
    case CurlKind::Auto: break;
  }
  throw std::invalid_argument("curlFeatureHeights: Auto is a choice, not a profile");
}

namespace {

// The natural cubic spline through a curl's five heights, built once per kind.
BSplineCurve profileCurve(CurlKind kind) {
  const std::array<double, 5> h = curlFeatureHeights(kind);
  Eigen::MatrixXd values(5, 1);
  for (int i = 0; i < 5; ++i) values(i, 0) = h[static_cast<std::size_t>(i)];
  return interpolateNaturalCubic({0.0, 0.25, 0.5, 0.75, 1.0}, values);
}

}  // namespace

double curlHeight(CurlKind kind, double t) {
  static const BSplineCurve parabola = profileCurve(CurlKind::Parabola);
  static const BSplineCurve sine = profileCurve(CurlKind::Sine);
  t = std::clamp(t, 0.0, 1.0);
  switch (kind) {
    case CurlKind::None: return 0.0;
    case CurlKind::Parabola: return parabola.evaluate(t)[0];
    case CurlKind::Sine: return sine.evaluate(t)[0];
    case CurlKind::Auto: break;
  }
  throw std::invalid_argument("curlHeight: Auto is a choice, not a profile");
}

}  // namespace leafdig::model
