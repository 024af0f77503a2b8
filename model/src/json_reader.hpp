#pragma once
// Private: the reader the JSON input formats share (markers, plant markers): required keys,
// finite and bounded numbers, points and units, each failure an InputError naming the
// source, where in the document, and what to fix.
#include <Eigen/Core>
#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <string>

#include "json_text.hpp"
#include "leafdig/model/errors.hpp"
#include "leafdig/model/files.hpp"
#include "leafdig/model/limits.hpp"

namespace leafdig::model::detail {

// A file a user hands us, read whole (files.hpp's checks: a regular file, bounded size); a
// file that cannot be read is the user's to fix, so an InputError.
inline std::string readInputText(const std::filesystem::path& path) {
  try {
    return readFile(path);
  } catch (const IoError& e) {
    throw InputError(std::string(e.what()) + "; check the path");
  }
}

class JsonReader {
 public:
  // `source` names the input in messages (a path, "<stdin>"); `format` is the document's
  // format name, whose schema a missing key points to.
  JsonReader(std::string source, std::string format) : source_(std::move(source)), format_(std::move(format)) {}

  [[noreturn]] void fail(const std::string& where, const std::string& what) const {
    throw InputError(source_ + ": " + where + ": " + what);
  }

  [[nodiscard]] const nlohmann::json& require(const nlohmann::json& object, const char* key,
                                              const std::string& where) const {
    if (!object.is_object()) fail(where, "expected an object");
    const auto it = object.find(key);
    if (it == object.end()) {
      fail(where, std::string("required key \"") + key + "\" is missing; add it (see the " + format_ +
                      " schema in data/schema/)");
    }
    return *it;
  }

  // A finite number times `scale`; NaN, Infinity, strings and null are named errors, and so
  // is a value beyond `limit` (in mm after scaling): `limitWhy` says what bounds it.
  [[nodiscard]] double bounded(const nlohmann::json& value, const std::string& where, const std::string& what,
                               double scale, double low, double high, const std::string& bound) const {
    const double v = number(value, where, what, scale);
    if (!(v >= low && v <= high)) {
      std::ostringstream out;
      out << what << " is " << v << " mm; " << bound << ". Check the number and the file's \"units\"";
      fail(where, out.str());
    }
    return v;
  }
  [[nodiscard]] double thickness(const nlohmann::json& value, const std::string& where, const std::string& what,
                                 double scale) const {
    return bounded(value, where, what, scale, -kMaxThicknessMm, kMaxThicknessMm,
                   "a caliper reading of a leaf is at most " + detail::formatNumber(kMaxThicknessMm) + " mm");
  }
  [[nodiscard]] std::optional<double> optionalThickness(const nlohmann::json& object, const char* key,
                                                        const std::string& where, double scale) const {
    const auto it = object.find(key);
    if (it == object.end() || it->is_null()) return std::nullopt;
    return thickness(*it, where, key, scale);
  }

  [[nodiscard]] double number(const nlohmann::json& value, const std::string& where, const std::string& what,
                              double scale) const {
    const std::string token = detail::nonFiniteToken(value);
    if (!token.empty()) {
      fail(where, what + " is " + token + ", not a finite number; re-measure or fix the file");
    }
    if (!value.is_number()) fail(where, what + " must be a number, found " + value.type_name());
    const double v = value.get<double>();
    if (!std::isfinite(v)) fail(where, what + " is not a finite number; re-measure or fix the file");
    return v * scale;
  }

  [[nodiscard]] std::optional<double> optionalNumber(const nlohmann::json& object, const char* key,
                                                     const std::string& where, double scale) const {
    const auto it = object.find(key);
    if (it == object.end() || it->is_null()) return std::nullopt;
    return number(*it, where, key, scale);
  }

  [[nodiscard]] Eigen::Vector3d point(const nlohmann::json& value, const std::string& where, double scale) const {
    if (!value.is_array() || value.size() != 3) {
      fail(where, "a marker must be [x, y, z], found " + value.dump());
    }
    Eigen::Vector3d p;
    for (int axis = 0; axis < 3; ++axis) {
      p[axis] =
          bounded(value[static_cast<std::size_t>(axis)], where, std::string("coordinate ") + "xyz"[axis], scale,
                  -kMaxCoordinateMm, kMaxCoordinateMm,
                  "a digitizer measures within " + detail::formatNumber(kMaxCoordinateMm / 1000) + " m of its origin");
    }
    return p;
  }

  // "mm", "cm" or "in": the factor to millimetres.
  [[nodiscard]] double unitScale(const nlohmann::json& units) const {
    if (!units.is_string()) fail("units", "must be a string: \"mm\", \"cm\" or \"in\"");
    const auto& u = units.get_ref<const std::string&>();
    if (u == "mm") return 1.0;
    if (u == "cm") return 10.0;
    if (u == "in") return 25.4;
    fail("units", "unknown unit \"" + u + "\"; use \"mm\", \"cm\" or \"in\"");
  }

 private:
  std::string source_;
  std::string format_;
};

}  // namespace leafdig::model::detail
