#pragma once
// The simulated plant capture shared by `plant capture --simulate` and `demo`
// (plant_capture_cmd.cpp).
#include <cstdint>
#include <functional>

#include "leafdig/acquisition/sim/plant_simulation.hpp"

namespace leafdig::cli {

// Captures plant session `id` with the virtual technician until it is complete, Ctrl-C /
// SIGTERM, or the technician gets nowhere for `giveUpAfterS` seconds (nothing but refusals,
// or nothing at all, while not paused: the words go to stderr and *gaveUp is set); the
// session stays open then, to resume. onFeedback after every committed change.
acquisition::PlantRunStats simulatePlant(
    db::Store& store, std::int64_t id, const acquisition::SimulationOptions& options,
    const std::function<void(const acquisition::PlantFeedback&, const acquisition::PlantCaptureSession&)>& onFeedback,
    double giveUpAfterS = 180, bool* gaveUp = nullptr);

}  // namespace leafdig::cli
