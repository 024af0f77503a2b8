#include "leafdig/model/leaf/markers.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <sstream>

#include "leafdig/model/errors.hpp"
#include "leafdig/model/limits.hpp"
#include "leafdig/names/name_table.hpp"

namespace leafdig::model {

namespace {

// Consecutive markers closer than this are the same point digitized twice.
constexpr double kCoincidentMm = 1e-6;

std::string pointName(int row, int column) {
  return "row " + std::to_string(row + 1) + ", point " + std::to_string(column + 1);
}

std::string formatPoint(const Eigen::Vector3d& p) {
  std::ostringstream out;
  out << "(" << p.x() << ", " << p.y() << ", " << p.z() << ")";
  return out.str();
}

void requirePositive(const std::optional<double>& value, const std::string& where, const std::string& what) {
  if (!value) return;
  if (!std::isfinite(*value) || *value <= 0.0) {
    std::ostringstream out;
    out << where << ": " << what << " is " << *value
        << " mm; a thickness must be a positive number of millimetres. Re-measure it with the "
           "caliper or correct the file.";
    throw InputError(out.str());
  }
  if (*value > kMaxThicknessMm) {
    std::ostringstream out;
    out << where << ": " << what << " is " << *value << " mm; a caliper reading of a leaf is at most "
        << kMaxThicknessMm << " mm. Re-measure it, or check the file's units.";
    throw InputError(out.str());
  }
}

}  // namespace

const char* toString(Serration serration) {
  return nameIn(kSerrationNames, serration);
}

Serration serrationFromString(const std::string& word) {
  return parseName(kSerrationNames, word, "serration");
}

// Tooth profile in units of D at θ = n φ (docs/synthetic-leaves.md).
double toothProfile(Serration s, double theta) {
  const double sn = std::abs(std::sin(theta));
  const double cs = std::abs(std::cos(theta));
  switch (s) {
    case Serration::None: return 0.0;
    case Serration::Round: return sn;
    case Serration::Sharp: return 1.0 - cs;
    case Serration::Straight: return sn + 1.0 - cs;
    case Serration::Acuminate: return sn + (1.0 - cs) * (1.0 - cs);
  }
  return 0.0;
}

ToothSpread toothSpread(Serration s) {
  // Over one period of the profile (π), finely: the mean by the midpoint rule, the largest
  // sample (the profiles are smooth between their kinks, which fall on samples).
  constexpr int kSamples = 4096;
  ToothSpread out;
  for (int k = 0; k < kSamples; ++k) {
    const double h = toothProfile(s, 3.14159265358979323846 * (k + 0.5) / kSamples);
    out.mean += h / kSamples;
    out.max = std::max(out.max, toothProfile(s, 3.14159265358979323846 * k / kSamples));
  }
  return out;
}

const char* toString(ThicknessMode mode) {
  return nameIn(kThicknessModeNames, mode);
}

ThicknessMode thicknessModeFromString(const std::string& word) {
  return parseName(kThicknessModeNames, word, "thickness mode");
}

ThicknessMode inferThicknessMode(const MarkerSet& markers) {
  if (markers.mode) return *markers.mode;
  bool anyOrigin = false;
  bool allMeasured = !markers.rows.empty();
  for (const MarkerRow& row : markers.rows) {
    anyOrigin = anyOrigin || row.veinOriginThicknessMm.has_value();
    for (const auto& t : row.measuredThicknessMm) allMeasured = allMeasured && t.has_value();
  }
  if (allMeasured) return ThicknessMode::Full;
  if (!anyOrigin) return ThicknessMode::Small;
  return ThicknessMode::Standard;
}

LeafThickness applyThicknessRule(const MarkerSet& markers) {
  LeafThickness result{inferThicknessMode(markers), 0.0, {}};
  const ThicknessMode mode = result.mode;
  requirePositive(markers.edgeThicknessMm, "leaf", "edge_thickness (d)");
  if (mode != ThicknessMode::Full && !markers.edgeThicknessMm) {
    // Per-row readings may stand in for d everywhere except at the tip.
    bool everyRow = !markers.rows.empty();
    for (const MarkerRow& row : markers.rows) everyRow = everyRow && row.edgeThicknessMm;
    if (!everyRow) {
      throw InputError(std::string("leaf: edge_thickness (d, the margin thickness) is missing; ") + toString(mode) +
                       " mode needs it. Measure the margin with the caliper and add "
                       "\"edge_thickness\" to the leaf (or to every row).");
    }
  }

  for (std::size_t i = 0; i < markers.rows.size(); ++i) {
    const MarkerRow& row = markers.rows[i];
    const std::string where = "row " + std::to_string(i + 1);
    requirePositive(row.midribThicknessMm, where, "midrib_thickness (r_i4^1)");
    requirePositive(row.veinOriginThicknessMm, where, "vein_origin_thickness (r_i4^2)");
    requirePositive(row.edgeThicknessMm, where, "edge_thickness");
    for (int j = 0; j < kMarkersPerRow; ++j) {
      requirePositive(row.measuredThicknessMm[j], pointName(static_cast<int>(i), j), "measured thickness");
    }
    if (!row.midribThicknessMm) {
      throw InputError(where +
                       ": midrib_thickness (r_i4^1) is missing; every mode needs the "
                       "midrib thickness at the 4th marker. Measure it and add it.");
    }
    std::optional<double> origin = row.veinOriginThicknessMm;
    if (!origin) origin = row.measuredThicknessMm[kMidribColumn];
    if (mode == ThicknessMode::Small && !origin) origin = row.midribThicknessMm;
    if (!origin) {
      throw InputError(where + ": vein_origin_thickness (r_i4^2) is missing; " + toString(mode) +
                       " mode needs the lateral vein thickness at its origin. Measure it, or "
                       "declare \"mode\": \"small\" if only the midrib was measured.");
    }
    if (mode == ThicknessMode::Full) {
      for (int j = 0; j < kMarkersPerRow; ++j) {
        if (!row.measuredThicknessMm[j]) {
          throw InputError(pointName(static_cast<int>(i), j) +
                           ": thickness missing; full mode needs all 7 measured thicknesses "
                           "per row. Measure it, or use standard mode.");
        }
      }
    }
    const double d = row.edgeThicknessMm.value_or(markers.edgeThicknessMm.value_or(0.0));
    const double r2 = *origin;
    RowThickness rt{};
    rt.midribMm = *row.midribThicknessMm;
    rt.lateralMm = {d, (2 * d + r2) / 3, (d + 2 * r2) / 3, r2, (d + 2 * r2) / 3, (2 * d + r2) / 3, d};
    for (int j = 0; j < kMarkersPerRow; ++j) {
      if (row.measuredThicknessMm[j]) rt.lateralMm[j] = *row.measuredThicknessMm[j];
    }
    result.rows.push_back(rt);
  }

  if (markers.edgeThicknessMm) {
    result.tipMm = *markers.edgeThicknessMm;
  } else if (!result.rows.empty()) {
    // No leaf-wide d: the tip takes the margin thickness of the first row.
    result.tipMm = 0.5 * (result.rows.front().lateralMm[0] + result.rows.front().lateralMm[6]);
  }
  return result;
}

void validateMarkerGeometry(const MarkerSet& markers) {
  if (markers.rows.empty()) {
    throw InputError(
        "the marker set has no rows; digitize at least one row of 7 markers below "
        "the tip");
  }
  if (markers.rows.size() > kMaxRows) {
    throw InputError("the marker set has " + std::to_string(markers.rows.size()) + " rows; a leaf takes at most " +
                     std::to_string(kMaxRows) + " (a 1 m leaf with a row every millimetre)");
  }
  for (int axis = 0; axis < 3; ++axis) {
    if (!std::isfinite(markers.tipMm[axis])) {
      throw InputError("tip: coordinate " + std::string(1, "xyz"[axis]) +
                       " is not a finite number; re-digitize the tip");
    }
  }
  for (std::size_t i = 0; i < markers.rows.size(); ++i) {
    for (int j = 0; j < kMarkersPerRow; ++j) {
      for (int axis = 0; axis < 3; ++axis) {
        if (!std::isfinite(markers.rows[i].pointsMm[j][axis])) {
          throw InputError(pointName(static_cast<int>(i), j) + ": coordinate " + std::string(1, "xyz"[axis]) +
                           " is not a finite number; re-digitize this marker");
        }
      }
    }
  }
  // Within what a digitizer measures, and the size of a leaf.
  const auto bounded = [](const Eigen::Vector3d& p, const std::string& name) {
    if (p.cwiseAbs().maxCoeff() > kMaxCoordinateMm)
      throw InputError(name + " is at " + formatPoint(p) + " mm, beyond what a digitizer measures (" +
                       std::to_string(static_cast<int>(kMaxCoordinateMm / 1000)) +
                       " m from its origin); check the file's units and numbers");
  };
  bounded(markers.tipMm, "the tip");
  Eigen::Vector3d low = markers.tipMm, high = markers.tipMm;
  for (std::size_t i = 0; i < markers.rows.size(); ++i)
    for (int j = 0; j < kMarkersPerRow; ++j) {
      const Eigen::Vector3d& p = markers.rows[i].pointsMm[j];
      bounded(p, pointName(static_cast<int>(i), j));
      low = low.cwiseMin(p);
      high = high.cwiseMax(p);
    }
  if ((high - low).norm() > kMaxLeafSpanMm) {
    std::ostringstream out;
    out << "the markers span " << (high - low).norm() << " mm; one leaf spans at most " << kMaxLeafSpanMm
        << " mm. Check the file's units, or a marker far from the others";
    throw InputError(out.str());
  }
  // A blade needs breadth: markers on one line (or one point) make a leaf of no area.
  {
    Eigen::Vector3d mean = markers.tipMm;
    for (const MarkerRow& row : markers.rows)
      for (const Eigen::Vector3d& p : row.pointsMm) mean += p;
    mean /= static_cast<double>(1 + kMarkersPerRow * markers.rows.size());
    Eigen::Matrix3d scatter = (markers.tipMm - mean) * (markers.tipMm - mean).transpose();
    for (const MarkerRow& row : markers.rows)
      for (const Eigen::Vector3d& p : row.pointsMm) scatter += (p - mean) * (p - mean).transpose();
    const Eigen::Vector3d spread = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(scatter).eigenvalues();  // ascending
    const double length = std::sqrt(std::max(spread[2], 0.0));
    const double breadth = std::sqrt(std::max(spread[1], 0.0));
    if (breadth <= 1e-3 * length || breadth < 1e-3) {
      throw InputError(
          "the markers lie on one line: a leaf's rows run across its midrib and give it breadth. Re-digitize the "
          "rows (7 points each, right to left across the leaf)");
    }
    // Rows with no width: every marker on the midrib's own (curved) line, each row's points
    // strung along it instead of across it — a blade of no area, whose interval would be empty.
    // A row has width when its points reach across the midrib's direction (from the row above
    // to it) by at least a tenth of their spread; a leaf none of whose rows does is refused.
    bool anyAcross = false;
    Eigen::Vector3d above = markers.tipMm;
    for (const MarkerRow& row : markers.rows) {
      const Eigen::Vector3d mid = row.pointsMm[kMidribColumn];
      const Eigen::Vector3d along = (mid - above).norm() > 0 ? (mid - above).normalized() : Eigen::Vector3d::UnitX();
      double across = 0.0, spread = 0.0;
      for (const Eigen::Vector3d& p : row.pointsMm) {
        const Eigen::Vector3d d = p - mid;
        across = std::max(across, (d - d.dot(along) * along).norm());
        spread = std::max(spread, d.norm());
      }
      anyAcross = anyAcross || across > 0.1 * spread;
      above = mid;
    }
    if (!anyAcross) {
      throw InputError(
          "the rows have no width: every marker lies on the midrib's line, so the blade has no area. Each row "
          "runs across the leaf, right edge to left edge through the midrib: re-digitize the rows");
    }
  }
  auto checkPair = [](const Eigen::Vector3d& a, const Eigen::Vector3d& b, const std::string& nameA,
                      const std::string& nameB, const char* along) {
    if ((a - b).norm() < kCoincidentMm) {
      throw InputError(nameA + " and " + nameB + " coincide at " + formatPoint(a) + " along the " + along +
                       "; consecutive markers must be distinct. Re-digitize one of them.");
    }
  };
  const int n = static_cast<int>(markers.rows.size());
  // Along each row (the two half-laterals) and down the blade's columns (midrib, contour).
  for (int i = 0; i < n; ++i) {
    const auto& pts = markers.rows[i].pointsMm;
    for (int j = 0; j + 1 < kMarkersPerRow; ++j) {
      checkPair(pts[j], pts[j + 1], pointName(i, j), pointName(i, j + 1), "row");
    }
    for (int j = 0; j < kMarkersPerRow; ++j) {
      if (i == 0) {
        checkPair(markers.tipMm, pts[j], "the tip", pointName(i, j), j == kMidribColumn ? "midrib" : "blade column");
      } else {
        checkPair(markers.rows[i - 1].pointsMm[j], pts[j], pointName(i - 1, j), pointName(i, j),
                  j == kMidribColumn ? "midrib" : "blade column");
      }
    }
  }
}

MarginSample marginAt(const MarginFromScan& margin, double spacingMm) {
  if (margin.empty()) return {spacingMm, 0.0, 0.0};
  if (spacingMm <= margin.front().spacingMm) return margin.front();
  for (std::size_t k = 1; k < margin.size(); ++k) {
    const MarginSample& a = margin[k - 1];
    const MarginSample& b = margin[k];
    if (spacingMm <= b.spacingMm) {
      const double t = (spacingMm - a.spacingMm) / (b.spacingMm - a.spacingMm);
      return {spacingMm, a.outsideMm + t * (b.outsideMm - a.outsideMm), a.insideMm + t * (b.insideMm - a.insideMm)};
    }
  }
  return margin.back();
}

double marginSpacingMm(const MarkerSet& markers) {
  if (markers.rows.empty()) return 0.0;
  double length = 0.0;
  Eigen::Vector3d right = markers.tipMm, left = markers.tipMm;
  for (const MarkerRow& row : markers.rows) {
    length += (row.pointsMm[0] - right).norm() + (row.pointsMm[kMarkersPerRow - 1] - left).norm();
    right = row.pointsMm[0];
    left = row.pointsMm[kMarkersPerRow - 1];
  }
  return length / static_cast<double>(2 * markers.rows.size());
}

MarkerGrid markerGrid(const MarkerSet& markers) {
  MarkerGrid grid;
  grid.reserve(markers.rows.size() + 1);
  std::array<Eigen::Vector3d, kMarkersPerRow> tipRow;
  tipRow.fill(markers.tipMm);
  grid.push_back(tipRow);
  for (const MarkerRow& row : markers.rows) grid.push_back(row.pointsMm);
  return grid;
}

}  // namespace leafdig::model
