// Outlines in and out: reading leafdig.outline/1 JSON and x_mm,y_mm CSV files, the checks
// every outline passes (points, bounds, a margin that does not cross itself, base and tip on
// it), and writing an outline. docs/leaf2d.md.
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <optional>
#include <sstream>

#include "json_text.hpp"
#include "leaf2d/outline_check.hpp"
#include "leafdig/model/errors.hpp"
#include "leafdig/model/files.hpp"
#include "leafdig/model/leaf2d/leaf2d.hpp"
#include "leafdig/model/limits.hpp"
#include "segment.hpp"

namespace leafdig::model {

using nlohmann::json;

// ---------------------------------------------------------------------------- outlines

double polygonArea(const std::vector<Eigen::Vector2d>& polygon) {
  double twice = 0.0;
  for (std::size_t i = 0; i < polygon.size(); ++i) {
    const Eigen::Vector2d& p = polygon[i];
    const Eigen::Vector2d& q = polygon[(i + 1) % polygon.size()];
    twice += p.x() * q.y() - q.x() * p.y();
  }
  return std::abs(twice) / 2.0;
}

namespace {

constexpr std::size_t kMinOutlinePoints = 8;
constexpr std::size_t kMaxOutlinePoints = 1'000'000;
constexpr double kEndTolerance = 5.0;  // mm: a given base or tip this far off the outline is an error

double distanceToSegment(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& p) {
  return std::sqrt(detail::squaredDistanceToSegment(a, b, p));
}

double distanceToOutline(const std::vector<Eigen::Vector2d>& polygon, const Eigen::Vector2d& p) {
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < polygon.size(); ++i)
    best = std::min(best, distanceToSegment(polygon[i], polygon[(i + 1) % polygon.size()], p));
  return best;
}

// Where the outline crosses itself (a figure of eight, points out of order), as the indices of
// two segments that cross properly, or nothing. Segments are bucketed in a grid of cells a
// few segments long, so the cost stays near-linear in the points.
std::optional<std::pair<std::size_t, std::size_t>> selfCrossing(const std::vector<Eigen::Vector2d>& pts) {
  const std::size_t n = pts.size();
  Eigen::Vector2d low = pts.front(), high = pts.front();
  double length = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    low = low.cwiseMin(pts[i]);
    high = high.cwiseMax(pts[i]);
    length += (pts[(i + 1) % n] - pts[i]).norm();
  }
  const double cell = std::max(4.0 * length / static_cast<double>(n), 1e-9 + (high - low).maxCoeff() / 4096.0);
  const auto cellOf = [&](double v, double origin) { return static_cast<long>(std::floor((v - origin) / cell)); };
  std::map<std::pair<long, long>, std::vector<std::size_t>> cells;
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector2d a = pts[i], b = pts[(i + 1) % n];
    for (long x = cellOf(std::min(a.x(), b.x()), low.x()); x <= cellOf(std::max(a.x(), b.x()), low.x()); ++x)
      for (long y = cellOf(std::min(a.y(), b.y()), low.y()); y <= cellOf(std::max(a.y(), b.y()), low.y()); ++y)
        cells[{x, y}].push_back(i);
  }
  const auto orient = [](const Eigen::Vector2d& p, const Eigen::Vector2d& q, const Eigen::Vector2d& r) {
    const double v = (q.x() - p.x()) * (r.y() - p.y()) - (q.y() - p.y()) * (r.x() - p.x());
    return (v > 0) - (v < 0);
  };
  std::optional<std::pair<std::size_t, std::size_t>> first;
  for (const auto& [key, segments] : cells)
    for (std::size_t u = 0; u < segments.size(); ++u)
      for (std::size_t w = u + 1; w < segments.size(); ++w) {
        const std::size_t i = std::min(segments[u], segments[w]), j = std::max(segments[u], segments[w]);
        if (j == i + 1 || (i == 0 && j == n - 1)) continue;  // neighbours share a point
        const Eigen::Vector2d &a = pts[i], &b = pts[(i + 1) % n], &c = pts[j], &d = pts[(j + 1) % n];
        const int o1 = orient(a, b, c), o2 = orient(a, b, d), o3 = orient(c, d, a), o4 = orient(c, d, b);
        if (o1 * o2 < 0 && o3 * o4 < 0 && (!first || std::make_pair(i, j) < *first)) first = std::make_pair(i, j);
      }
  return first;
}

}  // namespace

namespace detail {
void checkOutline(const Outline2d& o, const std::string& source) {
  if (o.pointsMm.size() > kMaxOutlinePoints) {
    throw InputError(source + ": the outline has " + std::to_string(o.pointsMm.size()) +
                     " points; leafdig reads at "
                     "most " +
                     std::to_string(kMaxOutlinePoints) + " (a 1 m margin every 0.01 mm)");
  }
  if (o.pointsMm.size() < kMinOutlinePoints) {
    throw InputError(source + ": the outline has " + std::to_string(o.pointsMm.size()) + " points; at least " +
                     std::to_string(kMinOutlinePoints) + " are needed to follow a leaf's margin");
  }
  for (std::size_t i = 0; i < o.pointsMm.size(); ++i) {
    if (!o.pointsMm[i].allFinite()) {
      throw InputError(source + ": outline point " + std::to_string(i + 1) + " is not a finite number; fix the file");
    }
  }
  Eigen::Vector2d low = o.pointsMm.front(), high = o.pointsMm.front();
  for (std::size_t i = 0; i < o.pointsMm.size(); ++i) {
    if (o.pointsMm[i].cwiseAbs().maxCoeff() > kMaxCoordinateMm) {
      std::ostringstream msg;
      msg << source << ": outline point " << i + 1 << " is at (" << o.pointsMm[i].x() << ", " << o.pointsMm[i].y()
          << ") mm, beyond " << kMaxCoordinateMm / 1000 << " m; check that the points are in millimetres";
      throw InputError(msg.str());
    }
    low = low.cwiseMin(o.pointsMm[i]);
    high = high.cwiseMax(o.pointsMm[i]);
  }
  if ((high - low).norm() > kMaxLeafSpanMm) {
    std::ostringstream msg;
    msg << source << ": the outline spans " << (high - low).norm() << " mm; one leaf spans at most " << kMaxLeafSpanMm
        << " mm. Check that the points are in millimetres";
    throw InputError(msg.str());
  }
  if (const auto crossing = selfCrossing(o.pointsMm)) {
    throw InputError(source + ": the outline crosses itself (the segment from point " +
                     std::to_string(crossing->first + 1) + " crosses the one from point " +
                     std::to_string(crossing->second + 1) +
                     "): a leaf's margin goes round once, without crossing. Check the points' order");
  }
  if (polygonArea(o.pointsMm) <= 1e-6 * (high - low).squaredNorm() || polygonArea(o.pointsMm) <= 0.0) {
    throw InputError(source + ": the outline encloses no area (its points lie on a line); check the columns");
  }
  for (const auto& [name, end] : {std::pair{"base", o.baseMm}, std::pair{"tip", o.tipMm}}) {
    if (end && distanceToOutline(o.pointsMm, *end) > kEndTolerance) {
      std::ostringstream msg;
      msg << source << ": the " << name << " (" << end->x() << ", " << end->y() << ") is "
          << distanceToOutline(o.pointsMm, *end) << " mm from the outline; it must lie on the margin (within "
          << kEndTolerance << " mm) — check that it is in the outline's millimetres";
      throw InputError(msg.str());
    }
  }
  if (o.measuredAreaMm2 && !(*o.measuredAreaMm2 > 0.0)) {
    throw InputError(source + ": measured_area_mm2 must be a positive area in mm^2");
  }
}

}  // namespace detail

namespace {

Eigen::Vector2d jsonPoint(const json& v, const std::string& source, const std::string& where) {
  if (!v.is_array() || v.size() != 2)
    throw InputError(source + ": " + where + ": expected [x, y] in mm, found " + v.dump());
  Eigen::Vector2d p;
  for (int k = 0; k < 2; ++k) {
    const json& c = v[static_cast<std::size_t>(k)];
    const std::string token = detail::nonFiniteToken(c);
    if (!token.empty() || !c.is_number()) {
      throw InputError(source + ": " + where + ": coordinate " + "xy"[k] + " is " + (token.empty() ? c.dump() : token) +
                       ", not a finite number; fix the file");
    }
    p[k] = c.get<double>();
  }
  return p;
}

}  // namespace

Outline2d parseOutlineJson(const std::string& text, const std::string& source) {
  const json doc = detail::parseJsonLeniently(text, source);
  if (!doc.is_object()) throw InputError(source + ": expected a " + std::string(kOutlineFormat) + " JSON object");
  const auto format = doc.find("format");
  if (format == doc.end() || !format->is_string() || format->get<std::string>() != kOutlineFormat) {
    throw InputError(source + ": \"format\" must be \"" + kOutlineFormat + "\"" +
                     (format == doc.end() ? std::string(" (the key is missing)") : ", found " + format->dump()));
  }
  const auto units = doc.find("units");
  if (units == doc.end() || !units->is_string() || units->get<std::string>() != "mm") {
    throw InputError(source + ": \"units\" must be \"mm\"" +
                     (units == doc.end() ? std::string(" (the key is missing)") : ", found " + units->dump()) +
                     "; convert the points to millimetres (pixels: multiply by 25.4 / DPI, or give the image "
                     "itself with --dpi)");
  }
  const auto points = doc.find("points");
  if (points == doc.end() || !points->is_array()) {
    throw InputError(source + ": \"points\" must be an array of [x, y] in mm");
  }
  Outline2d o;
  for (std::size_t i = 0; i < points->size(); ++i) {
    o.pointsMm.push_back(jsonPoint((*points)[i], source, "points[" + std::to_string(i) + "]"));
  }
  if (o.pointsMm.size() > 1 && o.pointsMm.front() == o.pointsMm.back()) o.pointsMm.pop_back();
  if (auto it = doc.find("base"); it != doc.end() && !it->is_null()) o.baseMm = jsonPoint(*it, source, "base");
  if (auto it = doc.find("tip"); it != doc.end() && !it->is_null()) o.tipMm = jsonPoint(*it, source, "tip");
  if (auto it = doc.find("measured_area_mm2"); it != doc.end() && !it->is_null()) {
    if (!it->is_number()) throw InputError(source + ": measured_area_mm2 must be a number (mm^2)");
    o.measuredAreaMm2 = it->get<double>();
  }
  if (auto it = doc.find("id"); it != doc.end() && it->is_string()) o.id = it->get<std::string>();
  detail::checkOutline(o, source);
  return o;
}

Outline2d parseOutlineCsv(const std::string& text, const std::string& source) {
  Outline2d o;
  std::istringstream in(text);
  std::string line;
  int lineNo = 0;
  bool sawData = false;
  while (std::getline(in, line)) {
    ++lineNo;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const auto first = line.find_first_not_of(" \t");
    if (first == std::string::npos || line[first] == '#') continue;
    const std::string where = source + ":" + std::to_string(lineNo);
    const auto comma = line.find(',');
    if (comma == std::string::npos) throw InputError(where + ": expected \"x_mm,y_mm\", found \"" + line + "\"");
    const std::string a = line.substr(0, comma);
    const std::string b = line.substr(comma + 1);
    const bool letters = std::any_of(line.begin(), line.end(), [](unsigned char c) { return std::isalpha(c) != 0; });
    if (!sawData && letters && a.find("nan") == std::string::npos && a.find("inf") == std::string::npos) {
      // A header: its units must be millimetres.
      const bool mm = a.find("mm") != std::string::npos && b.find("mm") != std::string::npos;
      const bool bare =
          a.find_first_not_of(" \txX") == std::string::npos && b.find_first_not_of(" \tyY") == std::string::npos;
      if (!mm && !bare) {
        throw InputError(where + ": the header \"" + line +
                         "\" does not say millimetres; the columns must be x_mm,y_mm (convert pixels with "
                         "25.4 / DPI, or give the image itself with --dpi)");
      }
      sawData = true;  // only one header
      continue;
    }
    sawData = true;
    Eigen::Vector2d p;
    for (int k = 0; k < 2; ++k) {
      const std::string field = k == 0 ? a : b;
      std::size_t used = 0;
      double v = std::numeric_limits<double>::quiet_NaN();
      try {
        v = std::stod(field, &used);
      } catch (const std::exception&) {
        used = 0;
      }
      if (used == 0 || field.find_first_not_of(" \t", used) != std::string::npos || !std::isfinite(v)) {
        throw InputError(where + ": column " + std::to_string(k + 1) + " (\"" + field +
                         "\") is not a finite number in mm; fix the line");
      }
      p[k] = v;
    }
    o.pointsMm.push_back(p);
  }
  if (o.pointsMm.size() > 1 && o.pointsMm.front() == o.pointsMm.back()) o.pointsMm.pop_back();
  detail::checkOutline(o, source);
  return o;
}

Outline2d readOutlineFile(const std::filesystem::path& path) {
  const std::string ext = lowerExtension(path);
  if (ext != ".json" && ext != ".csv") {
    throw InputError(path.string() + ": an outline is a .json (" + kOutlineFormat +
                     ") or .csv (x_mm,y_mm) file; a scan is a .png, .tif or .jpg image given with --dpi");
  }
  std::string text;
  try {
    text = readFile(path);
  } catch (const IoError& e) {
    throw InputError(std::string(e.what()) + "; check the path");
  }
  if (text.find_first_not_of(" \t\r\n") == std::string::npos) throw InputError(path.string() + ": the file is empty");
  return ext == ".json" ? parseOutlineJson(text, path.string()) : parseOutlineCsv(text, path.string());
}

std::string outlineToJson(const Outline2d& o) {
  std::ostringstream out;
  out << "{\"format\": \"" << kOutlineFormat << "\", \"units\": \"mm\"";
  if (!o.id.empty()) out << ", \"id\": " << json(o.id).dump();
  if (o.baseMm)
    out << ", \"base\": [" << detail::formatNumber(o.baseMm->x()) << ", " << detail::formatNumber(o.baseMm->y()) << "]";
  if (o.tipMm)
    out << ", \"tip\": [" << detail::formatNumber(o.tipMm->x()) << ", " << detail::formatNumber(o.tipMm->y()) << "]";
  if (o.measuredAreaMm2) out << ", \"measured_area_mm2\": " << detail::formatNumber(*o.measuredAreaMm2);
  out << ",\n \"points\": [";
  for (std::size_t i = 0; i < o.pointsMm.size(); ++i) {
    out << (i ? ",\n  " : "\n  ") << "[" << detail::formatNumber(o.pointsMm[i].x()) << ", "
        << detail::formatNumber(o.pointsMm[i].y()) << "]";
  }
  out << "]}\n";
  return out.str();
}

}  // namespace leafdig::model
