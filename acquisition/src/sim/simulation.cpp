#include "leafdig/acquisition/sim/simulation.hpp"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <mutex>
#include <stdexcept>

#include "leafdig/acquisition/sim/truth.hpp"
#include "leafdig/devices/pose.hpp"
#include "leafdig/devices/rotation_eigen.hpp"

namespace leafdig::acquisition {
namespace {

namespace sim = leafdig::devices::sim;

}  // namespace

// ---- simulated rig --------------------------------------------------------------------------
namespace {

constexpr double kRad = 3.14159265358979323846 / 180.0;

Eigen::Vector3d vec(const Vec3& v) {
  return {v[0], v[1], v[2]};
}
Vec3 arr(const Eigen::Vector3d& v) {
  return {v.x(), v.y(), v.z()};
}
using devices::matrixOf;
using devices::rotationOf;

// A motion state moved rigidly: position, truth and the receiver's angles.
void moveState(sim::StylusMotion::State& s, const Eigen::Isometry3d& pose) {
  s.positionMm = arr(pose * vec(s.positionMm));
  s.truthMm = arr(pose * vec(s.truthMm));
  if (pose.linear().isIdentity(0.0)) return;  // angles exactly as the hand holds them
  s.orientationDeg = devices::eulerDegFromRotation(
      rotationOf(pose.linear() * matrixOf(devices::rotationFromEulerDeg(s.orientationDeg))));
}

}  // namespace

// The pot's angle at emulator time t: towards the latest aim at a bounded rate, from where it
// was when the aim changed. Both receivers ask with the same t in one output cycle, so they
// see one pot.
class PotTurn {
 public:
  explicit PotTurn(double degPerS) : rate_(degPerS) {}
  void aim(double deg) {
    std::lock_guard lock(mutex_);
    aim_ = deg;
  }
  [[nodiscard]] double at(double t) const {
    std::lock_guard lock(mutex_);
    if (aim_ != target_) {
      from_ = value(t);
      fromT_ = t;
      target_ = aim_;
    }
    return value(t);
  }

 private:
  [[nodiscard]] double value(double t) const {
    const double d = target_ - from_, step = rate_ * std::max(0.0, t - fromT_);
    return std::abs(d) <= step ? target_ : from_ + std::copysign(step, d);
  }
  double rate_;
  mutable std::mutex mutex_;
  double aim_ = 0;
  mutable double target_ = 0, from_ = 0, fromT_ = 0;
};

namespace {

// A motion on the turning pot: turned about the vertical through the pot's centre.
class OnPot final : public sim::StylusMotion {
 public:
  OnPot(std::shared_ptr<const sim::StylusMotion> motion, std::shared_ptr<const PotTurn> pot, const Vec3& centre)
      : motion_(std::move(motion)), pot_(std::move(pot)), centre_(vec(centre)) {}
  [[nodiscard]] State at(double t, std::uint64_t k) const override {
    State s = motion_->at(t, k);
    const Eigen::Isometry3d turn = Eigen::Translation3d(centre_) *
                                   Eigen::AngleAxisd(pot_->at(t) * kRad, Eigen::Vector3d::UnitZ()) *
                                   Eigen::Translation3d(-centre_);
    moveState(s, turn);
    return s;
  }

 private:
  std::shared_ptr<const sim::StylusMotion> motion_;
  std::shared_ptr<const PotTurn> pot_;
  Eigen::Vector3d centre_;
};

// The reference receiver where it is fixed on the pot (before the pot turns): on the rim,
// below and to one side of the stem, at an angle of its own so that every axis counts.
class FixedReceiver final : public sim::StylusMotion {
 public:
  explicit FixedReceiver(const Eigen::Isometry3d& pose) {
    state_.positionMm = state_.truthMm = arr(pose.translation());
    state_.orientationDeg = devices::eulerDegFromRotation(rotationOf(pose.linear()));
  }
  [[nodiscard]] State at(double, std::uint64_t) const override { return state_; }
  // Where it sits for a pot about `centre`.
  [[nodiscard]] static Eigen::Isometry3d placeFor(const Vec3& centre) {
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.linear() = matrixOf(devices::rotationFromEulerDeg({35.0, 12.0, -8.0}));
    pose.translation() = vec(centre) + Eigen::Vector3d(-110.0, -70.0, -40.0);
    return pose;
  }

 private:
  State state_;
};

}  // namespace

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
    moveState(s, pose);
    return s;
  }

 private:
  std::shared_ptr<const sim::StylusMotion> hand_;
  mutable std::mutex mutex_;
  Eigen::Isometry3d fromFirst_ = Eigen::Isometry3d::Identity();
};

void SimulatedRig::moveTransmitter(const Eigen::Isometry3d& fromFirst) {
  transmitter_->move(fromFirst);
  if (referenceTransmitter_) referenceTransmitter_->move(fromFirst);
}

void SimulatedRig::aimPot(double deg) {
  if (pot_) pot_->aim(deg);
}

Vec3 SimulatedRig::toStation(const Vec3& truthMm) const {
  return reference_ ? arr(receiver_.inverse() * vec(truthMm)) : truthMm;
}

Vec3 SimulatedRig::seen(const Vec3& truthMm) const {
  Vec3 at = toStation(truthMm);
  if (sensor_) {  // what the capture's tip leaves of the sensor's offset
    const Vec3& t = sensor_->tipMm();
    const Vec3 left =
        sensor_->turned(truthMm, {tipAppliedMm_[0] - t[0], tipAppliedMm_[1] - t[1], tipAppliedMm_[2] - t[2]});
    for (std::size_t a = 0; a < 3; ++a) at[a] += left[a];
  }
  if (!distortion_) return at;
  const Vec3 d = distortion_->displacementAt(truthMm);  // the transmitter's first frame: the hand's
  return {at[0] + d[0], at[1] + d[1], at[2] + d[2]};
}

Vec3 SimulatedRig::fromStation(const Vec3& stationMm) const {
  return reference_ ? arr(receiver_ * vec(stationMm)) : stationMm;
}

SimulatedRig::SimulatedRig(const SimulationOptions& o) : reference_(o.referenceReceiver), distortion_(o.distortion) {
  sim::StylusOptions so;
  so.seed = o.seed;
  so.sigmaMm = o.stylusNoiseMm;
  hand_ = std::make_shared<sim::OperatorHand>(so, o.speed);
  sim::CaliperOptions co;
  co.seed = o.seed + 1;
  caliper_ = std::make_shared<sim::VirtualCaliper>(std::vector<double>{1.0}, co);
  const std::string tag = std::to_string(::getpid()) + "-" + std::to_string(o.seed);
  sim::EmulatorOptions d;
  // Two receivers share the FASTRAK's 120 Hz: each reports at half of it.
  d.rateHz = std::min(120.0 * o.speed, 960.0) / (reference_ ? 2.0 : 1.0);
  digitizerRateHz_ = d.rateHz;
  d.linkPath = o.linkDir + "/leafdig-sim-fastrak-" + tag;
  d.faults = sim::FaultPlan::parse(o.digitizerFaults);
  d.faults.seed = o.seed;
  std::shared_ptr<const sim::StylusMotion> stylus = hand_, reference;
  if (reference_) {
    pot_ = std::make_shared<PotTurn>(3.0 * o.speed);
    stylus = std::make_shared<OnPot>(stylus, pot_, o.potCentreMm);
    receiver_ = FixedReceiver::placeFor(o.potCentreMm);
    referenceTransmitter_ = std::make_shared<TransmitterMotion>(
        std::make_shared<OnPot>(std::make_shared<FixedReceiver>(receiver_), pot_, o.potCentreMm));
    reference = referenceTransmitter_;
  }
  transmitter_ = std::make_shared<TransmitterMotion>(stylus);
  std::shared_ptr<const sim::StylusMotion> sensor = transmitter_;
  // The sensor where the stylus carries it, before the field bends what it reports.
  tipAppliedMm_ = o.tipAppliedMm;
  if (o.stylusTipMm != Vec3{0, 0, 0}) {
    sensor_ = std::make_shared<sim::StylusSensor>(sensor, o.stylusTipMm);
    sensor = sensor_;
  }
  if (o.distortion) {  // both receivers sit in the transmitter's bent field
    sensor = std::make_shared<sim::DistortedMotion>(sensor, o.distortion);
    if (reference) reference = std::make_shared<sim::DistortedMotion>(reference, o.distortion);
  }
  digitizer_ = sim::makeFastrak(sensor, d, reference);
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
  return "fastrak:" + digitizer_->path() + (reference_ ? ",reference=2" : "");
}
std::string SimulatedRig::caliperSpec() const {
  return "sylvac:" + gauge_->path();
}

Eigen::Isometry3d randomTransmitterMove(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> shift(-150.0, 150.0), lift(-40.0, 40.0), turn(-40.0, 40.0), tilt(-6.0, 6.0);
  constexpr double kDeg = 3.14159265358979323846 / 180.0;
  // Drawn in this order on every compiler (function arguments have none): the turn, the tilt, the
  // shift. The plant's technician drew them in an order GCC chose, so a seed's pose changed once.
  const double about = turn(rng) * kDeg, tilted = tilt(rng) * kDeg;
  const double x = shift(rng), y = shift(rng), z = lift(rng);
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() =
      (Eigen::AngleAxisd(about, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(tilted, Eigen::Vector3d::UnitX()))
          .toRotationMatrix();
  pose.translation() = Eigen::Vector3d(x, y, z);
  return pose;
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

// Moving the transmitter after `relocateSourceAfter` accepted points (tip and markers): the
// technician says so, and once the station asks for the board points again, moves it (a
// seeded random pose) and takes them; a move asked for at the station (its key) is made the
// same way. A move found half-done when this run began (after a restart: the transmitter's
// pose went with the process) is undone first.
bool VirtualOperator::relocate(const Snapshot& s) {
  if (!started_) {
    started_ = true;
    resumedInMove_ = s.step.what == What::BoardAgain;
  }
  const auto undo = [&] {
    Command c;
    c.kind = Command::Kind::Undo;
    send_(c);
    return true;
  };
  if (s.step.what == What::BoardAgain) {
    if (resumedInMove_) return send_ ? undo() : false;
    if (movedFor_ != s.step.row) {  // asked for by the technician, or by the station's key
      // A press under way when the move was asked for was taken as a board point again
      // before the transmitter moved: undone first.
      if (findItem(s.items, What::BoardAgain, s.step.row, 1) && send_) return undo();
      movedFor_ = s.step.row;
      moved_ = true;
      rig_.moveTransmitter(randomTransmitterMove(rng_));
    }
    return false;  // the board points again, as the station asks
  }
  resumedInMove_ = false;
  if (!send_) return false;
  if (options_.relocateSourceAfter <= 0 || moved_ || s.retaking) return false;
  int points = 0;
  for (const Item& i : s.items) points += i.what == What::Tip || i.what == What::Marker;
  const bool between = s.step.what == What::Tip || s.step.what == What::Marker || !isStylusItem(s.step.what);
  if (points < options_.relocateSourceAfter || !between || s.step.what == What::Done) return false;
  Command move;
  move.kind = Command::Kind::MoveTransmitter;
  send_(move);
  return true;
}

// A point is wrong more than 5 mm off its marker — or nearer another marker of its row than its
// own: a press taken for another step (on a small leaf the markers are under 5 mm apart).
bool VirtualOperator::wrongPoint(const Item& i) const {
  const double own = distanceMm(i.positionMm, rig_.seen(truth(i.what, i.row, i.col)));
  if (own > 5.0) return true;
  if (i.what != What::Marker || i.row < 1 || i.row > static_cast<int>(leaf_.rows.size())) return false;
  const int points = static_cast<int>(leaf_.rows[static_cast<std::size_t>(i.row - 1)].pointsMm.size());
  for (int c = 1; c <= points; ++c)
    if (c != i.col && distanceMm(i.positionMm, rig_.seen(truth(What::Marker, i.row, c))) < own) return true;
  return false;
}

void VirtualOperator::act(const Snapshot& s) {
  if (s.paused || s.complete || s.status != "open") return;
  if (relocate(s)) return;
  // A wrong item accepted last (a deliberate mistake, or noise): undo it with the stylus. A
  // board point taken again is in the moved transmitter's frame: the fit judges it.
  if (!s.items.empty() && s.items.back().what != What::BoardAgain) {
    const Item& last = s.items.back();
    const bool wrong = isStylusItem(last.what)
                           ? wrongPoint(last)
                           : std::abs(last.valueMm - truthThickness(last.what, last.row, last.col)) > 0.1;
    if (wrong && !s.retaking) {
      press(rig_.fromStation(last.positionMm), 3.4, 0.3, 0.2);  // a very long press: undo
      std::lock_guard lock(mutex_);
      ++stats_.wrongPointsUndone;
      return;
    }
  }
  const Step st = s.step;
  // A board on a turntable under a reference receiver: it turns as the rows go by.
  if (options_.referenceReceiver && options_.potTurnDeg != 0.0 && st.what == What::Marker) {
    const int rows = std::max<int>(2, static_cast<int>(leaf_.rows.size()));
    rig_.aimPot(options_.potTurnDeg * std::min(1.0, static_cast<double>(st.row - 1) / (rows - 1)));
  }
  if (st.what == What::BoardAgain) {
    if (st.col == 0)
      press(truth(What::Board, 0, 3), 1.7, 0.3, 0.3);  // every board point again: a long press fits the move
    else
      press(truth(What::Board, 0, st.col), 0.35);
    return;
  }
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
