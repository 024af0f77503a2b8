#pragma once
// Moving the transmitter during a capture (issue 29; docs/plants.md, "Moving the
// transmitter"): the technician re-digitizes landmarks taken before the move, and the rigid
// transform from the new transmitter position to the old is fitted to them by least squares
// (Kabsch's method: the SVD of the landmarks' cross-covariance, reflections excluded). A fit is
// refused, in words naming the landmark, when the landmarks cannot fix a rotation (fewer than
// three, or nearly on one line) or do not agree (RMS residual above the tolerance: one of them
// moved, or was pressed elsewhere). Fits chain: a third position maps to the first through the
// second (compose the transforms).
#include <Eigen/Geometry>
#include <optional>
#include <string>
#include <vector>

namespace leafdig::acquisition {

struct RelocationFit {
  Eigen::Isometry3d newToOld = Eigen::Isometry3d::Identity();  // new transmitter position → old
  double rmsMm = 0.0;                                          // RMS distance of the landmarks after the fit
  double worstMm = 0.0;                                        // the largest one…
  std::size_t worst = 0;                                       // …and its landmark (0-based, in the order given)
  int worstLandmark = 0;               // that landmark's number (numbers[worst]; else worst + 1)
  std::optional<std::string> refusal;  // why the fit cannot be used, in words; empty: use it
};

struct RelocationSettings {
  double toleranceMm = 1.5;  // RMS residual above this: refused
  double minSpreadMm = 5.0;  // the landmarks must stand this far off their best line
  // How the words name the landmarks, and what to do when they stand on one line: a plant's
  // landmarks around the pot, a leaf's three board points.
  std::string noun = "landmark";
  std::string lineRemedy = "take landmarks around the pot";
};

// `before[i]` and `after[i]` are landmark i digitized before and after the move (in the old
// and the new transmitter frame); at least three pairs. `numbers[i]`, when given, is what the
// words call landmark i (its number on the pot rim); else i + 1.
[[nodiscard]] RelocationFit fitRelocation(const std::vector<Eigen::Vector3d>& before,
                                          const std::vector<Eigen::Vector3d>& after,
                                          const RelocationSettings& settings = {},
                                          const std::vector<int>& numbers = {});

}  // namespace leafdig::acquisition
