#pragma once
// Numbers as the technician reads them in acquisition's messages.
#include <cstdio>
#include <string>

namespace leafdig::acquisition::detail {

// "12.3 mm": one decimal, as the station shows distances in refusals.
inline std::string mm(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.1f mm", v);
  return b;
}

}  // namespace leafdig::acquisition::detail
