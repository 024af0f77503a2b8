#pragma once
// A plant digitized where it stands (docs/plants.md, "The plant frame"): the frame its
// exports are in, set up from landmarks on the pot rim (or a board) and the collar, and the
// angles measured in it.
//
// The plant frame: millimetres, origin at the collar (the stem at soil level), +Z the normal
// of the landmarks' best-fitting plane on the side the stem grows to, +X towards the first
// landmark projected on that plane, +Y = Z × X. Raw digitizer samples stay in the log; the
// frame is recomputed from them, so correcting a landmark moves every point after it.
#include <Eigen/Geometry>
#include <optional>
#include <vector>

namespace leafdig::model {

// What the landmarks must be for a frame to be trusted (the limits say why in their words).
inline constexpr double kLandmarkMinApartMm = 2.0;    // two landmarks closer are one press twice
inline constexpr double kLandmarkMinSpreadMm = 20.0;  // the farthest two at least this apart
inline constexpr double kLandmarkMinOffLineMm = 5.0;  // some landmark this far off the others' line

struct PlantFrame {
  Eigen::Isometry3d fromDigitizer = Eigen::Isometry3d::Identity();  // digitizer mm → plant frame mm
  double flatnessMm = 0.0;  // RMS distance of the landmarks from their plane (a tilted pot rim is not flat)

  [[nodiscard]] Eigen::Vector3d point(const Eigen::Vector3d& digitizerMm) const { return fromDigitizer * digitizerMm; }
  [[nodiscard]] Eigen::Vector3d direction(const Eigen::Vector3d& digitizer) const {
    return fromDigitizer.linear() * digitizer;
  }
};

// The landmarks' best-fitting plane (its normal's sign is arbitrary) and their RMS distance from
// it. Throws InputError naming the landmark and what to do: fewer than three, two the same
// point, all within 20 mm, nearly on one line.
struct LandmarkPlane {
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
  double flatnessMm = 0.0;
};
[[nodiscard]] LandmarkPlane landmarkPlane(const std::vector<Eigen::Vector3d>& landmarks);

// The frame of ≥ 3 landmarks and the collar, all in the digitizer's frame. `up` says which
// side of the landmarks' plane the stem grows to (the first node minus the collar, or before
// any node the digitizer's own +Z); only its side matters. Throws InputError naming the
// landmark and what to do: fewer than three, two the same point, all within 20 mm, nearly on
// one line, the first straight above the collar, `up` in the plane.
[[nodiscard]] PlantFrame plantFrameFromLandmarks(const std::vector<Eigen::Vector3d>& landmarks,
                                                 const Eigen::Vector3d& collar, const Eigen::Vector3d& up);

// Degrees counterclockwise from +X seen from above (+Z towards the eye), in [0, 360).
[[nodiscard]] double azimuthDeg(const Eigen::Vector3d& direction);
// Degrees from +Z: 0 straight up, 90 horizontal, 180 straight down.
[[nodiscard]] double inclinationDeg(const Eigen::Vector3d& direction);
// From one leaf's azimuth to the next one's, counterclockwise, in [0, 360) (137.5° for a
// golden-angle spiral turning counterclockwise, 222.5° for one turning clockwise).
[[nodiscard]] double divergenceDeg(double fromAzimuthDeg, double toAzimuthDeg);

// A leaf measured by its base (the insertion of the blade), its tip and, for the quick
// protocol, the widest point of one margin, all in the plant frame.
struct LeafPose {
  double lengthMm = 0.0;          // base to tip
  double azimuthDeg = 0.0;        // of the base-to-tip chord
  double inclinationDeg = 0.0;    // of the chord, from +Z
  std::optional<double> widthMm;  // twice the side point's distance from the chord
  std::optional<double> rollDeg;  // the blade's width line about the chord, in (-90, 90]
};
// Throws InputError when base and tip are within 1 mm, or the side point is on the chord.
[[nodiscard]] LeafPose leafPose(const Eigen::Vector3d& base, const Eigen::Vector3d& tip,
                                const std::optional<Eigen::Vector3d>& side = std::nullopt);

}  // namespace leafdig::model
