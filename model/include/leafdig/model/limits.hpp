#pragma once
// What a leaf, a plant and the files describing them can be: every input is checked against
// these bounds before any work is done (issue 26), so that a number at the edge of what JSON
// allows is named instead of turning into infinities in an export, and no input makes the
// cost run away. docs/decisions.md, "Bounds", says why each is where it is.
#include <cstddef>
#include <cstdint>

namespace leafdig::model {

// A coordinate, in millimetres, in any frame: a FASTRAK-class tracker reaches 1.5 m from its
// transmitter, a board or plant frame a few metres.
inline constexpr double kMaxCoordinateMm = 10'000.0;
// The span of one leaf's markers (the largest tobacco leaves are about 0.8 m long).
inline constexpr double kMaxLeafSpanMm = 3'000.0;
// A caliper reading of a vein, petiole or margin (a digital caliper reads up to 150 mm; a
// tobacco midrib is under 15 mm).
inline constexpr double kMaxThicknessMm = 100.0;
// A measured leaf area (a 3 m × 3 m leaf would be 9 m²).
inline constexpr double kMaxLeafAreaMm2 = 9e6;
// Marker rows of one leaf: a 1 m leaf with a row every millimetre. Costs are linear in rows
// (tests/bench: AreaInterval and Rebuild up to 1 000 rows).
inline constexpr std::size_t kMaxRows = 1000;
// A file a user hands us (markers, outlines, plant plans): far above any real one (a 1 000-row
// markers file is about 200 kB).
inline constexpr std::uintmax_t kMaxInputFileBytes = 64ull << 20;
// A plant plan: no number beyond a million (mm, degrees, days or degree-days); a stem's
// diameter at most 1 m; a logistic growth rate at most 1 000 per time unit.
inline constexpr double kMaxPlanNumber = 1e6;
inline constexpr double kMaxStemDiameterMm = 1'000.0;
inline constexpr double kMaxGrowthRate = 1'000.0;
// A growth state's stem shorter than this fraction of its final height has not emerged; a
// leaf shorter than this fraction of its final length is not yet visible (left out).
inline constexpr double kMinGrowthFactor = 1e-3;
// A leaf scan: pixels, and the physical size at its resolution.
inline constexpr std::uint64_t kMaxScanPixels = 400'000'000;  // 20 000 × 20 000
inline constexpr double kMaxScanSideMm = 2'000.0;
inline constexpr double kMinScanDpi = 25.0;
inline constexpr double kMaxScanDpi = 20'000.0;

}  // namespace leafdig::model
