#pragma once
// What an MTG line may hold (docs/plants.md, "MTG"): values in fixed notation (an exponent's
// `+` would be read as a branch) and words without the format's syntax characters. Shared by
// the plan's MTG and the survey's.
#include <cctype>
#include <cstdio>
#include <string>
#include <string_view>

namespace leafdig::model::detail {

// Fixed notation with three decimals; never an exponent, never "-0.000".
inline std::string mtgReal(double v) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.3f", v);
  std::string s(buffer);
  if (s == "-0.000") s = "0.000";
  return s;
}

// MTG values must not hold its syntax characters, tabs or spaces.
inline std::string mtgAlpha(const std::string& s) {
  std::string out;
  for (char c : s) {
    const bool bad = std::string_view("+</[](),=^").find(c) != std::string_view::npos ||
                     std::isspace(static_cast<unsigned char>(c)) != 0;
    out += bad ? '_' : c;
  }
  return out.empty() ? "unnamed" : out;
}

}  // namespace leafdig::model::detail
