// A correction of a bent field (issue 50; docs/devices.md, "Checking the field"). The error metal
// puts into a magnetic tracker is static and smooth, so a low-order polynomial in the measured
// position models it (Kindratenko's survey of tracker calibration: polynomial fits beat lookup
// tables where the samples are few and scattered, as a jig's divots are). A correction maps a
// position the digitizer reports to where it is:  corrected = p + Σ c_k · m_k((p − centre) / span),
// one polynomial per axis over the monomials m_k of total degree ≤ d. Outside the box of the
// points it was fitted on the polynomial is not trusted: the position is clamped to the box to
// evaluate it (as a distortion grid's nearest cell), and `inside` says so.
//
// Which degree: chooseCorrection tries none (the rigid fit alone) and degrees 1–3 where there are
// points enough, and keeps the one whose error on points it did not see is smallest — five-fold
// cross-validation in the jig's order (fold = index mod 5: every point is held out once, a fifth
// at a time, ≥ 20 % out of each fit), the pose and the polynomial fitted again on each fold's
// rest. The held-out numbers it reports are those of that procedure, never of the final fit on
// every point.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "leafdig/model/field/jig.hpp"

namespace leafdig::model {

inline constexpr const char* kFieldCorrectionFormat = "leafdig.field-correction/1";
inline constexpr int kMaxCorrectionDegree = 3;

struct FieldCorrection {
  int degree = 0;  // 0: none (no change)
  Eigen::Vector3d centreMm = Eigen::Vector3d::Zero(), spanMm = Eigen::Vector3d::Ones();
  Eigen::Vector3d lowMm = Eigen::Vector3d::Zero(), highMm = Eigen::Vector3d::Zero();  // the box fitted in
  Eigen::Matrix3Xd coefficients;  // row per axis, column per monomial (monomials(degree) order)

  [[nodiscard]] std::string name() const;  // "none", "polynomial-1", …
  [[nodiscard]] bool inside(const Eigen::Vector3d& pMm) const;
  // Where a reported position is (itself for "none"); clamped into the box to evaluate.
  [[nodiscard]] Eigen::Vector3d apply(const Eigen::Vector3d& pMm) const;
};

// How many coefficients per axis a degree has: 1, 4, 10, 20.
[[nodiscard]] int monomialCount(int degree);
// A degree is tried when the points fitted (four fifths of them) are at least one and a half times its count.
[[nodiscard]] bool enoughPointsFor(int degree, std::size_t points);

// Fits the correction of `degree` that takes `measuredMm` to `targetMm` best (least squares, a
// tiny ridge so a poorly spread set stays finite). InputError when there are too few points.
[[nodiscard]] FieldCorrection fitCorrection(const std::vector<Eigen::Vector3d>& measuredMm,
                                            const std::vector<Eigen::Vector3d>& targetMm, int degree);

// The jig's rigid fit and a correction made together: the pose fitted on the corrected points,
// the correction on the residuals of the pose, alternately until they settle.
struct CorrectedFit {
  JigFit fit;  // of the corrected points: what remains
  FieldCorrection correction;
};
[[nodiscard]] CorrectedFit fitJigCorrected(const Jig& jig, const std::vector<Eigen::Vector3d>& measuredMm, int degree);

struct CorrectionCandidate {
  std::string model;   // "none", "polynomial-1", …
  bool tried = false;  // false: too few points for it
  double holdoutRmsMm = 0, holdoutMaxMm = 0;
};
struct CorrectionChoice {
  FieldCorrection correction;                 // the chosen model, fitted on every point
  JigFit corrected;                           // the jig's fit after it (on every point: not held out)
  double holdoutRmsMm = 0, holdoutMaxMm = 0;  // the chosen model's, on points it did not see
  std::vector<CorrectionCandidate> candidates;
};
[[nodiscard]] CorrectionChoice chooseCorrection(const Jig& jig, const std::vector<Eigen::Vector3d>& measuredMm);

// The correction as JSON (`leafdig.field-correction/1`: format, model, degree, centre_mm, span_mm,
// box_mm {low, high}, coefficients [[…x], […y], […z]]) and read back, checked as any input:
// InputError naming `source`, the field and what is wrong (a degree above 3, a coefficient count
// that does not match it, a box that is not one, numbers beyond what a field's error can be).
[[nodiscard]] std::string encodeCorrection(const FieldCorrection& c);
[[nodiscard]] FieldCorrection parseCorrection(const std::string& json, const std::string& source);

// The error map (docs/devices.md, "Checking the field"): the jig's points seen from above and
// from the side in the digitizer's frame, an arrow at each from where the jig says it is to where
// the digitizer put it (drawn `exaggeration`× — chosen so the largest is a tenth of the view),
// coloured by its length against `toleranceMm`; the title says RMS, the largest, the verdict.
struct FieldMapInput {
  const Jig* jig = nullptr;
  const JigFit* fit = nullptr;  // its residuals are the arrows
  double toleranceMm = 1.5;
  std::string verdict, title;
};
[[nodiscard]] std::string fieldErrorMapSvg(const FieldMapInput& in);

// The same figure as shapes in pixels, for a front end that paints it (the station's Field tab):
// what fieldErrorMapSvg writes, one layout for both.
struct FieldMapArrow {
  double x = 0, y = 0, tipX = 0, tipY = 0;  // from where the jig puts the divot to the exaggerated report
  std::string colour;                       // "#1a9850" within half the tolerance, "#f39c12" within it, "#d73027"
  std::string label;                        // the divot's id, or "" where ids would stand on each other
};
struct FieldMapPanel {
  double x0 = 0, y0 = 0, size = 0;
  std::string title;
  std::vector<FieldMapArrow> arrows;
};
struct FieldMapLayout {
  double width = 0, height = 0;
  std::string title, summary;  // the summary: RMS, the largest, tolerance, verdict, the arrows' factor
  std::vector<FieldMapPanel> panels;
  std::vector<std::pair<std::string, std::string>> legend;  // colour, words
  double legendY = 0, scaleBarPx = 0;                       // the scale bar is 100 mm of positions
};
[[nodiscard]] FieldMapLayout fieldErrorMapLayout(const FieldMapInput& in);

}  // namespace leafdig::model
