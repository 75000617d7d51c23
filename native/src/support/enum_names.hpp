// One table of names per enum (values 0 .. N-1): parsing, printing and listing read the same table,
// so a name is written once and every error lists the same choices.
#pragma once

#include <shadecut/support/errors.hpp>

#include <string>
#include <vector>

namespace shadecut {

inline std::string join_names(const std::vector<std::string>& names) {
  std::string text;
  for (std::size_t i = 0; i < names.size(); ++i) text += (i ? ", " : "") + names[i];
  return text;
}

/// The value named `name` in `names`; InvalidArgument naming `what` and the choices otherwise.
template <class Enum>
Enum parse_enum(const std::vector<std::string>& names, const std::string& name, const char* what) {
  for (std::size_t i = 0; i < names.size(); ++i)
    if (names[i] == name) return Enum(i);
  throw InvalidArgument(std::string("shadecut: unknown ") + what + " '" + name + "'; choose one of " + join_names(names));
}

}  // namespace shadecut
