// Small helpers shared by the codecs (private).
#pragma once

#include <bit>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "leafdig/devices/sample.hpp"

namespace leafdig::devices::detail {

inline std::optional<double> toDouble(std::string_view s) {
  while (!s.empty() && s.front() == ' ') s.remove_prefix(1);
  while (!s.empty() && s.back() == ' ') s.remove_suffix(1);
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  if (s.empty()) return std::nullopt;
  double v = 0;
  const auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc() || p != s.data() + s.size() || !std::isfinite(v)) return std::nullopt;
  return v;
}

// Millimetres rounded to a nanometre: unit conversion leaves no 0.8999999999 tails.
inline double roundMm(double v) {
  const double r = std::round(v * 1e6) / 1e6;
  return r == 0.0 ? 0.0 : r;
}

inline bool isDigit(char c) {
  return c >= '0' && c <= '9';
}
inline bool isLetter(char c) {
  return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z');
}

// A right-aligned fixed-point field of `width` characters with `decimals` decimals:
// leading spaces, optional '-', at least one digit, '.', exactly `decimals` digits.
inline std::optional<double> fixedField(std::string_view f, int decimals) {
  const auto width = static_cast<int>(f.size());
  const int dot = width - decimals - 1;
  if (dot < 1 || f[static_cast<std::size_t>(dot)] != '.') return std::nullopt;
  for (int i = dot + 1; i < width; ++i)
    if (!isDigit(f[static_cast<std::size_t>(i)])) return std::nullopt;
  int i = 0;
  while (i < dot && f[static_cast<std::size_t>(i)] == ' ') ++i;
  if (i < dot && f[static_cast<std::size_t>(i)] == '-') ++i;
  if (i >= dot) return std::nullopt;  // no integer digit
  for (; i < dot; ++i)
    if (!isDigit(f[static_cast<std::size_t>(i)])) return std::nullopt;
  return toDouble(f);
}

inline float readF32(const char* p) {
  std::uint32_t u = 0;
  for (int i = 3; i >= 0; --i) u = (u << 8) | static_cast<unsigned char>(p[i]);
  return std::bit_cast<float>(u);
}
inline std::uint32_t readU32(const char* p) {
  std::uint32_t u = 0;
  for (int i = 3; i >= 0; --i) u = (u << 8) | static_cast<unsigned char>(p[i]);
  return u;
}
inline std::uint16_t readU16(const char* p) {
  return static_cast<std::uint16_t>(static_cast<unsigned char>(p[0]) | (static_cast<unsigned char>(p[1]) << 8));
}
inline void appendU32(std::string& s, std::uint32_t u) {
  for (int i = 0; i < 4; ++i) s += static_cast<char>((u >> (8 * i)) & 0xff);
}
inline void appendF32(std::string& s, double v) {
  appendU32(s, std::bit_cast<std::uint32_t>(static_cast<float>(v)));
}
inline void appendU16(std::string& s, std::uint16_t u) {
  s += static_cast<char>(u & 0xff);
  s += static_cast<char>(u >> 8);
}

inline std::string fmt(const char* format, double v) {
  char buf[64];
  const int n = std::snprintf(buf, sizeof buf, format, v);
  return std::string(buf, n > 0 ? static_cast<std::size_t>(n) : 0);
}

// Delivers a validated stylus record: keeps its raw bytes and counts it.
inline void deliver(StylusSample&& s, std::string raw, DecodeStats& stats, std::vector<StylusSample>& out) {
  s.raw = std::move(raw);
  if (s.status != "ok") ++stats.statusWarnings;
  ++stats.records;
  out.push_back(std::move(s));
}

inline bool plausibleAngles(double az, double el, double roll) {
  return std::abs(az) <= 180.001 && std::abs(el) <= 90.001 && std::abs(roll) <= 180.001;
}

}  // namespace leafdig::devices::detail
