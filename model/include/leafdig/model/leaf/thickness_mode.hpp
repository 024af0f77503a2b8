#pragma once
// Which thicknesses a capture measures (docs/method.md §2): the one enum of the marker
// file, the capture protocol and the model.
#include <string>

namespace leafdig::model {

// Standard: midrib at every row, each vein's origin, one edge value; Full: every marker;
// Small: midrib only, one edge value.
enum class ThicknessMode { Standard, Full, Small };

[[nodiscard]] const char* toString(ThicknessMode mode);  // "standard", "full", "small"
// Throws UnknownName naming the accepted words.
[[nodiscard]] ThicknessMode thicknessModeFromString(const std::string& word);

}  // namespace leafdig::model
