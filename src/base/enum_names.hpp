#pragma once
// One string table per enum: the names of an enum's values as config files, logs and result
// files spell them, declared once next to the enum as
//   inline constexpr EnumNames<E, N> kENames{{{E::A, "a"}, {E::B, "b"}}};
// and used through name_of (writing), value_of (parsing) and io::TableReader::choice (a config
// key with its allowed values). An enum's strings appear in its table and nowhere else.
#include <array>
#include <optional>
#include <string>
#include <string_view>

namespace codesign {

template <class E>
struct EnumName {
  E value;
  std::string_view name;
};

template <class E, std::size_t N>
using EnumNames = std::array<EnumName<E>, N>;

// The name of v ("?" for a value missing from the table; each table's test rules that out).
template <class E, std::size_t N>
constexpr std::string_view name_of(const EnumNames<E, N>& names, E v) {
  for (const EnumName<E>& n : names)
    if (n.value == v) return n.name;
  return "?";
}

// The value named s, or nullopt.
template <class E, std::size_t N>
constexpr std::optional<E> value_of(const EnumNames<E, N>& names, std::string_view s) {
  for (const EnumName<E>& n : names)
    if (n.name == s) return n.value;
  return std::nullopt;
}

// The names in table order (for messages listing the allowed values).
template <class E, std::size_t N>
constexpr std::array<std::string_view, N> names_in(const EnumNames<E, N>& names) {
  std::array<std::string_view, N> out{};
  for (std::size_t i = 0; i < N; ++i) out[i] = names[i].name;
  return out;
}

// "a, b, c": the names in table order, for a message listing the allowed values.
template <class E, std::size_t N>
std::string names_list(const EnumNames<E, N>& names) {
  std::string out;
  for (const EnumName<E>& n : names) out += (out.empty() ? "" : ", ") + std::string(n.name);
  return out;
}

}  // namespace codesign
