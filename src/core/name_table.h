#pragma once
/// Enum <-> name tables (yocto-gl habit: one table per enum, shared by the command line, the viewer's panels and
/// script, the stats JSON and the loaders). A table lists each value once, in the order menus show it; nothing
/// depends on the enums' numeric values.
#include <optional>
#include <span>
#include <string>
#include <string_view>

namespace pt {

template <class E>
struct EnumName {
  E value;
  const char* name;
};

/// The name of `value`, or "?" if the table lacks it.
template <class E>
const char* name_of(std::span<const EnumName<E>> table, E value) {
  for (const EnumName<E>& e : table)
    if (e.value == value) return e.name;
  return "?";
}

/// The value named `name` exactly, if any.
template <class E>
std::optional<E> value_of(std::span<const EnumName<E>> table, std::string_view name) {
  for (const EnumName<E>& e : table)
    if (name == e.name) return e.value;
  return std::nullopt;
}

/// "a, b or c": the names for an error message.
template <class E>
std::string names_list(std::span<const EnumName<E>> table) {
  std::string out;
  for (size_t i = 0; i < table.size(); ++i) {
    if (i > 0) out += i + 1 == table.size() ? " or " : ", ";
    out += table[i].name;
  }
  return out;
}

}  // namespace pt
