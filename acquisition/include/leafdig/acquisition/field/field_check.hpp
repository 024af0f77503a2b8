// Checking the field the stylus lives in (issue 50; docs/devices.md, "Checking the field"): the
// technician touches a jig's divots in the order prompted, leafdig fits the jig rigidly, says how
// far the field bends it (RMS, the largest, which divot), chooses a correction by its error on
// divots the fit did not see, and verdicts against a tolerance. The check is kept in the station
// file (db::Store::addFieldCheck) with its jig and every press, and read back by one definition:
// a stored check's numbers and correction are recomputed from its presses and must match.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "leafdig/acquisition/field/tip_calibration.hpp"
#include "leafdig/acquisition/protocol/items.hpp"
#include "leafdig/acquisition/protocol/point_rules.hpp"
#include "leafdig/db/store.hpp"
#include "leafdig/model/field/correction.hpp"

namespace leafdig::acquisition {

inline constexpr const char* kFieldCheckFormat = "leafdig.field-check/1";
inline constexpr double kDefaultFieldToleranceMm = 1.5;
// A press farther than this from where the divot asked for should be (the jig fitted on the
// divots taken so far, from the fourth on) is refused as the wrong divot — unless the technician
// presses the same place again (within kInsistMm): a field may bend that far.
inline constexpr double kWrongDivotMm = 30.0, kInsistMm = 5.0;

// The divots taken, in the jig's order.
struct JigPress {
  Vec3 positionMm{};  // the settled press, in the digitizer's frame
  std::string raw;    // the digitizer's record at the release
  std::int64_t tNs = 0;
};

// The jig check as the technician drives it, a pure state machine as the capture engines are:
// stylus samples in, decisions out. A short press takes the divot prompted (after the press rules
// of docs/method.md: still, not a double tap, and — from the fourth divot — near where the jig
// says it is); a press held for Settings::undoPressNs takes the last divot back.
class JigCapture {
 public:
  struct Decision {
    enum class Kind { Ignored, Accepted, Rejected, Undone };
    Kind kind = Kind::Ignored;
    std::size_t index = 0;  // the divot accepted or undone (its place in the jig)
    std::string words;      // a refusal's reason; an acceptance's "A3 taken (3 of 22)"
  };
  explicit JigCapture(model::Jig jig, Settings settings = {});
  Decision onStylus(const StylusInput& sample);
  Decision undo();
  [[nodiscard]] bool done() const { return taken_.size() == jig_.points.size(); }
  [[nodiscard]] std::size_t next() const { return taken_.size(); }
  [[nodiscard]] std::string prompt() const;
  [[nodiscard]] const model::Jig& jig() const { return jig_; }
  [[nodiscard]] const std::vector<JigPress>& taken() const { return taken_; }

 private:
  [[nodiscard]] Decision reject(std::string words) const;

  model::Jig jig_;
  Settings settings_;
  StylusPress press_;
  std::vector<JigPress> taken_;
  std::int64_t lastAcceptedReleaseNs_ = 0;
  std::optional<rules::Point> refusedAt_;  // the last press refused as the wrong divot
};

struct FieldCheckResult {
  model::JigFit fit;  // the rigid fit: the field as it is
  model::CorrectionChoice correction;
  double toleranceMm = kDefaultFieldToleranceMm;
  // "pass": the field's RMS within tolerance; "correctable": not, but the chosen correction's
  // held-out RMS is; "fail": neither.
  std::string verdict;
};
[[nodiscard]] FieldCheckResult checkField(const model::Jig& jig, const std::vector<Vec3>& measuredMm,
                                          double toleranceMm);

// What a check stores (docs/devices.md: format, jig, device, tolerance_mm, presses, rms_mm,
// max_mm, worst_point, residuals_mm, verdict, correction {model, holdout_rms_mm, holdout_max_mm,
// candidates, fitted}, and tip_calibration when the presses went through one — as a session's
// settings keep it).
[[nodiscard]] std::string encodeFieldCheck(const model::Jig& jig, const std::vector<JigPress>& presses,
                                           const FieldCheckResult& result, const std::string& device,
                                           const std::optional<TipApplied>& tip = std::nullopt);

// A stored check, read back and trusted: its record parsed (model::InputError naming the check
// and the field otherwise), its fit and correction recomputed from its presses and compared with
// what it says (a record whose numbers are not its presses' is refused).
struct FieldCalibration {
  std::int64_t id = 0;
  std::string station, operatorName, device, createdUtc, verdict;
  model::Jig jig;
  std::vector<JigPress> presses;
  FieldCheckResult result;
  std::optional<TipApplied> tip;  // the stylus' tip calibration the presses went through
};
[[nodiscard]] FieldCalibration readFieldCheck(const db::FieldCheckRow& row);
// Every check of the station file, oldest first (db::StoreError when the chain does not verify).
[[nodiscard]] std::vector<FieldCalibration> fieldCalibrations(const db::Store& store);

// The check as JSON for `field check --json` and `field show --json`: {id, rms_mm, max_mm,
// worst_point, tolerance_mm, verdict, correction: {model, holdout_rms_mm, holdout_max_mm},
// calibration_id, created_utc, operator, device, jig, tip_calibration: its number or null}.
[[nodiscard]] std::string fieldCheckSummaryJson(const FieldCalibration& c);
// The same in a few lines for a person.
[[nodiscard]] std::string fieldCheckSummaryText(const FieldCalibration& c);

}  // namespace leafdig::acquisition
