#pragma once
// Which thicknesses a capture measures (docs/method.md §2): the one enum of the marker
// file, the capture protocol and the model.
#include <string>

#include "leafdig/names/name_table.hpp"

namespace leafdig::model {

// Standard: midrib at every row, each vein's origin, one edge value; Full: every marker;
// Small: midrib only, one edge value.
enum class ThicknessMode { Standard, Full, Small };
// Its words in files, options and messages (the CLI's choices and the station's lists too).
inline constexpr NameTable<ThicknessMode, 3> kThicknessModeNames{
    {{ThicknessMode::Standard, "standard"}, {ThicknessMode::Full, "full"}, {ThicknessMode::Small, "small"}}};

[[nodiscard]] const char* toString(ThicknessMode mode);  // "standard", "full", "small"
// Throws UnknownName naming the accepted words.
[[nodiscard]] ThicknessMode thicknessModeFromString(const std::string& word);

}  // namespace leafdig::model
