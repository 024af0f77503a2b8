#pragma once
// A leaf scan as JSON: one shape wherever a scan is reported (`leaf2d scan --json`, the
// `scan` of `leaf2d build --json`, the `measured_area_scan` of `model build --json`).
#include <string>

#include "leafdig/model/leaf2d/leaf_scan.hpp"

namespace leafdig::model {

// {"file", "dpi", "area_mm2", "filled_area_mm2", "holes", "holes_area_mm2", "petiole",
//  "petiole_area_mm2", "other_objects", "touches_border", "dark_background", "width_px",
//  "height_px", "threshold", "pixel_mm", "outline_points", "base_mm" ([x, y] or null)}.
[[nodiscard]] std::string scanToJson(const LeafScan& scan, const std::string& file, double dpi);

}  // namespace leafdig::model
