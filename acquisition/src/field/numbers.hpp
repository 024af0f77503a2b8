// How the field's calibrations write and compare their numbers, one way for the field check,
// the tip calibration and the field study.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <stdexcept>
#include <string>

namespace leafdig::acquisition::detail {

// `v` with `digits` decimals ("12.35"), as every report and refusal of the field prints it.
inline std::string fixed(double v, int digits = 2) {
  char b[48];
  std::snprintf(b, sizeof b, "%.*f", digits, v);
  return b;
}

// A number a stored record states against the one its own data gives (a refit): the same to a
// millionth (relative, or absolute below 1).
inline bool sameNumber(double stated, double refitted) {
  return std::abs(stated - refitted) <= 1e-6 * std::max({1.0, std::abs(stated), std::abs(refitted)});
}

// A calibration's number as a capture's --field-calibration or --tip-calibration gives it (the
// caller has taken "latest" and "none"): std::invalid_argument naming the option, whose number
// it is and the command that lists them.
inline std::int64_t calibrationNumber(const std::string& which, const std::string& option, const std::string& whose,
                                      const std::string& lister) {
  if (which.empty() || which.size() > 12 || which.find_first_not_of("0123456789") != std::string::npos ||
      std::stoll(which) < 1)
    throw std::invalid_argument(option + " is a " + whose + "'s number (" + lister + "), latest or none; got '" +
                                which.substr(0, 40) + "'");
  return std::stoll(which);
}

}  // namespace leafdig::acquisition::detail
