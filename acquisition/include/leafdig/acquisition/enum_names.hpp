// One table per enum for its names in files, events and messages: the name of a value and
// the value of a name come from the same table, so the two directions cannot drift.
#pragma once

#include <array>
#include <cstddef>
#include <optional>
#include <string_view>
#include <utility>

namespace leafdig::acquisition {

template <class E, std::size_t N>
using NameTable = std::array<std::pair<E, std::string_view>, N>;

// The name of `value` ("?" for a value the table lacks). Names are string literals, so the
// pointer is null-terminated and lives forever.
template <class E, std::size_t N>
[[nodiscard]] constexpr const char* nameIn(const NameTable<E, N>& table, E value) {
  for (const auto& [v, name] : table)
    if (v == value) return name.data();
  return "?";
}

template <class E, std::size_t N>
[[nodiscard]] constexpr std::optional<E> valueIn(const NameTable<E, N>& table, std::string_view name) {
  for (const auto& [v, n] : table)
    if (n == name) return v;
  return std::nullopt;
}

}  // namespace leafdig::acquisition
