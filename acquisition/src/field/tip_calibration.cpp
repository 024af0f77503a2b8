#include "leafdig/acquisition/field/tip_calibration.hpp"

#include <cmath>
#include <cstdio>
#include <sstream>
#include <stdexcept>

#include "field/numbers.hpp"
#include "field/stored_record.hpp"
#include "leafdig/devices/pose.hpp"
#include "leafdig/devices/rotation_eigen.hpp"
#include "leafdig/model/errors.hpp"

namespace leafdig::acquisition {

using nlohmann::json;

namespace {

std::string point(const Eigen::Vector3d& p) {
  return "(" + detail::fixed(p.x(), 1) + ", " + detail::fixed(p.y(), 1) + ", " + detail::fixed(p.z(), 1) + ")";
}

json vec(const Eigen::Vector3d& v) {
  return json::array({v.x(), v.y(), v.z()});
}

// Three finite numbers within `limit`, or nothing.
std::optional<Vec3> threeNumbers(const json& j, double limit) {
  if (!j.is_array() || j.size() != 3) return std::nullopt;
  Vec3 v{};
  for (std::size_t a = 0; a < 3; ++a) {
    if (!j[a].is_number()) return std::nullopt;
    v[a] = j[a].get<double>();
    if (!(std::abs(v[a]) <= limit)) return std::nullopt;
  }
  return v;
}

}  // namespace

TipResult fitTip(const std::vector<TipSample>& samples, double toleranceMm) {
  if (!(toleranceMm > 0 && toleranceMm <= 20))
    throw model::InputError("a tip calibration's tolerance is a number of millimetres from 0 to 20, e.g. 1");
  std::vector<model::PivotSample> pivot;
  pivot.reserve(samples.size());
  for (const TipSample& s : samples) {
    model::PivotSample p;
    p.rotation = devices::matrixOf(devices::rotationFromEulerDeg(s.orientationDeg));
    p.positionMm = Eigen::Vector3d(s.positionMm[0], s.positionMm[1], s.positionMm[2]);
    pivot.push_back(p);
  }
  TipResult r;
  r.fit = model::fitPivot(pivot);
  if (!(r.fit.tipMm.norm() <= kMaxTipOffsetMm))
    throw model::InputError("the tip came out " + detail::fixed(r.fit.tipMm.norm(), 0) +
                            " mm from the sensor, more than " + detail::fixed(kMaxTipOffsetMm, 0) +
                            " mm: keep the tip in one divot while pivoting (the samples do not share a point)");
  r.toleranceMm = toleranceMm;
  r.verdict = r.fit.rmsMm <= toleranceMm ? "pass" : "fail";
  return r;
}

std::string encodeTipCalibration(const std::vector<TipSample>& samples, const TipResult& r, const std::string& device) {
  json ss = json::array();
  for (const TipSample& s : samples)
    ss.push_back({{"position_mm", s.positionMm}, {"orientation_deg", s.orientationDeg}, {"raw", s.raw}});
  const json doc = {{"format", kTipCalibrationFormat},
                    {"device", device},
                    {"tolerance_mm", r.toleranceMm},
                    {"samples", ss},
                    {"tip_mm", vec(r.fit.tipMm)},
                    {"pivot_mm", vec(r.fit.pivotMm)},
                    {"rms_mm", r.fit.rmsMm},
                    {"max_mm", r.fit.maxMm},
                    {"rejected", r.fit.rejected},
                    {"tilt_spread_deg", r.fit.tiltSpreadDeg},
                    {"verdict", r.verdict}};
  return doc.dump();
}

TipCalibration readTipCalibration(const db::CalibrationRow& row) {
  const detail::StoredRecord record(row, "tip calibration", kTipCalibrationFormat, "calibrate again");
  const json& doc = record.doc();
  const auto fail = [&](const std::string& what) { record.fail(what); };
  TipCalibration c;
  detail::copyHeader(row, c);
  c.hash = row.hash;
  if (doc.value("device", "") != c.device) fail("its record names another device than its row");
  const json tol = doc.value("tolerance_mm", json());
  if (!tol.is_number() || !(tol.get<double>() > 0 && tol.get<double>() <= 20))
    fail("its tolerance is not a number of millimetres from 0 to 20");
  const json ss = doc.value("samples", json());
  if (!ss.is_array() || ss.size() > kMaxTipSamples) fail("its samples are not a list of at most 2000");
  for (std::size_t i = 0; i < ss.size(); ++i) {
    const json& s = ss[i];
    if (!s.is_object() || !s.value("raw", json()).is_string())
      fail("sample " + std::to_string(i + 1) + " has no record");
    const auto p = threeNumbers(s.value("position_mm", json()), 10'000);
    const auto o = threeNumbers(s.value("orientation_deg", json()), 360);
    if (!p || !o) fail("sample " + std::to_string(i + 1) + " is not a position within 10 m and three angles");
    c.samples.push_back({*p, *o, s["raw"].get<std::string>()});
  }
  try {
    c.result = fitTip(c.samples, tol.get<double>());
  } catch (const model::InputError& e) {
    fail(std::string("its samples give no tip (") + e.what() + ")");
  }
  // What it says must be what its samples give.
  const auto tip = threeNumbers(doc.value("tip_mm", json()), kMaxTipOffsetMm);
  if (!tip || !detail::sameNumber((*tip)[0], c.result.fit.tipMm.x()) ||
      !detail::sameNumber((*tip)[1], c.result.fit.tipMm.y()) || !detail::sameNumber((*tip)[2], c.result.fit.tipMm.z()))
    fail("its tip is not what its samples give " + point(c.result.fit.tipMm));
  if (!doc.value("rms_mm", json()).is_number() || !detail::sameNumber(doc["rms_mm"].get<double>(), c.result.fit.rmsMm))
    fail("its RMS is not what its samples give (" + detail::fixed(c.result.fit.rmsMm, 3) + " mm)");
  if (doc.value("verdict", "") != c.result.verdict || row.verdict != c.result.verdict)
    fail("its verdict is not what its samples give (" + c.result.verdict + ")");
  return c;
}

std::vector<TipCalibration> tipCalibrations(const db::Store& store) {
  std::vector<TipCalibration> out;
  for (const db::CalibrationRow& row : store.tipCalibrations()) out.push_back(readTipCalibration(row));
  return out;
}

std::string tipCalibrationSummaryJson(const TipCalibration& c) {
  const model::PivotFit& f = c.result.fit;
  return json{{"calibration_id", c.id},
              {"created_utc", c.createdUtc},
              {"station", c.station},
              {"operator", c.operatorName},
              {"device", c.device},
              {"samples", f.samples},
              {"rejected", f.rejected.size()},
              {"tip_mm", vec(f.tipMm)},
              {"pivot_mm", vec(f.pivotMm)},
              {"rms_mm", f.rmsMm},
              {"max_mm", f.maxMm},
              {"tilt_spread_deg", f.tiltSpreadDeg},
              {"tolerance_mm", c.result.toleranceMm},
              {"verdict", c.result.verdict}}
      .dump();
}

std::string tipCalibrationSummaryText(const TipCalibration& c) {
  const model::PivotFit& f = c.result.fit;
  std::ostringstream out;
  out << "tip calibration " << c.id << " (" << c.createdUtc << ", " << c.device << ", by " << c.operatorName << ")\n"
      << "  tip: " << point(f.tipMm) << " mm in the sensor's frame, " << detail::fixed(f.tipMm.norm(), 1)
      << " mm from it\n"
      << "  " << f.samples << " samples, " << f.rejected.size() << " left out by the 3σ rule, tilted over "
      << detail::fixed(f.tiltSpreadDeg, 0) << "°\n"
      << "  residual: RMS " << detail::fixed(f.rmsMm) << " mm, largest " << detail::fixed(f.maxMm) << " mm; tolerance "
      << detail::fixed(c.result.toleranceMm) << " mm RMS\n"
      << "  verdict: " << c.result.verdict
      << (c.result.verdict == "pass" ? " — captures with this digitizer use this tip"
                                     : " — not used: seat the tip firmly in the divot and pivot again")
      << "\n";
  return out.str();
}

std::string TipApplied::words() const {
  return "tip calibration " + std::to_string(id) + " of " + createdUtc.substr(0, 16) + "Z: tip at " +
         point(Eigen::Vector3d(tipMm[0], tipMm[1], tipMm[2])) + " mm, " + detail::fixed(rmsMm) + " mm RMS";
}

std::optional<TipApplied> resolveTipCalibration(const db::Store& store, const std::string& which,
                                                const std::string& device) {
  if (which == "none") return std::nullopt;
  const std::vector<TipCalibration> all = tipCalibrations(store);
  const TipCalibration* chosen = nullptr;
  if (which.empty() || which == "latest") {
    for (const TipCalibration& c : all)
      if (c.device == device && c.result.verdict == "pass") chosen = &c;
    if (!chosen) return std::nullopt;
  } else {
    const std::int64_t id = detail::calibrationNumber(which, "--tip-calibration", "calibration", "leafdig field tips");
    for (const TipCalibration& c : all)
      if (c.id == id) chosen = &c;
    if (!chosen)
      throw std::invalid_argument("there is no tip calibration " + which + " in " + store.path() +
                                  ": 'leafdig field tips' lists them");
    if (chosen->result.verdict != "pass")
      throw std::invalid_argument("tip calibration " + which + " failed (its RMS " +
                                  detail::fixed(chosen->result.fit.rmsMm) +
                                  " mm is over its tolerance): calibrate the tip again");
    if (chosen->device != device)
      throw std::invalid_argument("tip calibration " + which + " is of " + chosen->device + ", not " + device +
                                  ": a tip is its own stylus's; calibrate this one (leafdig field tip)");
  }
  TipApplied t;
  t.id = chosen->id;
  t.hash = chosen->hash;
  t.createdUtc = chosen->createdUtc;
  t.device = chosen->device;
  t.tipMm = {chosen->result.fit.tipMm.x(), chosen->result.fit.tipMm.y(), chosen->result.fit.tipMm.z()};
  t.rmsMm = chosen->result.fit.rmsMm;
  return t;
}

json tipAppliedJson(const TipApplied& t) {
  return {{"id", t.id},         {"hash", t.hash},    {"created_utc", t.createdUtc},
          {"device", t.device}, {"tip_mm", t.tipMm}, {"rms_mm", t.rmsMm}};
}

namespace {

// The tip a session's settings (or a check's record) keep, read from its entry.
std::optional<TipApplied> tipIn(const detail::SettingsEntry& e) {
  if (!e.present()) return std::nullopt;
  TipApplied t;
  t.id = e.id("a calibration's number");
  t.hash = e.text("hash", 300);
  t.createdUtc = e.text("created_utc", 300);
  t.device = e.text("device", 300);
  const auto tip = threeNumbers(e.doc().value("tip_mm", json()), kMaxTipOffsetMm);
  if (!tip) e.fail("tip_mm is not three numbers of millimetres within 500");
  t.tipMm = *tip;
  t.rmsMm = e.millimetres("rms_mm", 20);
  return t;
}

}  // namespace

std::optional<TipApplied> tipAppliedIn(const json& doc, const std::string& source) {
  return tipIn(detail::SettingsEntry(doc, source, "tip_calibration"));
}

std::optional<TipApplied> tipAppliedFromSettings(const std::string& settingsJson, const std::string& source) {
  return tipIn(detail::SettingsEntry(settingsJson, source, "tip_calibration"));
}

std::string withTip(const std::string& spec, const std::optional<TipApplied>& tip) {
  if (!tip) return spec;
  return spec + ",tip=" + detail::fixed(tip->tipMm[0], 3) + ":" + detail::fixed(tip->tipMm[1], 3) + ":" +
         detail::fixed(tip->tipMm[2], 3);
}

std::string tipDevice(const std::string& spec, bool simulated) {
  const std::size_t colon = spec.find(':');
  const std::string kind = spec.substr(0, colon);
  if (simulated) return kind + ":simulated";
  if (colon == std::string::npos) return spec;
  const std::string port = spec.substr(colon + 1);
  return kind + ":" + port.substr(0, port.find(','));
}

}  // namespace leafdig::acquisition
