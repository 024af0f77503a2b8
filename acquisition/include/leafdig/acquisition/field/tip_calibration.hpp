// The stylus' tip (issue 50; docs/devices.md, "The stylus tip"): a tip (pivot) calibration finds
// where the stylus' tip is in its sensor's frame from samples taken while it pivots in one divot
// (model::fitPivot: least squares, 3σ rejection, its tilt checked), verdicts its residual against
// a tolerance and is kept in the station file with every sample (db::Store::addTipCalibration),
// read back by one definition: a stored calibration's numbers are fitted again from its samples
// and must match. A capture applies the newest passing calibration of its digitizer (or the one
// named, or none): every stylus sample becomes p + R·t before anything else sees it, and the
// session keeps which calibration it was in its settings.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "leafdig/acquisition/protocol/items.hpp"
#include "leafdig/db/store.hpp"
#include "leafdig/model/field/pivot.hpp"

namespace leafdig::acquisition {

inline constexpr const char* kTipCalibrationFormat = "leafdig.tip-calibration/1";
// The fit's RMS over the samples kept may be this much for a tip to be used (a setting of
// `field tip`, --tolerance-mm): a FASTRAK's noise gives about 0.5 mm.
inline constexpr double kDefaultTipToleranceMm = 1.0;
// A tip further than this from its sensor is no stylus's (and no calibration's to trust).
inline constexpr double kMaxTipOffsetMm = 500.0;
// At most this many samples are kept and fitted (a pivot of several seconds at 120 Hz is a few
// hundred; beyond, every k-th is kept).
inline constexpr std::size_t kMaxTipSamples = 2000;

// One sample of the pivot: the sensor's position and orientation as the digitizer reported them.
struct TipSample {
  Vec3 positionMm{};
  Vec3 orientationDeg{};  // azimuth, elevation, roll
  std::string raw;        // the digitizer's record
};

struct TipResult {
  model::PivotFit fit;
  double toleranceMm = kDefaultTipToleranceMm;
  std::string verdict;  // "pass": the fit's RMS within tolerance; "fail" otherwise
};
// Fits the samples (model::InputError in words when they cannot give a tip).
[[nodiscard]] TipResult fitTip(const std::vector<TipSample>& samples, double toleranceMm);

// What a calibration stores: {format, device, tolerance_mm, samples: [{position_mm,
// orientation_deg, raw}], tip_mm, pivot_mm, rms_mm, max_mm, rejected, tilt_spread_deg, verdict}.
[[nodiscard]] std::string encodeTipCalibration(const std::vector<TipSample>& samples, const TipResult& result,
                                               const std::string& device);

struct TipCalibration {
  std::int64_t id = 0;
  std::string station, operatorName, device, createdUtc, verdict, hash;
  std::vector<TipSample> samples;
  TipResult result;
};
// A stored calibration, its numbers fitted again from its samples: model::InputError naming the
// calibration and what does not match.
[[nodiscard]] TipCalibration readTipCalibration(const db::CalibrationRow& row);
// Every calibration of the file, oldest first (db::StoreError when the chain does not verify).
[[nodiscard]] std::vector<TipCalibration> tipCalibrations(const db::Store& store);

// `field tip --json` and `field tips --json`: {calibration_id, created_utc, station, operator,
// device, samples, rejected, tip_mm, pivot_mm, rms_mm, max_mm, tilt_spread_deg, tolerance_mm,
// verdict}; and the same in words.
[[nodiscard]] std::string tipCalibrationSummaryJson(const TipCalibration& c);
[[nodiscard]] std::string tipCalibrationSummaryText(const TipCalibration& c);

// What a capture applies of a tip calibration: kept in the session's settings ("tip_calibration":
// {id, hash, created_utc, device, tip_mm, rms_mm}), covered by its genesis hash.
struct TipApplied {
  std::int64_t id = 0;
  std::string hash, createdUtc, device;
  Vec3 tipMm{};
  double rmsMm = 0;
  // "tip calibration 2 of 2026-11-29T10:00Z: tip at (0.0, 0.0, 120.1) mm, 0.41 mm RMS"
  [[nodiscard]] std::string words() const;
};
// "none": nothing; "latest" (or ""): the newest passing calibration of `device` ("fastrak:PORT",
// "fastrak:simulated"), nothing when it has none; a number: that calibration, refused in words
// (std::invalid_argument) when there is none of that number, it failed, or it is another
// device's. A record that does not read (model::InputError) or a chain that does not verify
// (db::StoreError) is refused as such.
[[nodiscard]] std::optional<TipApplied> resolveTipCalibration(const db::Store& store, const std::string& which,
                                                              const std::string& device);
[[nodiscard]] nlohmann::json tipAppliedJson(const TipApplied& t);
// The session's, or nothing (model::InputError naming `source` and the key when it does not read).
[[nodiscard]] std::optional<TipApplied> tipAppliedFromSettings(const std::string& settingsJson,
                                                               const std::string& source);
// The same from a document already parsed (a stored field check's record keeps its tip so).
[[nodiscard]] std::optional<TipApplied> tipAppliedIn(const nlohmann::json& doc, const std::string& source);
// The digitizer spec a capture opens: `spec` with ",tip=x:y:z" (the tip in the sensor's frame, mm)
// when a calibration applies (live/device_set.hpp's parseDigitizerSpec reads it).
[[nodiscard]] std::string withTip(const std::string& spec, const std::optional<TipApplied>& tip);
// The device a calibration or a capture names: "KIND:PORT" of a spec without its options, and
// "KIND:simulated" for a simulated one.
[[nodiscard]] std::string tipDevice(const std::string& spec, bool simulated);

}  // namespace leafdig::acquisition
