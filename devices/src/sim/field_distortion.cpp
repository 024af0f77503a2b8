#include "leafdig/devices/sim/field_distortion.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <sstream>

#include "leafdig/devices/pose.hpp"
#include "leafdig/devices/rotation_eigen.hpp"

namespace leafdig::devices::sim {
namespace {

using nlohmann::json;

[[noreturn]] void refuse(const std::string& source, const std::string& what) {
  throw FieldDistortionError(source + ": " + what +
                             " (a leafdig.field-distortion/1 file: docs/devices.md, \"The field\"; `leafdig field "
                             "model steel-bench -o FILE` writes one)");
}

double numberAt(const json& j, const std::string& source, const std::string& where, double limit) {
  if (!j.is_number()) refuse(source, where + " is not a number");
  const double v = j.get<double>();
  if (!std::isfinite(v) || std::abs(v) > limit)
    refuse(source, where + " is " + j.dump() + ", not a number within ±" + json(limit).dump());
  return v;
}

Vec3 tripleAt(const json& j, const std::string& source, const std::string& where, double limit) {
  if (!j.is_array() || j.size() != 3) refuse(source, where + " is not three numbers [x, y, z]");
  Vec3 out{};
  for (std::size_t a = 0; a < 3; ++a) out[a] = numberAt(j[a], source, where + "[" + std::to_string(a) + "]", limit);
  return out;
}

std::vector<Vec3> gridAt(const json& doc, const char* key, std::size_t cells, const std::string& source, double limit) {
  const json& a = doc.at(key);
  if (!a.is_array()) refuse(source, std::string(key) + " is not a list of [x, y, z]");
  if (a.size() != cells)
    refuse(source, std::string(key) + " holds " + std::to_string(a.size()) + " values but the shape makes " +
                       std::to_string(cells) + " cells (nx·ny·nz, x fastest)");
  std::vector<Vec3> out;
  out.reserve(cells);
  for (std::size_t i = 0; i < cells; ++i)
    out.push_back(tripleAt(a[i], source, std::string(key) + "[" + std::to_string(i) + "]", limit));
  return out;
}

// Trilinear over the grid, the position clamped to the grid's box (outside: the nearest cell's).
Vec3 interpolate(const FieldDistortion& f, const std::vector<Vec3>& values, const Vec3& p) {
  std::array<int, 3> i0{};
  std::array<double, 3> w{};
  for (std::size_t a = 0; a < 3; ++a) {
    const int n = f.shape[a];
    const double u = std::clamp((p[a] - f.originMm[a]) / f.spacingMm, 0.0, static_cast<double>(n - 1));
    i0[a] = std::min(static_cast<int>(std::floor(u)), n - 2);
    w[a] = u - i0[a];
  }
  const auto at = [&](int x, int y, int z) -> const Vec3& {
    return values[static_cast<std::size_t>(x + f.shape[0] * (y + f.shape[1] * z))];
  };
  Vec3 out{0, 0, 0};
  for (int dz = 0; dz < 2; ++dz)
    for (int dy = 0; dy < 2; ++dy)
      for (int dx = 0; dx < 2; ++dx) {
        const double weight = (dx ? w[0] : 1 - w[0]) * (dy ? w[1] : 1 - w[1]) * (dz ? w[2] : 1 - w[2]);
        if (weight == 0) continue;
        const Vec3& v = at(i0[0] + dx, i0[1] + dy, i0[2] + dz);
        for (std::size_t a = 0; a < 3; ++a) out[a] += weight * v[a];
      }
  return out;
}

std::string fixed(double v, int decimals) {
  char b[64];
  std::snprintf(b, sizeof b, "%.*f", decimals, v);
  std::string s = b;
  if (s == "-0" || s.find_first_not_of("-0.") == std::string::npos) return "0";  // no "-0.000"
  // Trailing zeros off: 1.250 -> 1.25, 2.000 -> 2.
  if (s.find('.') != std::string::npos) {
    s.erase(s.find_last_not_of('0') + 1);
    if (s.back() == '.') s.pop_back();
  }
  return s;
}

}  // namespace

Vec3 FieldDistortion::displacementAt(const Vec3& pMm) const {
  return interpolate(*this, displacementMm, pMm);
}

Vec3 FieldDistortion::rotationAt(const Vec3& pMm) const {
  if (rotationDeg.empty()) return {0, 0, 0};
  return interpolate(*this, rotationDeg, pMm);
}

Vec3 FieldDistortion::reportedPosition(const Vec3& truthMm) const {
  const Vec3 d = displacementAt(truthMm);
  return {truthMm[0] + d[0], truthMm[1] + d[1], truthMm[2] + d[2]};
}

Vec3 FieldDistortion::reportedOrientation(const Vec3& truthMm, const Vec3& orientationDeg) const {
  if (rotationDeg.empty()) return orientationDeg;
  const Vec3 r = rotationAt(truthMm);
  constexpr double kDeg = 3.14159265358979323846 / 180.0;
  const Eigen::Matrix3d turn = (Eigen::AngleAxisd(r[2] * kDeg, Eigen::Vector3d::UnitZ()) *
                                Eigen::AngleAxisd(r[1] * kDeg, Eigen::Vector3d::UnitY()) *
                                Eigen::AngleAxisd(r[0] * kDeg, Eigen::Vector3d::UnitX()))
                                   .toRotationMatrix();
  return eulerDegFromRotation(rotationOf(turn * matrixOf(rotationFromEulerDeg(orientationDeg))));
}

FieldDistortion parseFieldDistortion(const std::string& text, const std::string& source) {
  json doc;
  try {
    doc = json::parse(text);
  } catch (const json::exception& e) {
    refuse(source, std::string("is not JSON leafdig reads (") + e.what() + ")");
  }
  if (!doc.is_object()) refuse(source, "is not a JSON object");
  for (const auto& [key, value] : doc.items()) {
    static const char* const kKeys[] = {"format",     "units", "frame",           "origin",
                                        "spacing_mm", "shape", "displacement_mm", "rotation_deg"};
    if (std::find(std::begin(kKeys), std::end(kKeys), key) == std::end(kKeys))
      refuse(source, "has a key leafdig does not read ('" + key.substr(0, 40) + "')");
  }
  for (const char* key : {"format", "units", "frame", "origin", "spacing_mm", "shape", "displacement_mm"})
    if (!doc.contains(key)) refuse(source, std::string("lacks \"") + key + "\"");
  if (doc.at("format") != kFieldDistortionFormat)
    refuse(source, "is not a field distortion: its format is " + doc.at("format").dump().substr(0, 60) + ", not \"" +
                       kFieldDistortionFormat + "\"");
  if (doc.at("units") != "mm") refuse(source, "gives units " + doc.at("units").dump().substr(0, 20) + ": only \"mm\"");
  if (doc.at("frame") != "transmitter")
    refuse(source, "is in the frame " + doc.at("frame").dump().substr(0, 30) + ": only \"transmitter\"");
  FieldDistortion f;
  f.originMm = tripleAt(doc.at("origin"), source, "origin", 10000.0);
  f.spacingMm = numberAt(doc.at("spacing_mm"), source, "spacing_mm", 1000.0);
  if (f.spacingMm < 1.0) refuse(source, "spacing_mm is " + json(f.spacingMm).dump() + ": at least 1 mm");
  const json& shape = doc.at("shape");
  if (!shape.is_array() || shape.size() != 3) refuse(source, "shape is not three whole numbers [nx, ny, nz]");
  std::size_t cells = 1;
  for (std::size_t a = 0; a < 3; ++a) {
    if (!shape[a].is_number_integer() || shape[a].get<std::int64_t>() < 2 || shape[a].get<std::int64_t>() > 400)
      refuse(source, "shape[" + std::to_string(a) + "] is " + shape[a].dump().substr(0, 20) +
                         ": each axis has 2 to 400 grid points");
    f.shape[a] = shape[a].get<int>();
    cells *= static_cast<std::size_t>(f.shape[a]);
  }
  if (cells > kMaxFieldCells)
    refuse(source, "shape makes " + std::to_string(cells) + " cells: at most " + std::to_string(kMaxFieldCells));
  f.displacementMm = gridAt(doc, "displacement_mm", cells, source, 1000.0);
  if (doc.contains("rotation_deg")) f.rotationDeg = gridAt(doc, "rotation_deg", cells, source, 45.0);
  return f;
}

FieldDistortion readFieldDistortion(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw FieldDistortionError("cannot read the field distortion file " + path + ": check the path");
  constexpr std::size_t kMaxBytes = 256u << 20;
  std::string text;
  char buf[65536];
  while (in.read(buf, sizeof buf) || in.gcount() > 0) {
    text.append(buf, static_cast<std::size_t>(in.gcount()));
    if (text.size() > kMaxBytes) throw FieldDistortionError(path + ": larger than 256 MiB: not a field distortion");
  }
  return parseFieldDistortion(text, path);
}

std::string encodeFieldDistortion(const FieldDistortion& f) {
  std::ostringstream o;
  const auto triple = [&](const Vec3& v, int decimals) {
    o << "[" << fixed(v[0], decimals) << "," << fixed(v[1], decimals) << "," << fixed(v[2], decimals) << "]";
  };
  const auto grid = [&](const std::vector<Vec3>& values, int decimals) {
    o << "[";
    for (std::size_t i = 0; i < values.size(); ++i) {
      o << (i == 0 ? "\n  " : (i % 4 == 0 ? ",\n  " : ", "));
      triple(values[i], decimals);
    }
    o << "\n ]";
  };
  o << "{\"format\": \"" << kFieldDistortionFormat << "\", \"units\": \"mm\", \"frame\": \"transmitter\",\n";
  o << " \"origin\": ";
  triple(f.originMm, 3);
  o << ", \"spacing_mm\": " << fixed(f.spacingMm, 3) << ", \"shape\": [" << f.shape[0] << "," << f.shape[1] << ","
    << f.shape[2] << "],\n \"displacement_mm\": ";
  grid(f.displacementMm, 3);
  if (!f.rotationDeg.empty()) {
    o << ",\n \"rotation_deg\": ";
    grid(f.rotationDeg, 4);
  }
  o << "}\n";
  return o.str();
}

FieldDistortion steelBench(const SteelBenchModel& m) {
  FieldDistortion f;
  f.originMm = {-0.5 * m.spacingMm * (m.shape[0] - 1), -0.5 * m.spacingMm * (m.shape[1] - 1), 50.0 - m.belowMm};
  f.spacingMm = m.spacingMm;
  f.shape = m.shape;
  const Eigen::Vector3d image(0, 0, -2.0 * m.belowMm);  // the transmitter mirrored in the plate
  for (int z = 0; z < m.shape[2]; ++z)
    for (int y = 0; y < m.shape[1]; ++y)
      for (int x = 0; x < m.shape[0]; ++x) {
        const Eigen::Vector3d p(f.originMm[0] + x * m.spacingMm, f.originMm[1] + y * m.spacingMm,
                                f.originMm[2] + z * m.spacingMm);
        const double r = p.norm(), rImage = (p - image).norm();
        if (r < 1e-9 || p.z() <= -m.belowMm) {  // at the source, or in the plate: nothing is measured there
          f.displacementMm.push_back({0, 0, 0});
          f.rotationDeg.push_back({0, 0, 0});
          continue;
        }
        const double share = m.strength * std::pow(r / rImage, 3);
        const Eigen::Vector3d d = p * (std::pow(1.0 - share, -1.0 / 3.0) - 1.0);
        f.displacementMm.push_back({d.x(), d.y(), d.z()});
        // The tilt: about the horizontal axis across the line from the source, by share/2 rad.
        Eigen::Vector3d axis = Eigen::Vector3d::UnitZ().cross(p);
        const Eigen::Vector3d turn =
            axis.norm() < 1e-9 ? Eigen::Vector3d::Zero()
                               : Eigen::Vector3d(axis.normalized() * (0.5 * share * 180.0 / 3.14159265358979323846));
        f.rotationDeg.push_back({turn.x(), turn.y(), turn.z()});
      }
  return f;
}

DistortedMotion::DistortedMotion(std::shared_ptr<const StylusMotion> inner,
                                 std::shared_ptr<const FieldDistortion> field)
    : inner_(std::move(inner)), field_(std::move(field)) {}

StylusMotion::State DistortedMotion::at(double t, std::uint64_t k) const {
  State s = inner_->at(t, k);
  const Vec3 d = field_->displacementAt(s.truthMm);
  for (std::size_t a = 0; a < 3; ++a) s.positionMm[a] += d[a];
  s.orientationDeg = field_->reportedOrientation(s.truthMm, s.orientationDeg);
  return s;
}

}  // namespace leafdig::devices::sim
