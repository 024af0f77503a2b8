#include "leafdig/acquisition/run/capture_run.hpp"

#include <stdexcept>

#include "leafdig/model/leaf/markers_json.hpp"
#include "leafdig/version.hpp"
#include "protocol/rigid_map.hpp"

namespace leafdig::acquisition {
namespace {

std::string defaultLeafFile() {
  const std::string dir = samplesDir();
  return (dir.empty() ? sourceDataDir() + "/samples" : dir) + "/lower-leaf-n10.markers.json";
}

}  // namespace

void checkPotTurn(double degrees, bool simulated, bool referenceReceiver, const std::string& carrier) {
  if (degrees != 0.0 && !(simulated && referenceReceiver))
    throw std::invalid_argument("--pot-turn turns the simulated " + carrier +
                                " with the reference receiver on it: it goes with --simulate --reference-receiver "
                                "(without one, a turning " +
                                carrier + " moves the " + (carrier == "pot" ? "plant" : "leaf") + " under the stylus)");
  if (!(std::abs(degrees) <= 360.0)) throw std::invalid_argument("--pot-turn must be between -360 and 360 degrees");
}

void checkSimulationSpeed(double speed) {
  // Slower than a tenth of real time a simulated capture would take hours (1e-300: for ever).
  if (!(speed >= kMinSimulationSpeed && speed <= kMaxSimulationSpeed))
    throw std::invalid_argument("the simulation speed must be between 0.1 (ten times slower than real time) and 50");
}

CaptureRun::CaptureRun(RunRequest request, RunObserver observer) : observer_(std::move(observer)) {
  SessionSetup setup = request.setup;
  if (request.resume == 0) {
    // Everything the operator typed is checked before the store is touched.
    if (setup.simulated) {
      checkSimulationSpeed(request.simulation.speed);
      if (request.leaf && !request.leafFile.empty())
        throw std::invalid_argument("give the simulated leaf as a file or as a synthetic leaf, not both");
      if (!(request.simulation.stylusNoiseMm >= 0.0 && request.simulation.stylusNoiseMm <= 20.0))
        throw std::invalid_argument("the stylus noise must be between 0 and 20 mm");
      setup.simulatedLeaf =
          request.leaf ? *request.leaf
                       : model::readMarkersFile(request.leafFile.empty() ? defaultLeafFile() : request.leafFile);
      // The virtual technician reads the leaf area meter too: the leaf's recorded area (a
      // synthetic leaf's exact area) unless the operator typed one.
      if (!setup.measuredAreaMm2) setup.measuredAreaMm2 = setup.simulatedLeaf->leaf.measuredAreaMm2;
      // …and knows its margin, as a technician declares it in the set-up.
      if (!setup.serration) setup.serration = setup.simulatedLeaf->leaf.serration;
      if (!setup.toothDepthMm) setup.toothDepthMm = setup.simulatedLeaf->leaf.toothDepthMm;
      // A reference receiver is kept with the session: a resumed capture goes on in its frame.
      setup.digitizer = request.simulation.referenceReceiver ? "fastrak:simulated,reference=2" : "fastrak:simulated";
      setup.caliper = "sylvac:simulated";
      setup.timeScale = request.simulation.speed;
    } else {
      if (setup.digitizer.empty() || setup.caliper.empty())
        throw std::invalid_argument(
            "a capture needs a digitizer and a caliper (KIND:PORT each), or the simulated devices: see 'leafdig "
            "devices "
            "list'");
      (void)parseDigitizerSpec(setup.digitizer);
      (void)parseCaliperSpec(setup.caliper);
      setup.timeScale = 1.0;
    }
  }
  if (request.speed) checkSimulationSpeed(*request.speed);
  if (request.resume > 0 && !request.fieldCalibration.empty())
    throw std::invalid_argument(
        "a resumed session goes on through the field check it began with (sessions show "
        "says which): leave out --field-calibration");
  store_ = std::make_unique<db::Store>(request.db.empty() ? db::Store::defaultPath() : request.db);
  if (request.resume > 0 && !request.tipCalibration.empty())
    throw std::invalid_argument(
        "a resumed session goes on with the tip calibration it began with (sessions show says which): leave out "
        "--tip-calibration");
  if (request.resume == 0) {
    setup.field = resolveFieldCalibration(*store_, request.fieldCalibration);
    attachSentinels(setup.field, request.sentinels);
    setup.tip = resolveTipCalibration(*store_, request.tipCalibration, tipDevice(setup.digitizer, setup.simulated));
  }
  id_ = request.resume > 0 ? request.resume : CaptureSession::create(*store_, setup);
  session_ = std::make_unique<CaptureSession>(*store_, id_);
  setup_ = session_->setup();

  const std::string name = "session " + std::to_string(id_);
  if (request.resume > 0 && request.setup.simulated && !setup_.simulated)
    throw std::invalid_argument(name + " was captured with real devices (" + setup_.digitizer + ", " + setup_.caliper +
                                "): resume it with them, without simulation");
  timeScale_ = setup_.simulated ? request.speed.value_or(setup_.timeScale) : 1.0;

  LoopListener listener;
  listener.onFeedback = [this](const Feedback& f) {
    if (observer_.onFeedback) observer_.onFeedback(f);
  };
  listener.onSnapshot = [this](const Snapshot& s) {
    if (operator_) operator_->observe(s);
    if (observer_.onSnapshot) observer_.onSnapshot(s);
  };
  preview_ = request.preview;
  loop_ = std::make_unique<LeafCaptureLoop>(*session_, listener, timeScale_, preview_);

  std::string digitizer = request.digitizer.empty() ? setup_.digitizer : request.digitizer;
  std::string caliper = request.caliper.empty() ? setup_.caliper : request.caliper;
  if (setup_.simulated) {
    prepareSimulation(request);
    digitizer = rig_->digitizerSpec();
    caliper = rig_->caliperSpec();
  }
  // The stylus' tip, when a calibration applies: the digitizer's link turns every sample to it.
  devices_ = std::make_unique<DeviceSet>(withTip(digitizer, setup_.tip), caliper, loop_->sinks(),
                                         rig_ ? rig_->digitizerRateHz() : 0.0);
}

void CaptureRun::prepareSimulation(const RunRequest& request) {
  model::MarkerSet leaf;
  if (setup_.simulatedLeaf) {
    leaf = *setup_.simulatedLeaf;
    if (request.leaf && model::markersToJson(*request.leaf) != model::markersToJson(leaf))
      throw std::invalid_argument("session " + std::to_string(id_) +
                                  " was simulating another leaf (the session keeps its leaf): leave the synthetic "
                                  "leaf out to go on");
    if (!request.leafFile.empty() &&
        model::markersToJson(model::readMarkersFile(request.leafFile)) != model::markersToJson(leaf))
      throw std::invalid_argument("session " + std::to_string(id_) + " was simulating another leaf than " +
                                  request.leafFile + " (the session keeps its leaf): leave the leaf file out to go on");
  } else {
    // A session from before simulated leaves were recorded: the given leaf, or the sample.
    leaf = request.leaf ? *request.leaf
                        : model::readMarkersFile(request.leafFile.empty() ? defaultLeafFile() : request.leafFile);
  }
  SimulationOptions so = request.simulation;
  so.speed = timeScale_;
  if (setup_.tip) so.tipAppliedMm = setup_.tip->tipMm;
  // The session's own: with a reference receiver (fixed to the leaf's board) or without; the
  // board turns about the leaf's middle.
  so.referenceReceiver = parseDigitizerSpec(setup_.digitizer).referenceStation > 0;
  Eigen::Vector3d middle = leaf.tipMm;
  int n = 1;
  for (const auto& row : leaf.rows)
    for (const auto& p : row.pointsMm) {
      middle += p;
      ++n;
    }
  middle /= n;
  so.potCentreMm = {middle.x(), middle.y(), middle.z()};
  rig_ = std::make_unique<SimulatedRig>(so);
  operator_ = std::make_unique<VirtualOperator>(*rig_, std::move(leaf), so);
  operator_->setCommands([this](const Command& c) { loop_->command(c); });
  // A session that moved the transmitter goes on from where it was: the rig reports every
  // point as the last fitted position sees it (the inverse of that position's fit).
  const Engine& engine = session_->engine();
  if (const int positions = engine.transmitterPositions(); positions > 1) {
    rig_->moveTransmitter(detail::isometryOf(engine.positionToFirst(positions - 1)).inverse());
    operator_->transmitterMovedBefore();
  }
}

CaptureRun::~CaptureRun() {
  (void)shutdown("capture stopped");
}

void CaptureRun::start() {
  if (started_) return;
  started_ = true;
  if (session_->paused()) {
    Command c;
    c.kind = Command::Kind::Resume;
    loop_->command(c);
  }
  devices_->start();
  if (operator_) operator_->start();
  thread_ = std::thread([this] {
    last_ = loop_->run();
    finished_ = true;
  });
}

void CaptureRun::wait() {
  if (thread_.joinable()) thread_.join();
}

Snapshot CaptureRun::shutdown(const std::string& why) {
  if (shutDown_) return last_ ? *last_ : session_->snapshot(false);
  shutDown_ = true;
  loop_->stop();
  wait();
  if (operator_) operator_->stop();
  devices_->stop();
  // Every way out of a started capture that did not end it leaves the same trace: a pause
  // with its reason, so the session's log says why it stopped and a resume continues it.
  if (started_ && !session_->ended() && !session_->paused()) {
    const auto feedback = session_->pause(why, loop_->monoNs(LeafCaptureLoop::Clock::now()));
    for (const Feedback& f : feedback)
      if (observer_.onFeedback) observer_.onFeedback(f);
    if (!feedback.empty() && observer_.onSnapshot)
      observer_.onSnapshot(session_->snapshot(preview_ != PreviewDetail::None, preview_ == PreviewDetail::Meshes));
  }
  last_ = session_->snapshot(false);
  return *last_;
}

VirtualOperator::Stats CaptureRun::operatorStats() const {
  return operator_ ? operator_->stats() : VirtualOperator::Stats{};
}

}  // namespace leafdig::acquisition
