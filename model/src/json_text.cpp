#include "json_text.hpp"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>

#include "leafdig/model/errors.hpp"

namespace leafdig::model::detail {

namespace {

constexpr std::string_view kNonFinitePrefix = "nonfinite:";

std::string replaceNonFiniteTokens(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  bool inString = false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (inString) {
      out += c;
      if (c == '\\' && i + 1 < text.size()) {
        out += text[++i];
      } else if (c == '"') {
        inString = false;
      }
      continue;
    }
    if (c == '"') {
      inString = true;
      out += c;
      continue;
    }
    // A number too large for a double (1e999) becomes +-Infinity, reported like one.
    if (c == '-' || (c >= '0' && c <= '9')) {
      std::size_t end = i + 1;
      while (end < text.size() && std::strchr("0123456789+-.eE", text[end]) != nullptr) ++end;
      const std::string number(text.substr(i, end - i));
      errno = 0;
      const double value = std::strtod(number.c_str(), nullptr);
      if (errno == ERANGE && std::isinf(value)) {
        out += "\"";
        out += kNonFinitePrefix;
        out += value > 0 ? "Infinity" : "-Infinity";
        out += "\"";
      } else {
        out += number;
      }
      i = end - 1;
      continue;
    }
    bool replaced = false;
    for (std::string_view token : {"-Infinity", "Infinity", "NaN"}) {
      if (text.substr(i, token.size()) == token) {
        out += "\"";
        out += kNonFinitePrefix;
        out += token;
        out += "\"";
        i += token.size() - 1;
        replaced = true;
        break;
      }
    }
    if (!replaced) out += c;
  }
  return out;
}

}  // namespace

nlohmann::json parseJsonLeniently(std::string_view text, const std::string& source) {
  const std::string cleaned = replaceNonFiniteTokens(text);
  try {
    return nlohmann::json::parse(cleaned);
  } catch (const nlohmann::json::parse_error& e) {
    // Report the position in the user's text (the replacement may shift it slightly).
    const std::size_t byte = std::min<std::size_t>(e.byte == 0 ? 0 : e.byte - 1, text.size());
    std::size_t line = 1;
    std::size_t column = 1;
    for (std::size_t i = 0; i < byte && i < text.size(); ++i) {
      if (text[i] == '\n') {
        ++line;
        column = 1;
      } else {
        ++column;
      }
    }
    const bool truncated = e.byte >= cleaned.size();
    throw InputError(source + ": not valid JSON" + (truncated ? " (the file ends too early: is it truncated?)" : "") +
                     " at line " + std::to_string(line) + ", column " + std::to_string(column) +
                     ". Export the file again or fix it in a text editor.");
  }
}

std::string nonFiniteToken(const nlohmann::json& value) {
  if (!value.is_string()) return {};
  const auto& s = value.get_ref<const std::string&>();
  if (s.rfind(kNonFinitePrefix, 0) != 0) return {};
  return s.substr(kNonFinitePrefix.size());
}

}  // namespace leafdig::model::detail
