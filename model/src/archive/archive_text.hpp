#pragma once
// The archive readers' text helpers (mtg_archive.cpp, hydroshoot_table.cpp): one definition of a
// trimmed cell, a split line, a whole number and a digitized number.
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace leafdig::model::detail {

inline std::string trimmed(std::string_view s) {
  std::size_t a = 0, b = s.size();
  while (a < b && std::isspace(static_cast<unsigned char>(s[a])) != 0) ++a;
  while (b > a && std::isspace(static_cast<unsigned char>(s[b - 1])) != 0) --b;
  return std::string(s.substr(a, b - a));
}

inline std::vector<std::string> splitOn(std::string_view s, char sep) {
  std::vector<std::string> out;
  std::size_t at = 0;
  for (;;) {
    const std::size_t next = s.find(sep, at);
    out.emplace_back(s.substr(at, next == std::string_view::npos ? std::string_view::npos : next - at));
    if (next == std::string_view::npos) return out;
    at = next + 1;
  }
}

inline bool isInteger(const std::string& s) {
  std::size_t i = (!s.empty() && (s[0] == '+' || s[0] == '-')) ? 1 : 0;
  if (i == s.size()) return false;
  for (; i < s.size(); ++i)
    if (std::isdigit(static_cast<unsigned char>(s[i])) == 0) return false;
  return true;
}

inline std::optional<double> realOf(const std::string& s) {
  if (s.empty() || s.size() > 64) return std::nullopt;
  // strtod, not from_chars: a leading '+' ("+12.5") is written by some stations.
  char* end = nullptr;
  const double v = std::strtod(s.c_str(), &end);
  if (end != s.c_str() + s.size() || !std::isfinite(v)) return std::nullopt;
  // Words strtod would take ("inf", "nan", hexadecimal) are no digitized number.
  for (char c : s)
    if (std::string_view("0123456789+-.eE").find(c) == std::string_view::npos) return std::nullopt;
  return v;
}

}  // namespace leafdig::model::detail
