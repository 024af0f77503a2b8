#pragma once
// The `leafdig.markers/1` interchange format (docs/method.md §5 and data/schema/; JSON Schema in
// data/schema/leafdig.markers-1.schema.json). Unknown keys are ignored; a missing required
// key, a wrong type, an unknown unit, a non-finite number, a row without 7 points is an
// InputError naming the source, the row and point, and what to fix.
#include <filesystem>
#include <string>
#include <string_view>

#include "leafdig/model/leaf/markers.hpp"

namespace leafdig::model {

inline constexpr const char* kMarkersFormat = "leafdig.markers/1";

// `source` names the input in messages (a path, "<stdin>").
[[nodiscard]] MarkerSet parseMarkersJson(std::string_view text, const std::string& source);

// Reads and parses a file; an unreadable file is an InputError too (the user must fix it).
[[nodiscard]] MarkerSet readMarkersFile(const std::filesystem::path& path);

// Serialises in millimetres, thickness as diameters; numbers in shortest round-trip form.
[[nodiscard]] std::string markersToJson(const MarkerSet& markers);

}  // namespace leafdig::model
