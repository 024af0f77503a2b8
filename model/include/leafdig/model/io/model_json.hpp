#pragma once
// The `leafdig.model/1` document (docs/method.md §5 and data/schema/): veins as ball B-splines (radii are radii,
// thickness / 2), the blade surface, metrics. leafdig writes it; the reader exists so the
// document can be checked to round-trip and reloaded by tools.
#include <string>
#include <string_view>
#include <vector>

#include "leafdig/model/leaf/leaf_model.hpp"
#include "leafdig/model/metrics/metrics.hpp"

namespace leafdig::model {

inline constexpr const char* kModelFormat = "leafdig.model/1";

// frame: "digitizer" or "leaf" (the frame the model is already in).
[[nodiscard]] std::string modelToJson(const LeafModel& model, const std::string& frame, const LeafMetrics& metrics);

struct ModelDocument {
  std::string frame;
  std::vector<Vein> veins;
  BladeSurface blade;
  double bladeAreaMm2 = 0.0;
  double projectedAreaMm2 = 0.0;
};

// Throws InputError naming the key at fault.
[[nodiscard]] ModelDocument parseModelJson(std::string_view text, const std::string& source);

}  // namespace leafdig::model
