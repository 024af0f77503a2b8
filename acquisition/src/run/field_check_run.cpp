#include "leafdig/acquisition/run/field_check_run.hpp"

#include <atomic>
#include <chrono>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <thread>

#include "leafdig/acquisition/field/tip_calibration.hpp"
#include "leafdig/acquisition/live/device_set.hpp"
#include "leafdig/acquisition/session/session.hpp"
#include "leafdig/db/event_store.hpp"
#include "leafdig/devices/links/links.hpp"

namespace leafdig::acquisition {

namespace dev = leafdig::devices;

Eigen::Isometry3d parseJigPose(const std::string& text) {
  std::istringstream in(text);
  double v[4] = {0, 0, 0, 0};
  char comma = 0;
  bool ok = static_cast<bool>(in >> v[0]);
  for (int i = 1; ok && i < 4; ++i) ok = (in >> comma) && comma == ',' && (in >> v[i]);
  std::string rest;
  if (!ok || (in >> rest) || !std::isfinite(v[0] + v[1] + v[2] + v[3]))
    throw std::invalid_argument(
        "--jig-pose is x,y,z,yaw_deg (mm and degrees about the vertical), e.g. "
        "-300,-500,0,15; got '" +
        text.substr(0, 60) + "'");
  for (int i = 0; i < 3; ++i)
    if (std::abs(v[i]) > 2000)
      throw std::invalid_argument("--jig-pose: the jig lies within 2000 mm of the transmitter");
  if (std::abs(v[3]) > 360) throw std::invalid_argument("--jig-pose: the yaw is -360 to 360 degrees");
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.rotate(Eigen::AngleAxisd(v[3] * M_PI / 180.0, Eigen::Vector3d::UnitZ()));
  pose.pretranslate(Eigen::Vector3d(v[0], v[1], v[2]));
  return pose;
}

// The virtual technician of a simulated check: touches the divot the station asks for where the
// jig really is, and touches it again when no answer comes (a press the digitizer lost).
class FieldCheckRun::Technician {
 public:
  Technician(SimulatedRig& rig, const model::Jig& jig, const Eigen::Isometry3d& pose, double speed)
      : rig_(rig), jig_(jig), pose_(pose), wait_(speed) {}
  ~Technician() { stop(); }
  Technician(const Technician&) = delete;
  Technician& operator=(const Technician&) = delete;
  void ask(std::size_t divot) {
    next_ = divot;
    ++version_;
  }
  void start() {
    thread_ = std::thread([this] { loop(); });
  }
  void stop() {
    stop_ = true;
    if (thread_.joinable()) thread_.join();
  }

 private:
  void loop() {
    while (!stop_) {
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
      const std::size_t divot = next_;
      if (divot >= jig_.points.size() || !wait_.due(version_, rig_.hand().idle())) continue;
      const Eigen::Vector3d at = pose_ * jig_.points[divot].pointMm;
      rig_.hand().perform({{at.x(), at.y(), at.z()}, 0.3, 0.45, 0.7});
    }
  }

  SimulatedRig& rig_;
  const model::Jig& jig_;
  Eigen::Isometry3d pose_;
  AnswerWait wait_;
  std::atomic<std::size_t> next_{0};
  std::atomic<std::uint64_t> version_{0};
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

FieldCheckRun::FieldCheckRun(FieldCheckRequest request, FieldCheckListener listener)
    : request_(std::move(request)),
      listener_(std::move(listener)),
      inputs_(request_.simulated ? request_.simulation.speed : 1.0),
      capture_(request_.jig) {
  if (request_.who.empty())
    throw std::invalid_argument("a field check is signed by the technician who makes it: give a name");
  if (request_.station.empty()) request_.station = thisStation();
  if (!request_.simulated) (void)parseDigitizerSpec(request_.digitizer);  // refused before anything opens
  store_ = std::make_unique<db::Store>(request_.db.empty() ? db::Store::defaultPath() : request_.db);
}

FieldCheckRun::~FieldCheckRun() {
  if (technician_) technician_->stop();
  if (digitizer_) digitizer_->stop();
}

void FieldCheckRun::undo() {
  inputs_.command(FieldCommand::Undo);
}

void FieldCheckRun::stop() {
  inputs_.stop();
}

bool FieldCheckRun::takeDivots() {
  spec_ = request_.digitizer;
  double rateHz = 0;
  // The divots are touched with the stylus' tip: the request's tip calibration (by default the
  // digitizer's newest that passed) applies, as it does in a capture, and the check keeps it.
  tip_ = resolveTipCalibration(*store_, request_.tipCalibration,
                               tipDevice(request_.simulated ? "fastrak" : spec_, request_.simulated));
  if (request_.simulated) {
    if (tip_) request_.simulation.tipAppliedMm = tip_->tipMm;
    rig_ = std::make_unique<SimulatedRig>(request_.simulation);
    spec_ = rig_->digitizerSpec();
    rateHz = rig_->digitizerRateHz();
    technician_ = std::make_unique<Technician>(*rig_, request_.jig, request_.jigPose, request_.simulation.speed);
  }
  digitizer_ = startDigitizer(withTip(spec_, tip_), rateHz, inputs_.sinks(listener_.onStatus));
  const auto tell = [&](const JigCapture::Decision& d) {
    if (d.kind == JigCapture::Decision::Kind::Ignored) return;
    if (listener_.onDecision) listener_.onDecision(d);
    if (listener_.onPrompt && !capture_.done()) listener_.onPrompt(capture_.prompt());
    if (technician_) technician_->ask(capture_.next());
  };
  if (listener_.onPrompt) listener_.onPrompt(capture_.prompt());
  if (technician_) technician_->start();
  while (!capture_.done() && !inputs_.stopped()) {
    for (const auto& in : inputs_.take(std::chrono::milliseconds(100))) {
      if (std::holds_alternative<FieldCommand>(in)) {
        tell(capture_.undo());
      } else if (const auto* e = std::get_if<dev::DeviceEvent>(&in)) {
        if (const auto* s = std::get_if<dev::StylusSample>(e)) tell(capture_.onStylus(inputs_.stylusInput(*s)));
      }
      if (capture_.done()) break;
    }
  }
  if (technician_) technician_->stop();
  digitizer_->stop();
  return capture_.done();
}

std::optional<FieldSentinels> FieldCheckRun::runSentinels(const FieldCalibration& check) {
  // Through the tip the check's presses went through, whatever the capture's: like with like.
  request_.tipCalibration = check.tip ? std::to_string(check.tip->id) : "none";
  if (!takeDivots()) return std::nullopt;
  return compareSentinels(check, request_.jig, capture_.taken(), db::utcNow());
}

std::optional<FieldCalibration> FieldCheckRun::run() {
  if (!takeDivots()) return std::nullopt;
  std::vector<Vec3> points;
  for (const JigPress& p : capture_.taken()) points.push_back(p.positionMm);
  const FieldCheckResult result = checkField(request_.jig, points, request_.toleranceMm);
  const auto colon = spec_.find(':');
  const std::string kind = spec_.substr(0, colon);
  // A simulation's pseudo-terminal is a new path each run: it is recorded as "simulated".
  const std::string port = request_.simulated ? "simulated" : spec_.substr(colon + 1);
  const std::int64_t id =
      store_->addFieldCheck({request_.station, request_.who, kind, port, result.verdict,
                             encodeFieldCheck(request_.jig, capture_.taken(), result, kind + ":" + port, tip_)});
  for (const db::FieldCheckRow& row : store_->fieldChecks())
    if (row.id == id) return readFieldCheck(row);
  throw db::StoreError(db::StoreErrorKind::Io, "the field check just written is not in " + store_->path(),
                       "check the file with 'leafdig sessions verify --all'");
}

}  // namespace leafdig::acquisition
