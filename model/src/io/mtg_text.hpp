#pragma once
// What an MTG line may hold (docs/plants.md, "MTG"): values in fixed notation (an exponent's
// `+` would be read as a branch) and words without the format's syntax characters. Shared by
// the plan's MTG and the survey's.
#include <cctype>
#include <cstdio>
#include <ostream>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

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
    // Control characters too (a NUL or a line break would end the line a reader splits on).
    const auto u = static_cast<unsigned char>(c);
    const bool bad = std::string_view("+</[](),=^").find(c) != std::string_view::npos || std::isspace(u) != 0 ||
                     u < 0x20 || u == 0x7f;
    out += bad ? '_' : c;
  }
  return out.empty() ? "unnamed" : out;
}

// From `CODE:` to the body's column titles, for a plant (`P`, scale 1) of internodes (`I`,
// following one another) and leaves (`L`, branching from an internode), with these features
// (name, type) in order. With `branches`, an internode may also bear an internode (`I I + ?`:
// a branch). `topoColumns`: the body's deepest line + 1 (at least 2). The caller writes its
// comment lines first.
inline void writeMtgHeader(std::ostream& out, const std::vector<std::pair<const char*, const char*>>& features,
                           bool branches = false, int topoColumns = 2) {
  out << "CODE:\tFORM-A\n\nCLASSES:\nSYMBOL\tSCALE\tDECOMPOSITION\tINDEXATION\tDEFINITION\n"
      << "$\t0\tFREE\tFREE\tIMPLICIT\nP\t1\tCONNECTED\tFREE\tIMPLICIT\nI\t2\tNONE\tFREE\tEXPLICIT\n"
      << "L\t2\tNONE\tFREE\tEXPLICIT\n\nDESCRIPTION:\nLEFT\tRIGHT\tRELTYPE\tMAX\nI\tI\t<\t1\n"
      << (branches ? "I\tI\t+\t?\n" : "") << "I\tL\t+\t?\n\n"
      << "FEATURES:\nNAME\tTYPE\n";
  for (const auto& [name, type] : features) out << name << "\t" << type << "\n";
  out << "\nMTG:\nTOPO" << std::string(static_cast<std::size_t>(topoColumns - 1), '\t');
  for (const auto& feature : features) out << "\t" << feature.first;
  out << "\n";
}

// One line of the body: `depth` leading tabs, the entity, tabs up to the first feature column
// (`topoColumns`), then the values; trailing empty values are left out, so no line ends in a tab.
inline void writeMtgLine(std::ostream& out, int depth, const std::string& entity, std::vector<std::string> values,
                         int topoColumns = 2) {
  while (!values.empty() && values.back().empty()) values.pop_back();
  out << std::string(static_cast<std::size_t>(depth), '\t') << entity;
  if (!values.empty()) out << std::string(static_cast<std::size_t>(topoColumns - depth), '\t');
  for (std::size_t i = 0; i < values.size(); ++i) out << (i ? "\t" : "") << values[i];
  out << "\n";
}

}  // namespace leafdig::model::detail
