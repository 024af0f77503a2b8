#include "json_text.hpp"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <set>
#include <vector>

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

// Where the parser stands, for naming a duplicate key: the keys and array indices around it.
class KeyTracker {
 public:
  static constexpr std::size_t kMaxDepth = 256;  // a leafdig file nests at most 7 levels

  // Called by the parser for every event, in order; false stops nothing (the values are kept).
  void onEvent(nlohmann::json::parse_event_t event, const nlohmann::json& parsed) {
    using E = nlohmann::json::parse_event_t;
    switch (event) {
      case E::object_start:
      case E::array_start:
        countElement();
        if (frames_.size() >= kMaxDepth) throw TooDeep{};  // stop before the document grows
        frames_.push_back({event == E::array_start, 0, {}, {}});
        break;
      case E::object_end:
      case E::array_end:
        if (!frames_.empty()) frames_.pop_back();
        break;
      case E::key:
        if (!frames_.empty()) {
          Frame& f = frames_.back();
          f.lastKey = parsed.get<std::string>();
          if (!f.keys.insert(f.lastKey).second && duplicate_.empty()) duplicate_ = where() + "\"" + f.lastKey + "\"";
        }
        break;
      case E::value: countElement(); break;
    }
  }
  [[nodiscard]] const std::string& duplicate() const { return duplicate_; }
  struct TooDeep {};

 private:
  struct Frame {
    bool array = false;
    std::size_t index = 0;
    std::set<std::string> keys;
    std::string lastKey;
  };
  void countElement() {
    if (!frames_.empty() && frames_.back().array) ++frames_.back().index;
  }
  // "rows[3].points: " style: the enclosing keys and indices (1-based, as error messages count).
  [[nodiscard]] std::string where() const {
    std::string out;
    for (std::size_t i = 0; i + 1 < frames_.size(); ++i) {
      const Frame& f = frames_[i];
      out += f.array ? "[" + std::to_string(f.index) + "]" : (out.empty() ? "" : ".") + f.lastKey;
    }
    return out.empty() ? "the top level's key " : "the key in " + out + ": ";
  }

  std::vector<Frame> frames_;
  std::string duplicate_;
};

}  // namespace

nlohmann::json parseJsonLeniently(std::string_view text, const std::string& source) {
  const std::string cleaned = replaceNonFiniteTokens(text);
  KeyTracker keys;
  try {
    nlohmann::json doc =
        nlohmann::json::parse(cleaned, [&keys](int, nlohmann::json::parse_event_t event, nlohmann::json& parsed) {
          keys.onEvent(event, parsed);
          return true;
        });
    // Two values for one key: JSON readers keep one of them (which one differs), so the file
    // does not say what it means.
    if (!keys.duplicate().empty())
      throw InputError(source + ": " + keys.duplicate() +
                       " appears twice; a reader would keep only one of its values. Remove the one that is wrong.");
    return doc;
  } catch (const KeyTracker::TooDeep&) {
    throw InputError(source + ": the JSON nests deeper than " + std::to_string(KeyTracker::kMaxDepth) +
                     " levels; a leafdig file nests a few. This is not a leafdig file.");
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

namespace {
void findNonFinite(const nlohmann::json& j, const std::string& where, std::string& found) {
  if (!found.empty()) return;
  if (j.is_number_float() && !std::isfinite(j.get<double>())) {
    found = where.empty() ? "a value" : where;
  } else if (j.is_object()) {
    for (auto it = j.begin(); it != j.end(); ++it)
      findNonFinite(it.value(), where + (where.empty() ? "" : ".") + it.key(), found);
  } else if (j.is_array()) {
    for (std::size_t i = 0; i < j.size(); ++i) findNonFinite(j[i], where + "[" + std::to_string(i) + "]", found);
  }
}
}  // namespace

std::string dumpFinite(const nlohmann::json& doc, int indent) {
  std::string found;
  findNonFinite(doc, "", found);
  if (!found.empty())
    throw InputError(found +
                     " is not a finite number: the input holds numbers beyond what a leaf or plant can be. "
                     "Nothing was written");
  return doc.dump(indent);
}

std::string nonFiniteToken(const nlohmann::json& value) {
  if (!value.is_string()) return {};
  const auto& s = value.get_ref<const std::string&>();
  if (s.rfind(kNonFinitePrefix, 0) != 0) return {};
  return s.substr(kNonFinitePrefix.size());
}

}  // namespace leafdig::model::detail
