#include "leafdig/acquisition/field/field_check.hpp"

#include <Eigen/Geometry>
#include <Eigen/SVD>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <sstream>

#include "field/numbers.hpp"
#include "field/stored_record.hpp"
#include "leafdig/acquisition/protocol/point_rules.hpp"
#include "leafdig/model/errors.hpp"

namespace leafdig::acquisition {

namespace {

using nlohmann::json;

Eigen::Vector3d eig(const Vec3& v) {
  return {v[0], v[1], v[2]};
}

// The jig's points `upTo` and the presses for them, when they fix a pose (not all on one line).
std::optional<Eigen::Isometry3d> poseSoFar(const model::Jig& jig, const std::vector<JigPress>& taken) {
  const auto n = static_cast<Eigen::Index>(taken.size());
  if (n < 3) return std::nullopt;
  Eigen::Matrix3Xd from(3, n), to(3, n);
  for (Eigen::Index i = 0; i < n; ++i) {
    from.col(i) = jig.points[static_cast<std::size_t>(i)].pointMm;
    to.col(i) = eig(taken[static_cast<std::size_t>(i)].positionMm);
  }
  const Eigen::Matrix3Xd centred = from.colwise() - from.rowwise().mean();
  const Eigen::JacobiSVD<Eigen::Matrix3Xd> svd(centred);
  if (svd.singularValues()[1] / std::sqrt(static_cast<double>(n)) < 5.0) return std::nullopt;  // on one line
  Eigen::Isometry3d pose;
  pose.matrix() = Eigen::umeyama(from, to, false);
  return pose;
}

json jigJson(const model::Jig& jig) {
  json points = json::array();
  for (const auto& p : jig.points)
    points.push_back({{"id", p.id}, {"point", {p.pointMm.x(), p.pointMm.y(), p.pointMm.z()}}});
  return {{"format", model::kJigFormat}, {"units", "mm"}, {"name", jig.name}, {"points", points}};
}

json correctionJson(const FieldCheckResult& r) {
  json candidates = json::array();
  for (const auto& c : r.correction.candidates) {
    json one = {{"model", c.model}, {"tried", c.tried}};
    if (c.tried) {
      one["holdout_rms_mm"] = c.holdoutRmsMm;
      one["holdout_max_mm"] = c.holdoutMaxMm;
    }
    candidates.push_back(one);
  }
  return {{"model", r.correction.correction.name()},
          {"holdout_rms_mm", r.correction.holdoutRmsMm},
          {"holdout_max_mm", r.correction.holdoutMaxMm},
          {"corrected_rms_mm", r.correction.corrected.rmsMm},
          {"candidates", candidates},
          {"fitted", json::parse(model::encodeCorrection(r.correction.correction))}};
}

}  // namespace

JigCapture::JigCapture(model::Jig jig, Settings settings) : jig_(std::move(jig)), settings_(settings) {}

JigCapture::Decision JigCapture::reject(std::string words) const {
  Decision d;
  d.kind = Decision::Kind::Rejected;
  d.index = taken_.size();
  d.words = std::move(words);
  return d;
}

std::string JigCapture::prompt() const {
  if (done()) return "every divot is taken";
  const model::JigPoint& p = jig_.points[taken_.size()];
  return "touch divot " + p.id + " (" + std::to_string(taken_.size() + 1) + " of " +
         std::to_string(jig_.points.size()) + ") and press; a long press takes the last one back";
}

JigCapture::Decision JigCapture::undo() {
  if (taken_.empty()) return reject("no divot is taken yet: nothing to undo");
  taken_.pop_back();
  Decision d;
  d.kind = Decision::Kind::Undone;
  d.index = taken_.size();
  d.words = jig_.points[d.index].id + " taken back";
  return d;
}

JigCapture::Decision JigCapture::onStylus(const StylusInput& s) {
  const auto end = press_.take(s, settings_);
  if (!end) return {};
  if (end->cut) return reject(cutPressWords(end->heldNs));
  if (end->heldNs >= settings_.undoPressNs) return undo();
  if (done()) return reject("every divot is taken: the check is being fitted");
  const auto window = press_.window(s.tNs, settings_);
  const rules::Press press = rules::settle(window, settings_);
  if (press.refusal) return reject(*press.refusal);
  std::optional<rules::Point> previous;
  if (!taken_.empty()) previous = eig(taken_.back().positionMm);
  if (auto refusal =
          rules::doublePressNear(press.mean, previous, press_.pressedAt(), lastAcceptedReleaseNs_, settings_))
    return reject(*refusal);
  const model::JigPoint& want = jig_.points[taken_.size()];
  // The same place pressed again after a refusal as the wrong divot: the technician is sure (a
  // field bent beyond the rule's reach must still be checkable).
  const bool insisted = refusedAt_ && (press.mean - *refusedAt_).norm() <= kInsistMm;
  refusedAt_.reset();
  if (const auto pose = poseSoFar(jig_, taken_); pose && !insisted) {
    const double off = (press.mean - *pose * want.pointMm).norm();
    if (off > kWrongDivotMm) {
      refusedAt_ = press.mean;
      std::size_t nearest = 0;
      for (std::size_t i = 0; i < jig_.points.size(); ++i)
        if ((press.mean - *pose * jig_.points[i].pointMm).norm() <
            (press.mean - *pose * jig_.points[nearest].pointMm).norm())
          nearest = i;
      std::string words = "this is not divot " + want.id + ": it is " + detail::fixed(off, 0) + " mm from where " +
                          want.id + " is on the jig";
      if (nearest != taken_.size()) words += " (it is nearer " + jig_.points[nearest].id + ")";
      return reject(words + ". Touch " + want.id + " (press here again if it is " + want.id +
                    "), or take the last divot back if it was wrong");
    }
  }
  taken_.push_back({{press.mean.x(), press.mean.y(), press.mean.z()}, window.back()->raw, s.tNs});
  lastAcceptedReleaseNs_ = s.tNs;
  Decision d;
  d.kind = Decision::Kind::Accepted;
  d.index = taken_.size() - 1;
  d.words = want.id + " taken (" + std::to_string(taken_.size()) + " of " + std::to_string(jig_.points.size()) + ")";
  return d;
}

FieldCheckResult checkField(const model::Jig& jig, const std::vector<Vec3>& measured, double toleranceMm) {
  std::vector<Eigen::Vector3d> points;
  points.reserve(measured.size());
  for (const Vec3& v : measured) points.push_back(eig(v));
  FieldCheckResult r;
  r.toleranceMm = toleranceMm;
  r.fit = model::fitJig(jig, points);
  r.correction = model::chooseCorrection(jig, points);
  r.verdict = r.fit.rmsMm <= toleranceMm ? "pass" : r.correction.holdoutRmsMm <= toleranceMm ? "correctable" : "fail";
  return r;
}

std::string encodeFieldCheck(const model::Jig& jig, const std::vector<JigPress>& presses, const FieldCheckResult& r,
                             const std::string& device, const std::optional<TipApplied>& tip) {
  json ps = json::array();
  for (std::size_t i = 0; i < presses.size(); ++i) {
    const Vec3& p = presses[i].positionMm;
    ps.push_back(
        {{"id", jig.points[i].id}, {"point", {p[0], p[1], p[2]}}, {"raw", presses[i].raw}, {"t_ns", presses[i].tNs}});
  }
  json residuals = json::array();
  for (const auto& v : r.fit.residualsMm) residuals.push_back({v.x(), v.y(), v.z()});
  json doc = {{"format", kFieldCheckFormat},
              {"device", device},
              {"jig", jigJson(jig)},
              {"tolerance_mm", r.toleranceMm},
              {"presses", ps},
              {"rms_mm", r.fit.rmsMm},
              {"max_mm", r.fit.maxMm},
              {"worst_point", r.fit.worstId},
              {"residuals_mm", residuals},
              {"verdict", r.verdict},
              {"correction", correctionJson(r)}};
  if (tip) doc["tip_calibration"] = tipAppliedJson(*tip);
  return doc.dump();
}

FieldCalibration readFieldCheck(const db::FieldCheckRow& row) {
  const detail::StoredRecord record(row, "field check", kFieldCheckFormat, "run a new check");
  const std::string& source = record.source();
  const json& doc = record.doc();
  const auto fail = [&](const std::string& what) { record.fail(what); };
  FieldCalibration c;
  detail::copyHeader(row, c);
  if (!doc.contains("jig") || !doc.contains("presses") || !doc["presses"].is_array())
    fail("its record has no jig or presses");
  c.jig = model::parseJig(doc["jig"].dump(), source + " (its jig)");
  const json& ps = doc["presses"];
  if (ps.size() != c.jig.points.size()) fail("it holds a press for some divots only");
  const json tol = doc.value("tolerance_mm", json());
  if (!tol.is_number() || !(tol.get<double>() > 0 && tol.get<double>() <= 100))
    fail("its tolerance is not a number of millimetres from 0 to 100");
  std::vector<Vec3> points;
  for (std::size_t i = 0; i < ps.size(); ++i) {
    const json& p = ps[i];
    if (!p.is_object() || p.value("id", "") != c.jig.points[i].id || !p.contains("point") || !p["point"].is_array() ||
        p["point"].size() != 3 || !p.value("raw", json()).is_string() || !p.value("t_ns", json()).is_number_integer())
      fail("press " + std::to_string(i + 1) + " is not {id of divot " + c.jig.points[i].id + ", point, raw, t_ns}");
    Vec3 v{};
    for (std::size_t a = 0; a < 3; ++a) {
      if (!p["point"][a].is_number() || !(std::abs(p["point"][a].get<double>()) <= 10'000))
        fail("press " + std::to_string(i + 1) + "'s point is not within 10 m");
      v[a] = p["point"][a].get<double>();
    }
    c.presses.push_back({v, p["raw"].get<std::string>(), p["t_ns"].get<std::int64_t>()});
    points.push_back(v);
  }
  c.result = checkField(c.jig, points, tol.get<double>());
  c.tip = tipAppliedIn(doc, source);
  // What it says must be what its presses give.
  const json said = doc.value("correction", json::object());
  if (doc.value("verdict", "") != c.result.verdict || row.verdict != c.result.verdict)
    fail("its verdict is not what its presses give (" + c.result.verdict + ")");
  if (!doc.value("rms_mm", json()).is_number() || !detail::sameNumber(doc["rms_mm"].get<double>(), c.result.fit.rmsMm))
    fail("its RMS is not what its presses give (" + detail::fixed(c.result.fit.rmsMm, 3) + " mm)");
  if (!said.is_object() || said.value("model", "") != c.result.correction.correction.name() ||
      !said.value("holdout_rms_mm", json()).is_number() ||
      !detail::sameNumber(said["holdout_rms_mm"].get<double>(), c.result.correction.holdoutRmsMm))
    fail("its correction is not what its presses give (" + c.result.correction.correction.name() + ")");
  return c;
}

std::vector<FieldCalibration> fieldCalibrations(const db::Store& store) {
  std::vector<FieldCalibration> out;
  for (const db::FieldCheckRow& row : store.fieldChecks()) out.push_back(readFieldCheck(row));
  return out;
}

std::string fieldCheckSummaryJson(const FieldCalibration& c) {
  const FieldCheckResult& r = c.result;
  const json doc = {{"calibration_id", c.id},
                    {"created_utc", c.createdUtc},
                    {"station", c.station},
                    {"operator", c.operatorName},
                    {"device", c.device},
                    {"jig", c.jig.name},
                    {"points", c.jig.points.size()},
                    {"rms_mm", r.fit.rmsMm},
                    {"max_mm", r.fit.maxMm},
                    {"worst_point", r.fit.worstId},
                    {"tolerance_mm", r.toleranceMm},
                    {"verdict", r.verdict},
                    {"correction",
                     {{"model", r.correction.correction.name()},
                      {"holdout_rms_mm", r.correction.holdoutRmsMm},
                      {"holdout_max_mm", r.correction.holdoutMaxMm}}},
                    {"tip_calibration", c.tip ? json(c.tip->id) : json()}};
  return doc.dump();
}

std::string fieldCheckSummaryText(const FieldCalibration& c) {
  const FieldCheckResult& r = c.result;
  std::ostringstream out;
  out << "field check " << c.id << " (" << c.createdUtc << ", " << c.device << ", by " << c.operatorName << ")\n"
      << "  jig: " << c.jig.name << ", " << c.jig.points.size() << " divots\n"
      << "  stylus tip: " << (c.tip ? c.tip->words() : std::string("none (the sensor's own point)")) << "\n"
      << "  the field: RMS " << detail::fixed(r.fit.rmsMm) << " mm, largest " << detail::fixed(r.fit.maxMm) << " mm at "
      << r.fit.worstId << "; tolerance " << detail::fixed(r.toleranceMm) << " mm RMS\n"
      << "  correction: " << r.correction.correction.name();
  if (r.correction.correction.degree > 0)
    out << ", on divots it did not see RMS " << detail::fixed(r.correction.holdoutRmsMm) << " mm, largest "
        << detail::fixed(r.correction.holdoutMaxMm) << " mm (none: RMS "
        << detail::fixed(r.correction.candidates[0].holdoutRmsMm) << " mm)";
  else
    out << " (no polynomial did better on divots it did not see)";
  out << "\n  verdict: " << r.verdict;
  if (r.verdict == "pass") out << " — the field is within tolerance";
  if (r.verdict == "correctable") out << " — beyond tolerance, within it once corrected";
  if (r.verdict == "fail")
    out << " — beyond tolerance even corrected: move metal away from the working volume (docs/devices.md)";
  out << "\n";
  return out.str();
}

}  // namespace leafdig::acquisition
