// One table per enum for its words in files, events, options and messages: the word of a
// value and the value of a word come from the same table, so the two directions cannot
// drift. Every module uses it (names/README.md), and every unknown word is refused the same
// way: an UnknownName whose message reads
//     unknown serration "wavy": use none, round, sharp, straight or acuminate
#pragma once

#include <array>
#include <cstddef>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace leafdig {

template <class E, std::size_t N>
using NameTable = std::array<std::pair<E, std::string_view>, N>;

// The word printed for a value no table has (only a value cast from a bad integer).
inline constexpr const char* kUnnamedValue = "?";

// The word of `value`, or kUnnamedValue. Words are string literals, so the pointer is
// null-terminated and lives forever.
template <class E, std::size_t N>
[[nodiscard]] constexpr const char* nameIn(const NameTable<E, N>& table, E value) {
  for (const auto& [v, name] : table)
    if (v == value) return name.data();
  return kUnnamedValue;
}

template <class E, std::size_t N>
[[nodiscard]] constexpr std::optional<E> valueIn(const NameTable<E, N>& table, std::string_view word) {
  for (const auto& [v, name] : table)
    if (name == word) return v;
  return std::nullopt;
}

// The table's words as a reader says them: "a", "a or b", "a, b or c".
template <class E, std::size_t N>
[[nodiscard]] std::string choicesIn(const NameTable<E, N>& table) {
  std::string out;
  for (std::size_t i = 0; i < N; ++i) {
    if (i > 0) out += i + 1 == N ? " or " : ", ";
    out += table[i].second;
  }
  return out;
}

// The table's words in its order, for a list of choices (the CLI's IsMember, a combo box).
template <class E, std::size_t N>
[[nodiscard]] std::vector<std::string> wordsIn(const NameTable<E, N>& table) {
  std::vector<std::string> out;
  out.reserve(N);
  for (const auto& entry : table) out.emplace_back(entry.second);
  return out;
}

// A word that names nothing in its table. It is bad input (the command line exits 2 with
// the message as it is); `what` is what the word should have named ("serration").
class UnknownName : public std::invalid_argument {
 public:
  UnknownName(std::string_view what, std::string_view word, const std::string& choices)
      : std::invalid_argument("unknown " + std::string(what) + " \"" + std::string(word) + "\": use " + choices),
        word_(word) {}
  [[nodiscard]] const std::string& word() const noexcept { return word_; }

 private:
  std::string word_;
};

// The value of `word`, or an UnknownName naming `what` and the table's words.
template <class E, std::size_t N>
[[nodiscard]] E parseName(const NameTable<E, N>& table, std::string_view word, std::string_view what) {
  if (const auto v = valueIn(table, word)) return *v;
  throw UnknownName(what, word, choicesIn(table));
}

}  // namespace leafdig
