#include "leafdig/acquisition/simulation.hpp"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <mutex>
#include <stdexcept>

#include "leafdig/acquisition/truth.hpp"

namespace leafdig::acquisition {
namespace {

namespace sim = leafdig::devices::sim;

}  // namespace

// ---- simulated rig --------------------------------------------------------------------------
// The hand's motion as a transmitter reports it: the first position's frame moved by a pose
// that the virtual technician changes when it moves the transmitter.
class TransmitterMotion final : public sim::StylusMotion {
 public:
  explicit TransmitterMotion(std::shared_ptr<const sim::StylusMotion> hand) : hand_(std::move(hand)) {}
  void move(const Eigen::Isometry3d& fromFirst) {
    std::lock_guard lock(mutex_);
    fromFirst_ = fromFirst;
  }
  [[nodiscard]] State at(double t, std::uint64_t k) const override {
    State s = hand_->at(t, k);
    Eigen::Isometry3d pose;
    {
      std::lock_guard lock(mutex_);
      pose = fromFirst_;
    }
    const auto moved = [&](const Vec3& v) {
      const Eigen::Vector3d p = pose * Eigen::Vector3d(v[0], v[1], v[2]);
      return Vec3{p.x(), p.y(), p.z()};
    };
    s.positionMm = moved(s.positionMm);
    s.truthMm = moved(s.truthMm);
    return s;
  }

 private:
  std::shared_ptr<const sim::StylusMotion> hand_;
  mutable std::mutex mutex_;
  Eigen::Isometry3d fromFirst_ = Eigen::Isometry3d::Identity();
};

void SimulatedRig::moveTransmitter(const Eigen::Isometry3d& fromFirst) {
  transmitter_->move(fromFirst);
}

SimulatedRig::SimulatedRig(const SimulationOptions& o) {
  sim::StylusOptions so;
  so.seed = o.seed;
  so.sigmaMm = o.stylusNoiseMm;
  hand_ = std::make_shared<sim::OperatorHand>(so, o.speed);
  sim::CaliperOptions co;
  co.seed = o.seed + 1;
  caliper_ = std::make_shared<sim::VirtualCaliper>(std::vector<double>{1.0}, co);
  const std::string tag = std::to_string(::getpid()) + "-" + std::to_string(o.seed);
  sim::EmulatorOptions d;
  d.rateHz = std::min(120.0 * o.speed, 960.0);
  digitizerRateHz_ = d.rateHz;
  d.linkPath = o.linkDir + "/leafdig-sim-fastrak-" + tag;
  d.faults = sim::FaultPlan::parse(o.digitizerFaults);
  d.faults.seed = o.seed;
  transmitter_ = std::make_shared<TransmitterMotion>(std::shared_ptr<const sim::StylusMotion>(hand_));
  digitizer_ = sim::makeFastrak(std::shared_ptr<const sim::StylusMotion>(transmitter_), d);
  sim::EmulatorOptions g;
  g.linkPath = o.linkDir + "/leafdig-sim-sylvac-" + tag;
  g.faults = sim::FaultPlan::parse(o.caliperFaults);
  g.faults.seed = o.seed + 7;
  gauge_ = sim::makeSylvac(caliper_, g);
  digitizer_->start();
  gauge_->start();
}

SimulatedRig::~SimulatedRig() {
  if (digitizer_) digitizer_->stop();
  if (gauge_) gauge_->stop();
}

std::string SimulatedRig::digitizerSpec() const {
  return "fastrak:" + digitizer_->path();
}
std::string SimulatedRig::caliperSpec() const {
  return "sylvac:" + gauge_->path();
}

// ---- virtual operator -----------------------------------------------------------------------
VirtualOperator::VirtualOperator(SimulatedRig& rig, model::MarkerSet leaf, const SimulationOptions& o)
    : rig_(rig), leaf_(std::move(leaf)), options_(o), rng_(o.seed * 7919 + 3) {}

VirtualOperator::~VirtualOperator() {
  stop();
}

void VirtualOperator::observe(const Snapshot& s) {
  {
    std::lock_guard lock(mutex_);
    Snapshot light = s;
    light.preview.reset();  // the operator looks at the prompt, not the model
    latest_ = std::move(light);
  }
  cv_.notify_one();
}

void VirtualOperator::start() {
  thread_ = std::thread([this] { run(); });
}

void VirtualOperator::stop() {
  stop_ = true;
  cv_.notify_one();
  if (thread_.joinable()) thread_.join();
}

VirtualOperator::Stats VirtualOperator::stats() const {
  std::lock_guard lock(mutex_);
  return stats_;
}

Vec3 VirtualOperator::truth(What w, int row, int col) const {
  return leafPointTruth(leaf_, w, row, col);
}

double VirtualOperator::truthThickness(What w, int row, int col) const {
  return leafReadingTruth(leaf_, w, row, col);
}

void VirtualOperator::press(const Vec3& at, double pressS, double settleS, double travelS) {
  rig_.hand().perform({at, pressS, settleS, travelS});
  std::lock_guard lock(mutex_);
  ++stats_.gestures;
}

void VirtualOperator::measure(double mm) {
  rig_.caliper().hold(mm);
  rig_.caliperEmulator().pressData();
}

void VirtualOperator::act(const Snapshot& s) {
  if (s.paused || s.complete || s.status != "open") return;
  // A wrong item accepted last (a deliberate mistake, or noise): undo it with the stylus.
  if (!s.items.empty()) {
    const Item& last = s.items.back();
    const bool wrong = isStylusItem(last.what)
                           ? distanceMm(last.positionMm, truth(last.what, last.row, last.col)) > 5.0
                           : std::abs(last.valueMm - truthThickness(last.what, last.row, last.col)) > 0.1;
    if (wrong && !s.retaking) {
      press(last.positionMm, 3.4, 0.3, 0.2);  // a very long press: undo
      std::lock_guard lock(mutex_);
      ++stats_.wrongPointsUndone;
      return;
    }
  }
  const Step st = s.step;
  if (isStylusItem(st.what)) {
    if (st.what == What::Marker && st.row > static_cast<int>(leaf_.rows.size())) {
      press(truth(What::Marker, st.row - 1, 4), 1.7, 0.3, 0.3);  // a long press ends the rows
      std::lock_guard lock(mutex_);
      ++stats_.endRows;
      return;
    }
    if (options_.mistakes && !s.retaking) {
      if (!didDoubleTap_ && stylusAccepted_ == 3) {
        didDoubleTap_ = true;
        ++stylusAccepted_;
        const Vec3 at = truth(st.what, st.row, st.col);
        press(at, 0.35);
        press(at, 0.2, 0.1, 0.0);  // the button pressed twice on the same marker, without lifting
        std::lock_guard lock(mutex_);
        ++stats_.doubleTaps;
        return;
      }
      if (!didOutOfOrder_ && st.what == What::Marker && st.row == 2 && st.col == 3) {
        didOutOfOrder_ = true;
        press(truth(What::Marker, 2, 6), 0.35);  // skipped two markers
        std::lock_guard lock(mutex_);
        ++stats_.outOfOrder;
        return;
      }
      if (!didWrongPoint_ && st.what == What::Marker &&
          st.row == std::min<int>(3, static_cast<int>(leaf_.rows.size())) && st.col == 2) {
        didWrongPoint_ = true;
        Vec3 off = truth(What::Marker, st.row, st.col);
        off[1] += 9.0;  // a slip of the hand: accepted, then undone
        press(off, 0.35);
        return;
      }
    }
    ++stylusAccepted_;
    press(truth(st.what, st.row, st.col), 0.35);
    return;
  }
  if (st.what == What::Done) return;
  if (options_.mistakes && !didBounce_ && thicknessSteps_ == 1 && !s.retaking) {
    didBounce_ = true;
    measure(0.0);  // the jaws slipped: a zero reading
    std::lock_guard lock(mutex_);
    ++stats_.bounces;
    return;
  }
  ++thicknessSteps_;
  measure(truthThickness(st.what, st.row, st.col));
}

bool AnswerWait::due(std::uint64_t version, bool handIdle) {
  if (!handIdle) {
    idle_ = false;
    return false;
  }
  const auto now = Clock::now();
  if (!idle_) {
    idle_ = true;
    idleSince_ = now;  // the gesture has ended (a caliper reading is sent at once)
  }
  // Give the release time to reach the station, then act on what it says.
  if (now - idleSince_ < std::chrono::milliseconds(10)) return false;
  const bool answered = version != versionAtAction_;
  if (answered && awaiting_) {
    awaiting_ = false;
    slowestAnswer_ = std::max(slowestAnswer_, std::chrono::duration<double>(now - idleSince_));
  }
  if (!answered && now - idleSince_ < std::max(base_, 4 * slowestAnswer_)) return false;
  versionAtAction_ = version;
  awaiting_ = true;
  idle_ = false;
  return true;
}

void VirtualOperator::run() {
  AnswerWait wait(options_.speed);
  while (!stop_) {
    std::optional<Snapshot> snap;
    {
      std::unique_lock lock(mutex_);
      cv_.wait_for(lock, std::chrono::milliseconds(20), [&] { return stop_.load(); });
      snap = latest_;
    }
    if (stop_) break;
    if (!snap) continue;
    if (snap->complete || snap->status != "open") break;
    if (wait.due(snap->version, rig_.hand().idle())) act(*snap);
  }
}

}  // namespace leafdig::acquisition
