#include "leafdig/model/leaf/markers_json.hpp"

#include <cmath>
#include <sstream>

#include "json_reader.hpp"
#include "json_text.hpp"
#include "leafdig/model/errors.hpp"
#include "leafdig/model/files.hpp"
#include "leafdig/model/limits.hpp"
#include "leafdig/names/name_table.hpp"

namespace leafdig::model {

using nlohmann::json;

namespace {

std::string pointWhere(std::size_t row, std::size_t point) {
  return "row " + std::to_string(row + 1) + ", point " + std::to_string(point + 1);
}

}  // namespace

MarkerSet parseMarkersJson(std::string_view text, const std::string& source) {
  const detail::JsonReader reader(source, kMarkersFormat);
  if (text.find_first_not_of(" \t\r\n") == std::string_view::npos) {
    throw InputError(source + ": the file is empty; expected a " + std::string(kMarkersFormat) + " JSON document");
  }
  const json doc = detail::parseJsonLeniently(text, source);
  if (!doc.is_object()) reader.fail("top level", "expected a JSON object");

  const json& format = reader.require(doc, "format", "top level");
  if (format != kMarkersFormat) {
    reader.fail("format", "expected \"" + std::string(kMarkersFormat) + "\", found " + format.dump() +
                              "; this is not a leafdig marker file");
  }
  const double scale = reader.unitScale(reader.require(doc, "units", "top level"));
  double thicknessScale = scale;
  if (const auto it = doc.find("thickness_kind"); it != doc.end()) {
    if (*it == "radius") {
      thicknessScale = 2 * scale;  // stored as diameters inside
    } else if (*it != "diameter") {
      reader.fail("thickness_kind", "must be \"diameter\" (caliper readings) or \"radius\", found " + it->dump());
    }
  }

  MarkerSet m;
  if (const auto it = doc.find("leaf"); it != doc.end() && it->is_object()) {
    const json& leaf = *it;
    // Present means of its type: "plant": 12 is named, not read as no plant (issue 47, 23).
    const auto text = [&](const char* key, std::string& into) {
      const auto v = leaf.find(key);
      if (v == leaf.end() || v->is_null()) return;
      if (!v->is_string()) reader.fail(std::string("leaf.") + key, "must be text (in quotes), found " + v->dump());
      into = *v;
    };
    text("id", m.leaf.id);
    text("plant", m.leaf.plant);
    text("type", m.leaf.type);
    if (auto v = leaf.find("position"); v != leaf.end() && !v->is_null()) {
      if (!v->is_number_integer()) reader.fail("leaf.position", "must be a whole number, found " + v->dump());
      m.leaf.position = v->get<int>();
    }
    m.leaf.measuredAreaMm2 = reader.optionalNumber(leaf, "measured_area_mm2", "leaf", 1.0);
    if (const auto v = leaf.find("serration"); v != leaf.end() && !v->is_null()) {
      if (!v->is_string()) reader.fail("leaf.serration", "must be none, round, sharp, straight or acuminate");
      try {
        m.leaf.serration = serrationFromString(v->get<std::string>());
      } catch (const UnknownName& e) {
        reader.fail("leaf.serration", e.what());
      }
    }
    if (const auto v = leaf.find("tooth_depth_mm"); v != leaf.end() && !v->is_null()) {
      m.leaf.toothDepthMm =
          reader.bounded(*v, "leaf", "tooth_depth_mm", scale, 1e-9, kMaxThicknessMm,
                         "a tooth of a leaf's margin is at most " + detail::formatNumber(kMaxThicknessMm) + " mm deep");
      if (!m.leaf.serration || *m.leaf.serration == Serration::None)
        reader.fail("leaf.tooth_depth_mm", "is given but the leaf's serration is not: add \"serration\"");
    }
    if (const auto v = leaf.find("margin_from_scan"); v != leaf.end() && !v->is_null()) {
      if (!v->is_array() || v->empty() || v->size() > 64)
        reader.fail("leaf.margin_from_scan",
                    "must be a list of 1 to 64 {\"spacing_mm\", \"outside_mm\", \"inside_mm\"}, by spacing");
      MarginFromScan margin;
      for (std::size_t k = 0; k < v->size(); ++k) {
        const std::string where = "leaf.margin_from_scan[" + std::to_string(k) + "]";
        const std::string bound = "a leaf's margin detail is at most " + detail::formatNumber(kMaxThicknessMm) + " mm";
        MarginSample sample;
        sample.spacingMm = reader.bounded(reader.require((*v)[k], "spacing_mm", where), where, "spacing_mm", scale,
                                          1e-3, kMaxLeafSpanMm, "a spacing along a leaf's margin is at most 3 m");
        sample.outsideMm = reader.bounded(reader.require((*v)[k], "outside_mm", where), where, "outside_mm", scale, 0.0,
                                          kMaxThicknessMm, bound);
        sample.insideMm = reader.bounded(reader.require((*v)[k], "inside_mm", where), where, "inside_mm", scale, 0.0,
                                         kMaxThicknessMm, bound);
        if (!margin.empty() && !(sample.spacingMm > margin.back().spacingMm))
          reader.fail(where, "spacings must increase");
        margin.push_back(sample);
      }
      m.leaf.marginFromScan = margin;
    }
    if (m.leaf.measuredAreaMm2 && !(*m.leaf.measuredAreaMm2 > 0 && *m.leaf.measuredAreaMm2 <= kMaxLeafAreaMm2)) {
      std::ostringstream out;
      out << "measured_area_mm2 is " << *m.leaf.measuredAreaMm2 << " mm^2; a leaf's area is positive and at most "
          << kMaxLeafAreaMm2 / 1e6 << " m^2";
      reader.fail("leaf", out.str());
    }
  }
  if (const auto it = doc.find("mode"); it != doc.end() && !it->is_null()) {
    if (!it->is_string()) reader.fail("mode", "must be \"standard\", \"full\" or \"small\"");
    try {
      m.mode = thicknessModeFromString(it->get<std::string>());
    } catch (const UnknownName& e) {
      reader.fail("mode", e.what());
    }
  }

  m.tipMm = reader.point(reader.require(doc, "tip", "top level"), "tip", scale);
  const json& rows = reader.require(doc, "rows", "top level");
  if (!rows.is_array()) reader.fail("rows", "must be an array of rows");
  if (rows.empty()) {
    reader.fail("rows", "no rows; a leaf needs at least one row of 7 markers below the tip");
  }
  if (rows.size() > kMaxRows) {
    reader.fail("rows", std::to_string(rows.size()) + " rows; a leaf takes at most " + std::to_string(kMaxRows) +
                            " (a 1 m leaf with a row every millimetre)");
  }
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const std::string where = "row " + std::to_string(i + 1);
    const json& row = rows[i];
    const json& points = reader.require(row, "points", where);
    if (!points.is_array() || points.size() != kMarkersPerRow) {
      reader.fail(where, "has " + std::to_string(points.is_array() ? points.size() : 0) +
                             " points; every row needs exactly 7 markers, right to left with "
                             "the 4th on the midrib. Re-digitize the row.");
    }
    MarkerRow r;
    for (std::size_t j = 0; j < kMarkersPerRow; ++j) {
      r.pointsMm[j] = reader.point(points[j], pointWhere(i, j), scale);
    }
    r.midribThicknessMm = reader.optionalThickness(row, "midrib_thickness", where, thicknessScale);
    r.veinOriginThicknessMm = reader.optionalThickness(row, "vein_origin_thickness", where, thicknessScale);
    r.edgeThicknessMm = reader.optionalThickness(row, "edge_thickness", where, thicknessScale);
    if (const auto it = row.find("thickness"); it != row.end() && !it->is_null()) {
      if (!it->is_array() || it->size() != kMarkersPerRow) {
        reader.fail(where, "\"thickness\" must list 7 values (null where not measured)");
      }
      for (std::size_t j = 0; j < kMarkersPerRow; ++j) {
        const json& t = (*it)[j];
        if (!t.is_null()) r.measuredThicknessMm[j] = reader.thickness(t, pointWhere(i, j), "thickness", thicknessScale);
      }
    }
    m.rows.push_back(r);
  }
  m.edgeThicknessMm = reader.optionalThickness(doc, "edge_thickness", "top level", thicknessScale);
  return m;
}

MarkerSet readMarkersFile(const std::filesystem::path& path) {
  return parseMarkersJson(detail::readInputText(path), path.string());
}

namespace {

void appendPoint(std::ostringstream& out, const Eigen::Vector3d& p) {
  out << "[" << detail::formatNumber(p.x()) << ", " << detail::formatNumber(p.y()) << ", "
      << detail::formatNumber(p.z()) << "]";
}

}  // namespace

std::string markersToJson(const MarkerSet& m) {
  std::ostringstream out;
  out << "{\n  \"format\": \"" << kMarkersFormat << "\",\n  \"units\": \"mm\",\n"
      << "  \"thickness_kind\": \"diameter\",\n";
  json leaf = json::object();
  if (!m.leaf.id.empty()) leaf["id"] = m.leaf.id;
  if (!m.leaf.plant.empty()) leaf["plant"] = m.leaf.plant;
  if (m.leaf.position) leaf["position"] = *m.leaf.position;
  if (!m.leaf.type.empty()) leaf["type"] = m.leaf.type;
  if (m.leaf.measuredAreaMm2) leaf["measured_area_mm2"] = *m.leaf.measuredAreaMm2;
  if (m.leaf.serration) leaf["serration"] = toString(*m.leaf.serration);
  if (m.leaf.toothDepthMm) leaf["tooth_depth_mm"] = *m.leaf.toothDepthMm;
  if (m.leaf.marginFromScan) {
    json margin = json::array();
    for (const MarginSample& sample : *m.leaf.marginFromScan)
      margin.push_back(
          {{"spacing_mm", sample.spacingMm}, {"outside_mm", sample.outsideMm}, {"inside_mm", sample.insideMm}});
    leaf["margin_from_scan"] = margin;
  }
  out << "  \"leaf\": " << leaf.dump() << ",\n";
  if (m.mode) out << "  \"mode\": \"" << toString(*m.mode) << "\",\n";
  out << "  \"tip\": ";
  appendPoint(out, m.tipMm);
  out << ",\n  \"rows\": [\n";
  for (std::size_t i = 0; i < m.rows.size(); ++i) {
    const MarkerRow& r = m.rows[i];
    out << "    {\"points\": [";
    for (int j = 0; j < kMarkersPerRow; ++j) {
      out << (j ? ", " : "");
      appendPoint(out, r.pointsMm[j]);
    }
    out << "]";
    auto field = [&](const char* key, const std::optional<double>& v) {
      if (v) out << ",\n     \"" << key << "\": " << detail::formatNumber(*v);
    };
    field("midrib_thickness", r.midribThicknessMm);
    field("vein_origin_thickness", r.veinOriginThicknessMm);
    bool anyMeasured = false;
    for (const auto& t : r.measuredThicknessMm) anyMeasured = anyMeasured || t.has_value();
    if (anyMeasured) {
      out << ",\n     \"thickness\": [";
      for (int j = 0; j < kMarkersPerRow; ++j) {
        out << (j ? ", " : "") << (r.measuredThicknessMm[j] ? detail::formatNumber(*r.measuredThicknessMm[j]) : "null");
      }
      out << "]";
    }
    field("edge_thickness", r.edgeThicknessMm);
    out << "}" << (i + 1 < m.rows.size() ? "," : "") << "\n";
  }
  out << "  ]";
  if (m.edgeThicknessMm) out << ",\n  \"edge_thickness\": " << detail::formatNumber(*m.edgeThicknessMm);
  out << "\n}\n";
  return out.str();
}

}  // namespace leafdig::model
