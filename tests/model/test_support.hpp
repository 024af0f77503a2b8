#pragma once
// Shared fixtures of the model tests.
#include <unistd.h>

#include <filesystem>
#include <string>

#include "leafdig/model/leaf/markers.hpp"
#include "leafdig/model/leaf/markers_json.hpp"

namespace leafdig::model::test {

inline std::string samplePath(const std::string& name) {
  return std::string(LEAFDIG_SOURCE_DIR) + "/data/samples/" + name;
}

inline MarkerSet sample(const std::string& name) {
  return readMarkersFile(samplePath(name));
}

// An empty directory of this process's own under the system's temporary folder.
inline std::filesystem::path freshDir(const std::string& name) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("leafdig-test-" + name + "-" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

inline const char* const kSampleFiles[] = {"lower-leaf-n10.markers.json", "upper-small-leaf-n17.markers.json",
                                           "upper-curved-leaf-n14.markers.json"};

// A flat triangular leaf in z = 0: row k (1..n) has markers at x = (3 - l) a k, y = -k h.
// Its interpolating blade is the exact bilinear triangle of area 3 a h n^2.
inline MarkerSet flatTriangleLeaf(int n, double a, double h) {
  MarkerSet m;
  m.tipMm = Eigen::Vector3d::Zero();
  m.edgeThicknessMm = 0.3;
  for (int k = 1; k <= n; ++k) {
    MarkerRow row;
    for (int l = 0; l < kMarkersPerRow; ++l) row.pointsMm[l] = {(3 - l) * a * k, -k * h, 0.0};
    row.midribThicknessMm = 2.0;
    row.veinOriginThicknessMm = 1.0;
    m.rows.push_back(row);
  }
  return m;
}

}  // namespace leafdig::model::test
