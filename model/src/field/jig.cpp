#include "leafdig/model/field/jig.hpp"

#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <set>

#include "json_reader.hpp"
#include "leafdig/model/errors.hpp"

namespace leafdig::model {
namespace {

using nlohmann::json;

// How far the points spread across their best plane, in mm: under a millimetre, the jig is flat.
double thickness(const std::vector<JigPoint>& points) {
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const JigPoint& p : points) mean += p.pointMm;
  mean /= static_cast<double>(points.size());
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  for (const JigPoint& p : points) scatter += (p.pointMm - mean) * (p.pointMm - mean).transpose();
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(scatter);
  return std::sqrt(std::max(0.0, svd.singularValues()[2] / static_cast<double>(points.size())));
}

}  // namespace

Jig parseJig(const std::string& text, const std::string& source) {
  const detail::JsonReader r(source, kJigFormat);
  json doc;
  try {
    doc = json::parse(text);
  } catch (const json::exception& e) {
    r.fail("the file", std::string("is not JSON leafdig reads (") + e.what() + ")");
  }
  if (!doc.is_object()) r.fail("the file", "is not a JSON object");
  const json& format = r.require(doc, "format", "the file");
  if (format != kJigFormat)
    r.fail("format", "is " + format.dump().substr(0, 60) + ", not \"" + kJigFormat + "\": this is not a jig file");
  const double scale = r.unitScale(r.require(doc, "units", "the file"));
  Jig jig;
  if (const auto name = doc.find("name"); name != doc.end()) {
    if (!name->is_string() || name->get_ref<const std::string&>().size() > 200)
      r.fail("name", "must be text of at most 200 characters");
    jig.name = name->get<std::string>();
  }
  const json& points = r.require(doc, "points", "the file");
  if (!points.is_array()) r.fail("points", "must be a list of {\"id\", \"point\"}");
  if (points.size() > 1000) r.fail("points", "holds " + std::to_string(points.size()) + " points: at most 1000");
  std::set<std::string> ids;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const std::string where = "points[" + std::to_string(i) + "]";
    const json& id = r.require(points[i], "id", where);
    if (!id.is_string() || id.get_ref<const std::string&>().empty() || id.get_ref<const std::string&>().size() > 32)
      r.fail(where, "its id must be text of 1 to 32 characters");
    const std::string name = id.get<std::string>();
    if (!std::all_of(name.begin(), name.end(), [](char c) { return c > ' ' && c < 127 && c != '"' && c != ','; }))
      r.fail(where, "its id must be printable letters, digits and marks, without spaces, quotes or commas");
    if (!ids.insert(name).second) r.fail(where, "its id \"" + name + "\" is used twice: give each divot its own");
    jig.points.push_back({name, r.point(r.require(points[i], "point", where), where, scale)});
  }
  if (jig.points.size() < 4) r.fail("points", "a jig needs at least 4 points to check a field against");
  if (thickness(jig.points) < 1.0)
    r.fail("points",
           "all lie in one plane: a jig needs points on two or three levels, or a flat jig cannot tell a "
           "field's height error from a tilt");
  return jig;
}

Jig readJigFile(const std::string& path) {
  return parseJig(detail::readInputText(path), path);
}

JigFit fitJig(const Jig& jig, const std::vector<Eigen::Vector3d>& measuredMm) {
  if (measuredMm.size() != jig.points.size())
    throw InputError("the jig has " + std::to_string(jig.points.size()) + " points but " +
                     std::to_string(measuredMm.size()) + " were measured: digitize every point, in the jig's order");
  const std::size_t n = measuredMm.size();
  Eigen::Matrix3Xd from(3, static_cast<Eigen::Index>(n)), to(3, static_cast<Eigen::Index>(n));
  for (std::size_t i = 0; i < n; ++i) {
    from.col(static_cast<Eigen::Index>(i)) = jig.points[i].pointMm;
    to.col(static_cast<Eigen::Index>(i)) = measuredMm[i];
  }
  JigFit fit;
  fit.jigToDigitizer.matrix() = Eigen::umeyama(from, to, false);  // rotation and translation only
  double sum = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d r = measuredMm[i] - fit.jigToDigitizer * jig.points[i].pointMm;
    fit.residualsMm.push_back(r);
    sum += r.squaredNorm();
    if (fit.worstId.empty() || r.norm() > fit.maxMm) {
      fit.maxMm = r.norm();
      fit.worstId = jig.points[i].id;
    }
  }
  fit.rmsMm = std::sqrt(sum / static_cast<double>(n));
  return fit;
}

}  // namespace leafdig::model
