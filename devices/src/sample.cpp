// Raw device text shown to people (sample.hpp).
#include "leafdig/devices/sample.hpp"

#include <cstdio>
#include <string>
#include <string_view>

namespace leafdig::devices {

std::string printableRaw(std::string_view raw, bool keepLineEnds) {
  std::string out;
  out.reserve(raw.size() + 8);
  for (char c : raw) {
    const auto u = static_cast<unsigned char>(c);
    if (keepLineEnds && (c == '\r' || c == '\n' || c == '\t')) {
      out += c;
    } else if (c == '\r') {
      out += "\\r";
    } else if (c == '\n') {
      out += "\\n";
    } else if (c == '\t') {
      out += "\\t";
    } else if (c == '\\') {
      out += "\\\\";
    } else if (u >= 0x20 && u < 0x7f) {
      out += c;
    } else {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\x%02x", u);
      out += buf;
    }
  }
  return out;
}

}  // namespace leafdig::devices
