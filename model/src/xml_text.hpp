#pragma once
// Text inside XML (the SVG figures, Helios XML): the five characters XML reserves escaped, and
// control characters — which XML 1.0 does not allow at all — written as spaces (a tab stays), so
// a name from a user's file (a jig's point id, a plant id) cannot end an element or break the
// document.
#include <string>

namespace leafdig::model::detail {

inline std::string xmlText(const std::string& s) {
  std::string out;
  out.reserve(s.size());
  for (const char c : s) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&apos;"; break;
      default: out += (static_cast<unsigned char>(c) < 0x20 && c != '\t') || c == 0x7f ? ' ' : c;
    }
  }
  return out;
}

}  // namespace leafdig::model::detail
