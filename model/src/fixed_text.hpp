#pragma once
// Fixed-point decimal text written straight into a buffer, for the mesh writers (OBJ,
// CARIBU): integer arithmetic, no stream or printf, several times faster on meshes of
// hundreds of thousands of vertices. Never an exponent; the caller sizes the buffer (a
// number takes at most 22 characters).
#include <cmath>

namespace leafdig::model::detail {

// `scaled` / 10^decimals, e.g. (12345, 3) → "12.345", (-5, 3) → "-0.005"; at least one digit
// before the point. Returns the end of what was written.
inline char* writeScaled(char* out, long long scaled, int decimals) {
  if (scaled < 0) *out++ = '-';
  unsigned long long a =
      scaled < 0 ? static_cast<unsigned long long>(-(scaled + 1)) + 1 : static_cast<unsigned long long>(scaled);
  char digits[24];
  int n = 0;
  do {
    digits[n++] = static_cast<char>('0' + a % 10);
    a /= 10;
  } while (a != 0 || n <= decimals);
  for (int i = n - 1; i >= 0; --i) {
    *out++ = digits[i];
    if (i == decimals && decimals > 0) *out++ = '.';
  }
  return out;
}

// `value` rounded to `decimals` digits after the point (at most 9).
inline char* writeFixed(char* out, double value, int decimals) {
  static constexpr double kScale[] = {1, 10, 100, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9};
  return writeScaled(out, std::llround(value * kScale[decimals]), decimals);
}

}  // namespace leafdig::model::detail
