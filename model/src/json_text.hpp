#pragma once
// Private helpers shared by the JSON readers and writers of this module.
#include <charconv>
#include <cmath>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>

#include "leafdig/model/errors.hpp"

namespace leafdig::model::detail {

// Parses JSON, first turning the bare tokens NaN, Infinity and -Infinity (which Python's
// json module and some digitizer tools write) into marker strings, so that the reader can
// report them at the row and point where they stand instead of failing at a byte offset.
// Throws InputError with line and column for text that is not JSON.
[[nodiscard]] nlohmann::json parseJsonLeniently(std::string_view text, const std::string& source);

// "nonfinite:NaN" etc. produced by parseJsonLeniently, or empty.
[[nodiscard]] std::string nonFiniteToken(const nlohmann::json& value);

// The document as text, after checking that every number in it is finite (nlohmann would
// write NaN and infinities as null): InputError naming the key otherwise.
[[nodiscard]] std::string dumpFinite(const nlohmann::json& doc, int indent = -1);

// Shortest decimal form that reads back to the same double. A value that is not finite has no
// JSON (or MTG, or CSV) form: InputError, before a file is written.
inline std::string formatNumber(double value) {
  if (!std::isfinite(value))
    throw InputError(
        "a number to write is not finite: the input holds numbers beyond what a leaf or plant can be. "
        "Nothing was written");
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  return std::string(buffer, result.ptr);
}

}  // namespace leafdig::model::detail
