#include "leafdig/model/field/correction.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>

#include "json_reader.hpp"
#include "leafdig/model/errors.hpp"

namespace leafdig::model {
namespace {

using nlohmann::json;

// The exponents of every monomial of total degree ≤ d: by degree, then x's power down, y's down.
std::vector<std::array<int, 3>> monomials(int degree) {
  std::vector<std::array<int, 3>> out;
  for (int total = 0; total <= degree; ++total)
    for (int a = total; a >= 0; --a)
      for (int b = total - a; b >= 0; --b) out.push_back({a, b, total - a - b});
  return out;
}

Eigen::VectorXd basis(const Eigen::Vector3d& u, int degree) {
  const auto terms = monomials(degree);
  Eigen::VectorXd v(static_cast<Eigen::Index>(terms.size()));
  for (std::size_t k = 0; k < terms.size(); ++k)
    v[static_cast<Eigen::Index>(k)] =
        std::pow(u.x(), terms[k][0]) * std::pow(u.y(), terms[k][1]) * std::pow(u.z(), terms[k][2]);
  return v;
}

constexpr int kFolds = 5;
constexpr int kAlternations = 8;

// The residual of every point after `correction` and the pose fitted on the corrected points.
JigFit fitOf(const Jig& jig, const std::vector<Eigen::Vector3d>& measured, const FieldCorrection& c) {
  std::vector<Eigen::Vector3d> corrected;
  corrected.reserve(measured.size());
  for (const auto& p : measured) corrected.push_back(c.apply(p));
  return fitJig(jig, corrected);
}

Jig subset(const Jig& jig, const std::vector<std::size_t>& keep) {
  Jig out{jig.name, {}};
  for (std::size_t i : keep) out.points.push_back(jig.points[i]);
  return out;
}

}  // namespace

std::string FieldCorrection::name() const {
  return degree == 0 ? "none" : "polynomial-" + std::to_string(degree);
}

bool FieldCorrection::inside(const Eigen::Vector3d& p) const {
  return degree == 0 || ((p.array() >= lowMm.array()).all() && (p.array() <= highMm.array()).all());
}

Eigen::Vector3d FieldCorrection::apply(const Eigen::Vector3d& p) const {
  if (degree == 0) return p;
  const Eigen::Vector3d clamped = p.cwiseMax(lowMm).cwiseMin(highMm);
  const Eigen::Vector3d u = (clamped - centreMm).cwiseQuotient(spanMm);
  return p + coefficients * basis(u, degree);
}

int monomialCount(int degree) {
  return static_cast<int>(monomials(degree).size());
}

bool enoughPointsFor(int degree, std::size_t points) {
  const std::size_t fitted = points - (points + kFolds - 1) / kFolds;
  return points >= 4 && 2 * fitted >= 3 * static_cast<std::size_t>(monomialCount(degree));
}

FieldCorrection fitCorrection(const std::vector<Eigen::Vector3d>& measured, const std::vector<Eigen::Vector3d>& target,
                              int degree) {
  if (degree < 0 || degree > kMaxCorrectionDegree)
    throw InputError("a field correction's degree is 0 to 3, not " + std::to_string(degree));
  FieldCorrection c;
  c.degree = degree;
  if (degree == 0) return c;
  const auto n = static_cast<Eigen::Index>(measured.size());
  const int terms = monomialCount(degree);
  if (measured.size() != target.size() || n < terms)
    throw InputError("a degree-" + std::to_string(degree) + " correction needs at least " + std::to_string(terms) +
                     " points; digitize more of the jig");
  c.lowMm = c.highMm = measured.front();
  for (const auto& p : measured) {
    c.lowMm = c.lowMm.cwiseMin(p);
    c.highMm = c.highMm.cwiseMax(p);
  }
  c.centreMm = (c.lowMm + c.highMm) / 2;
  // Half the box's extent per axis, at least 1 mm (a jig is never that thin, but no division by 0).
  c.spanMm = ((c.highMm - c.lowMm) / 2).cwiseMax(Eigen::Vector3d::Ones());
  Eigen::MatrixXd a(n, terms);
  Eigen::MatrixXd b(n, 3);
  for (Eigen::Index i = 0; i < n; ++i) {
    const auto k = static_cast<std::size_t>(i);
    a.row(i) = basis((measured[k] - c.centreMm).cwiseQuotient(c.spanMm), degree).transpose();
    b.row(i) = (target[k] - measured[k]).transpose();
  }
  Eigen::MatrixXd normal = a.transpose() * a;
  normal.diagonal().array() += 1e-9 * std::max(1.0, normal.diagonal().maxCoeff());
  const Eigen::MatrixXd x = normal.ldlt().solve(a.transpose() * b);
  c.coefficients = x.transpose();
  if (!c.coefficients.allFinite())
    throw InputError("the field correction did not fit (the points are too few or too close together)");
  return c;
}

CorrectedFit fitJigCorrected(const Jig& jig, const std::vector<Eigen::Vector3d>& measured, int degree) {
  CorrectedFit out{fitJig(jig, measured), {}};
  if (degree == 0) return out;
  for (int round = 0; round < kAlternations; ++round) {
    // Where the pose (of the corrected points) puts each divot: what the correction aims at.
    std::vector<Eigen::Vector3d> target;
    for (const JigPoint& p : jig.points) target.push_back(out.fit.jigToDigitizer * p.pointMm);
    out.correction = fitCorrection(measured, target, degree);
    out.fit = fitOf(jig, measured, out.correction);
  }
  return out;
}

CorrectionChoice chooseCorrection(const Jig& jig, const std::vector<Eigen::Vector3d>& measured) {
  if (measured.size() != jig.points.size()) (void)fitJig(jig, measured);  // its refusal, in its words
  const std::size_t n = measured.size();
  CorrectionChoice choice;
  int best = -1;
  for (int degree = 0; degree <= kMaxCorrectionDegree; ++degree) {
    CorrectionCandidate cand;
    FieldCorrection named;
    named.degree = degree;
    cand.model = named.name();
    cand.tried = degree == 0 || enoughPointsFor(degree, n);
    if (cand.tried) {
      double sum = 0, worst = 0;
      for (int fold = 0; fold < kFolds; ++fold) {
        std::vector<std::size_t> in, out;
        for (std::size_t i = 0; i < n; ++i) (static_cast<int>(i % kFolds) == fold ? out : in).push_back(i);
        if (out.empty()) continue;
        std::vector<Eigen::Vector3d> fitted;
        for (std::size_t i : in) fitted.push_back(measured[i]);
        const CorrectedFit f = fitJigCorrected(subset(jig, in), fitted, degree);
        for (std::size_t i : out) {
          const Eigen::Vector3d r = f.correction.apply(measured[i]) - f.fit.jigToDigitizer * jig.points[i].pointMm;
          sum += r.squaredNorm();
          worst = std::max(worst, r.norm());
        }
      }
      cand.holdoutRmsMm = std::sqrt(sum / static_cast<double>(n));
      cand.holdoutMaxMm = worst;
      // A higher degree must do better on unseen points, not merely as well.
      if (best < 0 || cand.holdoutRmsMm < choice.candidates[static_cast<std::size_t>(best)].holdoutRmsMm * 0.97)
        best = degree;
    }
    choice.candidates.push_back(cand);
  }
  const CorrectionCandidate& chosen = choice.candidates[static_cast<std::size_t>(best)];
  choice.holdoutRmsMm = chosen.holdoutRmsMm;
  choice.holdoutMaxMm = chosen.holdoutMaxMm;
  CorrectedFit all = fitJigCorrected(jig, measured, best);
  choice.correction = std::move(all.correction);
  choice.corrected = std::move(all.fit);
  return choice;
}

std::string encodeCorrection(const FieldCorrection& c) {
  const auto vec = [](const Eigen::Vector3d& v) { return json::array({v.x(), v.y(), v.z()}); };
  json doc = {{"format", kFieldCorrectionFormat}, {"model", c.name()}, {"degree", c.degree}};
  if (c.degree > 0) {
    doc["centre_mm"] = vec(c.centreMm);
    doc["span_mm"] = vec(c.spanMm);
    doc["box_mm"] = {{"low", vec(c.lowMm)}, {"high", vec(c.highMm)}};
    json rows = json::array();
    for (Eigen::Index axis = 0; axis < 3; ++axis) {
      json row = json::array();
      for (Eigen::Index k = 0; k < c.coefficients.cols(); ++k) row.push_back(c.coefficients(axis, k));
      rows.push_back(row);
    }
    doc["coefficients"] = rows;
  }
  return detail::dumpFinite(doc);
}

FieldCorrection parseCorrection(const std::string& text, const std::string& source) {
  const detail::JsonReader r(source, kFieldCorrectionFormat);
  const json doc = detail::parseJsonLeniently(text, source);
  if (!doc.is_object()) r.fail("the correction", "is not a JSON object");
  if (r.require(doc, "format", "the correction") != kFieldCorrectionFormat)
    r.fail("format", std::string("is not \"") + kFieldCorrectionFormat + "\"");
  const json& degree = r.require(doc, "degree", "the correction");
  if (!degree.is_number_integer() || degree.get<int>() < 0 || degree.get<int>() > kMaxCorrectionDegree)
    r.fail("degree", "must be a whole number from 0 to 3");
  FieldCorrection c;
  c.degree = degree.get<int>();
  if (r.require(doc, "model", "the correction") != c.name())
    r.fail("model", "does not match the degree (expected \"" + c.name() + "\")");
  if (c.degree == 0) return c;
  c.centreMm = r.point(r.require(doc, "centre_mm", "the correction"), "centre_mm", 1.0);
  c.spanMm = r.point(r.require(doc, "span_mm", "the correction"), "span_mm", 1.0);
  if ((c.spanMm.array() < 1.0).any()) r.fail("span_mm", "every axis's span is at least 1 mm");
  const json& box = r.require(doc, "box_mm", "the correction");
  c.lowMm = r.point(r.require(box, "low", "box_mm"), "box_mm.low", 1.0);
  c.highMm = r.point(r.require(box, "high", "box_mm"), "box_mm.high", 1.0);
  if ((c.lowMm.array() > c.highMm.array()).any()) r.fail("box_mm", "low must not be above high on any axis");
  const json& rows = r.require(doc, "coefficients", "the correction");
  const int terms = monomialCount(c.degree);
  if (!rows.is_array() || rows.size() != 3)
    r.fail("coefficients", "must be three lists (x, y, z) of " + std::to_string(terms) + " numbers");
  c.coefficients.resize(3, terms);
  for (std::size_t axis = 0; axis < 3; ++axis) {
    const std::string where = "coefficients[" + std::to_string(axis) + "]";
    if (!rows[axis].is_array() || rows[axis].size() != static_cast<std::size_t>(terms))
      r.fail(where, "must hold " + std::to_string(terms) + " numbers for a degree-" + std::to_string(c.degree) +
                        " correction");
    for (int k = 0; k < terms; ++k)
      c.coefficients(static_cast<Eigen::Index>(axis), k) =
          r.bounded(rows[axis][static_cast<std::size_t>(k)], where, "a coefficient", 1.0, -1000, 1000,
                    "a field's error is within a metre");
  }
  return c;
}

}  // namespace leafdig::model
