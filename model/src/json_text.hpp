#pragma once
// Private helpers shared by the JSON readers and writers of this module.
#include <charconv>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>

namespace leafdig::model::detail {

// Parses JSON, first turning the bare tokens NaN, Infinity and -Infinity (which Python's
// json module and some digitizer tools write) into marker strings, so that the reader can
// report them at the row and point where they stand instead of failing at a byte offset.
// Throws InputError with line and column for text that is not JSON.
[[nodiscard]] nlohmann::json parseJsonLeniently(std::string_view text, const std::string& source);

// "nonfinite:NaN" etc. produced by parseJsonLeniently, or empty.
[[nodiscard]] std::string nonFiniteToken(const nlohmann::json& value);

// Shortest decimal form that reads back to the same double.
inline std::string formatNumber(double value) {
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  return std::string(buffer, result.ptr);
}

}  // namespace leafdig::model::detail
