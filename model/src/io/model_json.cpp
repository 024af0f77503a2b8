#include "leafdig/model/io/model_json.hpp"

#include "json_text.hpp"
#include "leafdig/model/errors.hpp"
#include "leafdig/names/name_table.hpp"

namespace leafdig::model {

using nlohmann::json;

namespace {

json vector3(const Eigen::Vector3d& p) {
  return json::array({p.x(), p.y(), p.z()});
}

}  // namespace

std::string modelToJson(const LeafModel& model, const std::string& frame, const LeafMetrics& metrics) {
  json doc;
  doc["format"] = kModelFormat;
  doc["units"] = "mm";
  doc["frame"] = frame;
  doc["radius_note"] = "ball radii are caliper thickness / 2";
  if (!model.markers.leaf.id.empty()) doc["leaf"] = model.markers.leaf.id;
  doc["thickness_mode"] = toString(model.thickness.mode);
  json veins = json::array();
  for (const Vein& v : model.veins) {
    const BSplineCurve& s = v.curve.spline();
    json control = json::array();
    for (Eigen::Index i = 0; i < s.controlPoints().rows(); ++i) {
      const auto row = s.controlPoints().row(i);
      control.push_back({row(0), row(1), row(2), row(3)});
    }
    json balls = json::array();
    for (const Ball& b : v.curve.dataBalls()) {
      balls.push_back({b.center.x(), b.center.y(), b.center.z(), b.radius});
    }
    veins.push_back({{"name", v.name},
                     {"degree", s.degree()},
                     {"knots", s.knots()},
                     {"control_balls", control},
                     {"data_parameters", v.curve.dataParameters()},
                     {"data_balls", balls}});
  }
  doc["veins"] = veins;
  const BladeSurface& b = model.blade;
  json net = json::array();
  for (const auto& row : b.controlNet) {
    json r = json::array();
    for (const auto& p : row) r.push_back(vector3(p));
    net.push_back(r);
  }
  doc["blade"] = {{"kind", toString(b.kind)},
                  {"degree_u", b.degreeU},
                  {"degree_v", b.degreeV},
                  {"knots_u", b.knotsU},
                  {"knots_v", b.knotsV},
                  {"control_net", net},
                  {"weights", b.weights.empty() ? json(nullptr) : json(b.weights)},
                  {"row_parameters", b.rowParameters},
                  {"column_parameters", b.columnParameters}};
  doc["metrics"] = json::parse(metricsToJson(metrics));
  return detail::dumpFinite(doc, 1) + "\n";
}

namespace {

const json& need(const json& obj, const char* key, const std::string& where) {
  if (!obj.is_object() || !obj.contains(key)) {
    throw InputError(where + ": required key \"" + key + "\" is missing");
  }
  return obj.at(key);
}

template <typename T>
T as(const json& value, const std::string& where) {
  try {
    return value.get<T>();
  } catch (const json::exception&) {
    throw InputError(where + ": wrong type (" + value.type_name() + ")");
  }
}

}  // namespace

ModelDocument parseModelJson(std::string_view text, const std::string& source) {
  const json doc = detail::parseJsonLeniently(text, source);
  if (as<std::string>(need(doc, "format", source), source + ": format") != kModelFormat) {
    throw InputError(source + ": format is not " + std::string(kModelFormat));
  }
  ModelDocument out;
  out.frame = as<std::string>(need(doc, "frame", source), source + ": frame");
  for (const json& v : need(doc, "veins", source)) {
    const std::string name = as<std::string>(need(v, "name", source + ": vein"), source + ": vein name");
    const std::string where = source + ": vein " + name;
    const auto control = as<std::vector<std::vector<double>>>(need(v, "control_balls", where), where);
    Eigen::MatrixXd ctrl(static_cast<Eigen::Index>(control.size()), 4);
    for (std::size_t i = 0; i < control.size(); ++i) {
      if (control[i].size() != 4) throw InputError(where + ": a control ball needs x, y, z, r");
      for (int c = 0; c < 4; ++c) ctrl(static_cast<Eigen::Index>(i), c) = control[i][c];
    }
    std::vector<Ball> balls;
    for (const auto& b : as<std::vector<std::vector<double>>>(need(v, "data_balls", where), where)) {
      if (b.size() != 4) throw InputError(where + ": a data ball needs x, y, z, r");
      balls.push_back({Eigen::Vector3d(b[0], b[1], b[2]), b[3]});
    }
    try {
      out.veins.push_back(
          {name, BallBSplineCurve(BSplineCurve(as<int>(need(v, "degree", where), where),
                                               as<KnotVector>(need(v, "knots", where), where), ctrl),
                                  as<std::vector<double>>(need(v, "data_parameters", where), where), balls)});
    } catch (const std::invalid_argument& e) {
      throw InputError(where + ": " + e.what());
    }
  }
  const json& b = need(doc, "blade", source);
  const std::string where = source + ": blade";
  try {
    out.blade.kind = bladeKindFromString(as<std::string>(need(b, "kind", where), where));
  } catch (const UnknownName& e) {
    throw InputError(where + " kind: " + e.what());
  }
  out.blade.degreeU = as<int>(need(b, "degree_u", where), where);
  out.blade.degreeV = as<int>(need(b, "degree_v", where), where);
  out.blade.knotsU = as<KnotVector>(need(b, "knots_u", where), where);
  out.blade.knotsV = as<KnotVector>(need(b, "knots_v", where), where);
  for (const auto& row : as<std::vector<std::vector<std::vector<double>>>>(need(b, "control_net", where), where)) {
    std::vector<Eigen::Vector3d> r;
    for (const auto& p : row) {
      if (p.size() != 3) throw InputError(where + ": a control point needs x, y, z");
      r.emplace_back(p[0], p[1], p[2]);
    }
    out.blade.controlNet.push_back(std::move(r));
  }
  if (const auto it = b.find("weights"); it != b.end() && !it->is_null()) {
    out.blade.weights = as<std::vector<std::vector<double>>>(*it, where);
  }
  if (b.contains("row_parameters")) out.blade.rowParameters = as<std::vector<double>>(b["row_parameters"], where);
  if (b.contains("column_parameters")) {
    out.blade.columnParameters = as<std::vector<double>>(b["column_parameters"], where);
  }
  const json& metrics = need(doc, "metrics", source);
  out.bladeAreaMm2 = as<double>(need(metrics, "blade_area_mm2", source + ": metrics"), source);
  out.projectedAreaMm2 = as<double>(need(metrics, "projected_area_mm2", source + ": metrics"), source);
  return out;
}

}  // namespace leafdig::model
