// A plant digitized by the virtual technician through the simulated FASTRAK and Sylvac on
// pseudo-terminals (docs/plants.md, "Simulated plant capture"): the real drivers read the
// ptys (a DeviceSet), every record goes to the PlantCaptureLoop of plant_loop.hpp on the
// calling thread — the loop real devices use — and the
// technician (a thread of its own) reads what the session asks for and moves the hand or
// closes the caliper's jaws, as `leafdig capture --simulate` does for a leaf. Shipped, not
// test-only: `leafdig plant capture --simulate` runs on it.
//
// Thread contract: runSimulatedPlant on one thread; onFeedback runs on it.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>

#include "leafdig/acquisition/live/plant_loop.hpp"
#include "leafdig/acquisition/session/plant_session.hpp"
#include "leafdig/acquisition/sim/simulation.hpp"

namespace leafdig::acquisition {

// The setup of a plant digitized by the virtual technician: the plant (its id, its date), the
// simulated FASTRAK and Sylvac, the default protocol and settings; the caller adds project,
// operator, station and what the operator chose over them.
[[nodiscard]] PlantSessionSetup simulatedPlantSetup(model::PlantMarkers plant);

// Captures (or goes on with) plant session `id`, whose settings hold the simulated plant, until
// it is complete or `stop` is set. Returns what happened; the session's status says whether the
// plant was finished. Throws SessionError when the session holds no simulated plant.
PlantRunStats runSimulatedPlant(db::Store& store, std::int64_t id, const SimulationOptions& options,
                                const std::function<void(const PlantFeedback&, const PlantCaptureSession&)>& onFeedback,
                                const std::atomic<bool>& stop);

}  // namespace leafdig::acquisition
