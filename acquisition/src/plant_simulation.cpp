#include "leafdig/acquisition/plant_simulation.hpp"

#include <chrono>
#include <condition_variable>
#include <deque>
#include <mutex>
#include <thread>
#include <utility>
#include <variant>

#include "leafdig/acquisition/device_set.hpp"
#include "leafdig/acquisition/session.hpp"
#include "leafdig/acquisition/truth.hpp"
#include "leafdig/devices/links/driver.hpp"
#include "leafdig/devices/links/links.hpp"

namespace leafdig::acquisition {

namespace {

namespace dev = leafdig::devices;
using Clock = std::chrono::steady_clock;

struct Choice {
  int node = 0;
  LeafChoice choice;
};
using Input = std::variant<dev::DeviceEvent, Choice>;

// What the capture thread and the technician share: inputs one way, the step the other.
struct Desk {
  std::mutex mutex;
  std::condition_variable cv;
  std::deque<Input> inputs;
  // The session as the technician sees it, after every committed change.
  PlantStep step;
  LeafChoice choice;  // the step's node's leaf, as the session has it
  std::uint64_t version = 0;
  bool ended = false;
  bool stop = false;
};

// The virtual technician: waits for the station's answer to each action (AnswerWait), then does
// what the plant says.
class PlantTechnician {
 public:
  PlantTechnician(SimulatedRig& rig, Desk& desk, const model::PlantMarkers& plant, double speed)
      : rig_(rig), desk_(desk), plant_(plant), speed_(speed) {}

  void run(PlantRunStats& stats) {
    AnswerWait wait(speed_);
    while (true) {
      PlantStep step;
      LeafChoice choice;
      std::uint64_t version = 0;
      {
        std::unique_lock lock(desk_.mutex);
        desk_.cv.wait_for(lock, std::chrono::milliseconds(20), [&] { return desk_.stop; });
        if (desk_.stop || desk_.ended) return;
        step = desk_.step;
        choice = desk_.choice;
        version = desk_.version;
      }
      if (wait.due(version, rig_.hand().idle())) act(step, choice, stats);
    }
  }

 private:
  void act(const PlantStep& s, const LeafChoice& current, PlantRunStats& stats) {
    // Before a node's first point, the technician says how its leaf will be taken.
    if (s.what == PlantWhat::Point && s.part == 1 && s.index <= static_cast<int>(plant_.nodes.size())) {
      const LeafChoice want = plantChoiceTruth(plant_, s.index);
      if (!(current == want)) {
        std::lock_guard lock(desk_.mutex);
        desk_.inputs.emplace_back(Choice{s.index, want});
        desk_.cv.notify_all();
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
      return;
    }
    last_ = *at;
    rig_.hand().perform({*at, 0.35, 0.45, 0.6});
  }

  SimulatedRig& rig_;
  Desk& desk_;
  const model::PlantMarkers& plant_;
  double speed_;
  Vec3 last_{};
};

}  // namespace

PlantRunStats runSimulatedPlant(db::Store& store, std::int64_t id, const SimulationOptions& options,
                                const std::function<void(const PlantFeedback&, const PlantCaptureSession&)>& onFeedback,
                                const std::atomic<bool>& stop) {
  PlantCaptureSession session(store, id);
  if (!session.setup().simulatedPlant)
    throw SessionError("plant session " + std::to_string(id) +
                       " was not started as a simulation: it has no plant for the virtual technician");
  const model::PlantMarkers plant = *session.setup().simulatedPlant;
  PlantRunStats stats;
  Desk desk;
  const auto publish = [&] {
    std::lock_guard lock(desk.mutex);
    desk.step = session.engine().step();
    desk.choice = session.engine().choiceFor(desk.step.index);
    desk.ended = session.ended();
    ++desk.version;
    desk.cv.notify_all();
  };
  publish();
  if (session.ended()) return stats;

  SimulatedRig rig(options);
  const dev::Driver::Callbacks callbacks{[&desk](const dev::DeviceEvent& e) {
                                           std::lock_guard lock(desk.mutex);
                                           desk.inputs.emplace_back(e);
                                           desk.cv.notify_all();
                                         },
                                         [](const dev::DeviceStatus&) {}};
  dev::DigitizerConfig digitizer = parseDigitizerSpec(rig.digitizerSpec());
  digitizer.recordRateHz = rig.digitizerRateHz();
  dev::Driver stylus(dev::makeDigitizerLink(std::move(digitizer)), callbacks);
  dev::Driver caliper(dev::makeCaliperLink(parseCaliperSpec(rig.caliperSpec())), callbacks);
  stylus.start();
  caliper.start();

  PlantTechnician technician(rig, desk, plant, options.speed);
  PlantRunStats technicianStats;
  std::thread hands([&] { technician.run(technicianStats); });

  // The engine sees device time scaled by the simulation's speed, as the leaf capture does.
  const Clock::time_point t0 = Clock::now();
  const auto monoNs = [&](Clock::time_point t) {
    return static_cast<std::int64_t>(
        static_cast<double>(std::chrono::duration_cast<std::chrono::nanoseconds>(t - t0).count()) * options.speed);
  };
  while (!session.ended() && !stop) {
    std::deque<Input> batch;
    {
      std::unique_lock lock(desk.mutex);
      desk.cv.wait_for(lock, std::chrono::milliseconds(100), [&] { return !desk.inputs.empty(); });
      batch.swap(desk.inputs);
    }
    for (const Input& in : batch) {
      PlantFeedback f;
      if (const auto* c = std::get_if<Choice>(&in)) {
        f = session.chooseLeaf(c->node, c->choice, monoNs(Clock::now()));
      } else if (const auto* s = std::get_if<dev::StylusSample>(&std::get<dev::DeviceEvent>(in))) {
        f = session.onStylus({monoNs(s->deviceTime.value_or(s->t)), s->positionMm, s->button, s->status,
                              dev::printableRaw(s->raw, true)});
      } else if (const auto* r = std::get_if<dev::CaliperReading>(&std::get<dev::DeviceEvent>(in))) {
        f = session.onCaliper({monoNs(r->t), r->valueMm, dev::printableRaw(r->raw, true)});
      }
      if (f.decision.kind == PlantDecision::Kind::Ignored && !f.storeRefused) continue;
      if (f.decision.kind == PlantDecision::Kind::Rejected)
        ++stats.rejected;
      else if (f.seq > 0)
        ++stats.accepted;
      if (onFeedback) onFeedback(f, session);
      publish();
      if (session.ended()) break;
    }
  }
  {
    std::lock_guard lock(desk.mutex);
    desk.stop = true;
    desk.cv.notify_all();
  }
  hands.join();
  stylus.stop();
  caliper.stop();
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
