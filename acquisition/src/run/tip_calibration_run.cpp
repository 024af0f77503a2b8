#include "leafdig/acquisition/run/tip_calibration_run.hpp"

#include <atomic>
#include <chrono>
#include <stdexcept>
#include <thread>

#include "leafdig/acquisition/live/device_set.hpp"
#include "leafdig/acquisition/session/session_log.hpp"
#include "leafdig/devices/links/links.hpp"
#include "leafdig/devices/pose.hpp"
#include "leafdig/model/errors.hpp"

namespace leafdig::acquisition {

namespace dev = leafdig::devices;

// The virtual technician of a simulated calibration: seats the tip in the divot and pivots the
// stylus, button held; pivots again when asked (a pivot the station refused).
class TipCalibrationRun::Technician {
 public:
  Technician(SimulatedRig& rig, const TipCalibrationRequest& r) : rig_(rig), r_(r) {}
  void pivot() { rig_.hand().perform({r_.divotMm, r_.pivotSeconds, 0.45, 0.7, r_.pivotDeg}); }

 private:
  SimulatedRig& rig_;
  const TipCalibrationRequest& r_;
};

TipCalibrationRun::TipCalibrationRun(TipCalibrationRequest request, TipCalibrationListener listener)
    : request_(std::move(request)),
      listener_(std::move(listener)),
      inputs_(request_.simulated ? request_.simulation.speed : 1.0) {
  if (request_.who.empty())
    throw std::invalid_argument("a tip calibration is signed by the technician who makes it: give a name");
  if (!(request_.toleranceMm > 0 && request_.toleranceMm <= 20))
    throw std::invalid_argument("--tolerance-mm is the RMS a tip may leave, from 0 to 20 mm (default 1)");
  if (request_.station.empty()) request_.station = thisStation();
  if (!request_.simulated) {
    const dev::DigitizerConfig c = parseDigitizerSpec(request_.digitizer);  // refused before anything opens
    if (c.tipOffsetMm)
      throw std::invalid_argument("--digitizer " + request_.digitizer +
                                  ": a tip calibration reads the sensor as the digitizer reports it; leave out tip=");
    if (c.kind == dev::DigitizerKind::MicroScribe)
      throw std::invalid_argument(
          "a MicroScribe's tip is its arm's (its tip length): a tip calibration is a "
          "FASTRAK's, Patriot's or Liberty's");
  }
  store_ = std::make_unique<db::Store>(request_.db.empty() ? db::Store::defaultPath() : request_.db);
}

TipCalibrationRun::~TipCalibrationRun() {
  if (digitizer_) digitizer_->stop();
}

void TipCalibrationRun::stop() {
  inputs_.stop();
}

std::optional<TipCalibration> TipCalibrationRun::run() {
  std::string spec = request_.digitizer;
  double rateHz = 0;
  if (request_.simulated) {
    rig_ = std::make_unique<SimulatedRig>(request_.simulation);
    spec = rig_->digitizerSpec();
    rateHz = rig_->digitizerRateHz();
    technician_ = std::make_unique<Technician>(*rig_, request_);
  }
  digitizer_ = startDigitizer(spec, rateHz, inputs_.sinks(listener_.onStatus));
  const auto prompt = [&] {
    if (listener_.onPrompt)
      listener_.onPrompt(
          "seat the stylus' tip in a divot, hold the button and pivot the stylus about ±45° each way, "
          "twice round, keeping the tip in the divot; release to fit");
  };
  prompt();
  if (technician_) technician_->pivot();
  std::vector<TipSample> pivot;
  std::optional<TipResult> result;
  bool pressed = false;
  while (!result && !inputs_.stopped()) {
    for (const auto& in : inputs_.take(std::chrono::milliseconds(100))) {
      const auto* e = std::get_if<dev::DeviceEvent>(&in);
      const auto* s = e ? std::get_if<dev::StylusSample>(e) : nullptr;
      if (!s || s->station != 1) continue;
      if (s->button && s->status == "ok" && !s->streamBegins) {
        if (const auto pose = dev::poseOf(*s)) {
          pressed = true;
          pivot.push_back({s->positionMm, dev::eulerDegFromRotation(pose->rotation), dev::printableRaw(s->raw, true)});
        }
        continue;
      }
      if (!pressed) continue;
      // The release: at most kMaxTipSamples kept, evenly over the pivot, then fitted.
      pressed = false;
      if (pivot.size() > kMaxTipSamples) {
        std::vector<TipSample> kept;
        for (std::size_t i = 0; i < kMaxTipSamples; ++i) kept.push_back(pivot[i * pivot.size() / kMaxTipSamples]);
        pivot.swap(kept);
      }
      try {
        result = fitTip(pivot, request_.toleranceMm);
        break;
      } catch (const model::InputError& refused) {
        if (listener_.onRefused) listener_.onRefused(refused.what());
        pivot.clear();
        prompt();
        if (technician_) technician_->pivot();
      }
    }
  }
  digitizer_->stop();
  if (!result) return std::nullopt;
  const std::string device = tipDevice(spec, request_.simulated);
  const auto colon = device.find(':');
  const std::int64_t id =
      store_->addTipCalibration({request_.station, request_.who, device.substr(0, colon), device.substr(colon + 1),
                                 result->verdict, encodeTipCalibration(pivot, *result, device)});
  for (const db::CalibrationRow& row : store_->tipCalibrations())
    if (row.id == id) return readTipCalibration(row);
  throw db::StoreError(db::StoreErrorKind::Io, "the tip calibration just written is not in " + store_->path(),
                       "check the file with 'leafdig sessions verify --all'");
}

}  // namespace leafdig::acquisition
