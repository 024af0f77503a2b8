// One cell of text in every CSV leafdig writes (a thickness reading's raw text, a plant or
// leaf id, a margin's words): quoted when it holds a comma, a quote or a line break, and
// neutralised when a spreadsheet would take it for a formula — a cell starting with = + - @,
// a tab or a carriage return gets a leading apostrophe (OWASP's advice for CSV injection), so
// `=HYPERLINK(…)` in a caliper's raw text reaches the curator's spreadsheet as text.
#pragma once

#include <string>

namespace leafdig::model {

inline std::string csvText(const std::string& s) {
  std::string cell = s;
  if (!cell.empty() && std::string("=+-@\t\r").find(cell.front()) != std::string::npos) cell.insert(0, 1, '\'');
  if (cell.find_first_of(",\"\n\r") == std::string::npos) return cell;
  std::string q = "\"";
  for (char c : cell) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

}  // namespace leafdig::model
