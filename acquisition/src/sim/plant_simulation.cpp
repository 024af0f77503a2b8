#include "leafdig/acquisition/sim/plant_simulation.hpp"

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <optional>
#include <random>
#include <thread>
#include <utility>

#include "leafdig/acquisition/live/device_set.hpp"
#include "leafdig/acquisition/session/session.hpp"
#include "leafdig/acquisition/sim/truth.hpp"

namespace leafdig::acquisition {

namespace {

namespace dev = leafdig::devices;
using Clock = std::chrono::steady_clock;

// What the capture thread and the technician share: the step, after every committed change
// (the technician's choices go to the loop as commands).
struct Desk {
  std::mutex mutex;
  std::condition_variable cv;
  // The session as the technician sees it, after every committed change.
  PlantStep step;
  LeafChoice choice;       // the step's node's leaf, as the session has it
  model::NodeLink link;    // where the step's node hangs, as the session has it
  int acceptedPoints = 0;  // stylus points held (the plant's and its full leaves')
  std::uint64_t version = 0;
  bool ended = false;
  bool stop = false;
};

// The virtual technician: waits for the station's answer to each action (AnswerWait), then does
// what the plant says.
class PlantTechnician {
 public:
  PlantTechnician(SimulatedRig& rig, Desk& desk, PlantCaptureLoop& loop, const model::PlantMarkers& plant,
                  const SimulationOptions& options)
      : rig_(rig),
        desk_(desk),
        loop_(loop),
        plant_(plant),
        speed_(options.speed),
        relocateAfter_(options.relocateSourceAfter),
        potTurnDeg_(options.referenceReceiver ? options.potTurnDeg : 0.0),
        rng_(options.seed + 29) {}

  void run(PlantRunStats& stats) {
    AnswerWait wait(speed_);
    while (true) {
      // A command is never lost: until the station has dealt with the last one, the state on
      // the desk is from before it, and acting on it again would say it twice (a second "end"
      // would end the plant).
      const bool commandPending = loop_.commandsTaken() < commandsSent_;
      // Nor is a press pressed twice because the station was slow to say what it made of it:
      // until the loop has taken the press's release, the desk is from before it. Only a
      // press whose release never comes (its records lost) is given up on, after 20 s.
      const bool pressPending = loop_.releasesTaken() < pressesMade_;
      PlantStep step;
      LeafChoice choice;
      model::NodeLink link;
      int points = 0;
      std::uint64_t version = 0;
      {
        std::unique_lock lock(desk_.mutex);
        desk_.cv.wait_for(lock, std::chrono::milliseconds(20), [&] { return desk_.stop; });
        if (desk_.stop || desk_.ended) return;
        step = desk_.step;
        choice = desk_.choice;
        link = desk_.link;
        points = desk_.acceptedPoints;
        version = desk_.version;
      }
      turnPot(step);
      if (commandPending) continue;
      if (pressPending && rig_.hand().idle()) {
        const auto now = Clock::now();
        if (!pendingSince_) pendingSince_ = now;
        if (now - *pendingSince_ < std::chrono::seconds(20)) continue;
        pressesMade_ = loop_.releasesTaken();  // lost: pressed again below
      }
      pendingSince_.reset();
      if (wait.due(version, rig_.hand().idle())) {
        if (relocate(step, points, stats)) continue;
        act(step, choice, link, stats);
      }
    }
  }

 private:
  void act(const PlantStep& s, const LeafChoice& current, const model::NodeLink& hangs, PlantRunStats& stats) {
    // Before a node's first point, the technician says where the node hangs (a branch begins
    // from a node of the stem, or ends: back on the stem) and how its leaf will be taken.
    if (s.what == PlantWhat::Point && s.part == 1 && s.index <= static_cast<int>(plant_.nodes.size())) {
      if (const auto place = plantPlacementTruth(plant_, s.index, hangs)) {
        if (place->relation == '+')
          send({.kind = PlantCommand::Kind::Branch, .node = place->parent});
        else
          send({.kind = PlantCommand::Kind::End});  // at a branch node's first point: the branch ends
        ++stats.choices;
        return;
      }
      const LeafChoice want = plantChoiceTruth(plant_, s.index);
      if (!(current == want)) {
        send({.kind = PlantCommand::Kind::Choose, .node = s.index, .choice = want});
        ++stats.choices;
        return;
      }
    }
    const bool reading = s.what == PlantWhat::CollarDiameter || s.what == PlantWhat::Reading ||
                         (s.what == PlantWhat::Leaf && !isStylusItem(s.leaf.what));
    if (reading) {
      rig_.caliper().hold(plantReadingTruth(plant_, s));
      rig_.caliperEmulator().pressData();
      ++stats.readings;
      return;
    }
    std::optional<Vec3> at = plantPointTruth(plant_, s);
    if (s.what == PlantWhat::Leaf && s.leaf.what == What::Marker && s.leaf.col == 1) {
      const model::MarkerSet* leaf = plantLeafTruth(plant_, s.index);
      if (leaf && s.leaf.row > static_cast<int>(leaf->rows.size())) at.reset();  // past the last row
    }
    ++stats.gestures;
    if (!at) {
      // A long press anywhere ends the landmarks, the leaf's rows or the plant.
      rig_.hand().perform({last_, 1.7, 0.3, 0.3});
      ++pressesMade_;
      return;
    }
    last_ = *at;
    rig_.hand().perform({*at, 0.35, 0.45, 0.6});
    ++pressesMade_;
  }

  void send(const PlantCommand& c) {
    loop_.command(c);
    ++commandsSent_;
  }

  // Moving the transmitter after `relocateAfter_` accepted points: the technician says so, and
  // once the station asks for the landmarks again, moves it (a seeded random pose) and takes
  // them. True when it acted.
  bool relocate(const PlantStep& s, int points, PlantRunStats& stats) {
    // A move this run did not make (found half-done after a restart: the transmitter's pose
    // went with the killed process) is undone first.
    if (s.what == PlantWhat::LandmarkAgain && !moved_ && !asked_) {
      send({.kind = PlantCommand::Kind::Undo});
      return true;
    }
    if (relocateAfter_ <= 0 || moved_) return false;
    if (asked_) {
      asked_ = false;
      if (s.what != PlantWhat::LandmarkAgain) return false;  // refused (e.g. a retake in progress): later
      moved_ = true;
      rig_.moveTransmitter(randomTransmitterMove(rng_));
      return false;  // then the first landmark again, as the station asks
    }
    const bool between =
        s.what != PlantWhat::Landmark && s.what != PlantWhat::LandmarkAgain && s.what != PlantWhat::Done;
    if (points < relocateAfter_ || !between) return false;
    send({.kind = PlantCommand::Kind::MoveTransmitter});
    asked_ = true;
    ++stats.choices;
    return true;
  }

  // The pot turns as the technician goes up the plant: by node k of n it aims at (k-1)/(n-1)
  // of the whole turn (SimulatedRig::aimPot moves it there smoothly).
  void turnPot(const PlantStep& s) {
    if (potTurnDeg_ == 0.0 || s.index <= 0) return;
    if (s.what != PlantWhat::Point && s.what != PlantWhat::Reading && s.what != PlantWhat::QuickPoint &&
        s.what != PlantWhat::Leaf)
      return;
    const int nodes = std::max<int>(2, static_cast<int>(plant_.nodes.size()));
    rig_.aimPot(potTurnDeg_ * std::min(1.0, static_cast<double>(s.index - 1) / (nodes - 1)));
  }

 public:
  // A restarted simulation whose session already fitted a move stands where it stood.
  void transmitterMovedBefore() { moved_ = true; }

 private:
  SimulatedRig& rig_;
  Desk& desk_;
  PlantCaptureLoop& loop_;
  const model::PlantMarkers& plant_;
  double speed_;
  int relocateAfter_ = 0;
  double potTurnDeg_ = 0;
  bool asked_ = false, moved_ = false;
  std::uint64_t commandsSent_ = 0, pressesMade_ = 0;
  std::optional<Clock::time_point> pendingSince_;  // a press's release awaited since (the hand done)
  std::mt19937_64 rng_;
  Vec3 last_{};
};

}  // namespace

PlantRunStats runSimulatedPlant(db::Store& store, std::int64_t id, const SimulationOptions& asked,
                                const std::function<void(const PlantFeedback&, const PlantCaptureSession&)>& onFeedback,
                                const std::atomic<bool>& stop) {
  // The engine sees device time scaled by the simulation's speed, as the leaf capture does.
  PlantCaptureLoop loop(store, id, asked.speed);
  const PlantCaptureSession& session = loop.session();
  if (!session.setup().simulatedPlant)
    throw SessionError("plant session " + std::to_string(id) +
                       " was not started as a simulation: it has no plant for the virtual technician");
  const model::PlantMarkers plant = *session.setup().simulatedPlant;
  // A session begun with the reference receiver goes on with it (its points are in its frame);
  // the pot turns about the plant's collar.
  SimulationOptions options = asked;
  options.referenceReceiver = parseDigitizerSpec(session.setup().digitizer).referenceStation > 0;
  options.potCentreMm = {plant.collarMm.x(), plant.collarMm.y(), plant.collarMm.z()};
  if (session.setup().tip) options.tipAppliedMm = session.setup().tip->tipMm;
  Desk desk;
  const bool countPoints = options.relocateSourceAfter > 0;  // only a move of the transmitter waits on them
  const auto publish = [&desk, countPoints](const PlantCaptureSession& s) {
    std::lock_guard lock(desk.mutex);
    desk.step = s.engine().step();
    desk.choice = s.engine().choiceFor(desk.step.index);
    desk.link = s.engine().link(desk.step.index);
    if (countPoints) {
      int points = 0;
      for (const PlantItem& i : s.engine().items()) points += isStylusItem(i.what);
      for (int node = 1; node <= s.engine().nodes(); ++node)
        if (const Engine* leaf = s.engine().leaf(node))
          for (const Item& i : leaf->items()) points += i.what == What::Tip || i.what == What::Marker;
      desk.acceptedPoints = points;
    }
    desk.ended = s.ended();
    ++desk.version;
    desk.cv.notify_all();
  };
  if (session.ended()) {
    publish(session);
    return {};
  }

  SimulatedRig rig(options);
  // The real drivers on the rig's pseudo-terminals: the simulated capture is the real one.
  DeviceSet devices(withTip(rig.digitizerSpec(), session.setup().tip), rig.caliperSpec(), loop.sinks(),
                    rig.digitizerRateHz());
  devices.start();
  PlantTechnician technician(rig, desk, loop, plant, options);
  // A session that moved the transmitter goes on from where it was: the rig reports every
  // point as the last fitted position sees it.
  if (session.engine().toFirst().size() > 1) {
    rig.moveTransmitter(session.engine().toFirst().back().inverse());
    technician.transmitterMovedBefore();
  }
  PlantRunStats technicianStats;
  std::thread hands([&] { technician.run(technicianStats); });
  std::atomic<bool> running{true};
  // The caller's stop flag, watched for the loop.
  std::thread watcher([&] {
    while (running) {
      if (stop) loop.stop();
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
  });
  // Whatever the loop does, the watcher and the technician's hands end before the rig goes.
  const auto finish = [&] {
    running = false;
    watcher.join();
    {
      std::lock_guard lock(desk.mutex);
      desk.stop = true;
      desk.cv.notify_all();
    }
    hands.join();
  };
  PlantRunStats stats;
  try {
    stats = loop.run({onFeedback, publish});
  } catch (...) {
    finish();
    throw;
  }
  finish();
  devices.stop();
  stats.gestures = technicianStats.gestures;
  stats.readings = technicianStats.readings;
  stats.choices = technicianStats.choices;
  return stats;
}

PlantSessionSetup simulatedPlantSetup(model::PlantMarkers plant) {
  PlantSessionSetup setup;
  setup.plant = plant.plant.empty() ? "plant" : plant.plant;
  setup.date = plant.date;
  setup.simulatedPlant = std::move(plant);
  setup.simulated = true;
  setup.digitizer = "fastrak:simulated";
  setup.caliper = "sylvac:simulated";
  return setup;
}

}  // namespace leafdig::acquisition
