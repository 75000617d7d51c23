#include "pipeline/method_registry.hpp"

#include <shadecut/support/errors.hpp>

#include "support/enum_names.hpp"

#include <string>

namespace shadecut {

namespace detail {

namespace {

MethodDefaults defaults(double min_curvature, double undefined_weight, double tolerance, int iterations, double smoothness) {
  return {min_curvature, undefined_weight, tolerance, iterations, smoothness};
}

}  // namespace

const std::vector<MethodEntry>& method_registry() {
  // name, defaults (min_curvature, undefined_weight, tolerance, iterations, smoothness), solve
  static const std::vector<MethodEntry> registry{
      {"graphcut", defaults(1.0, 0.5, 0.0, 0, 0.0), &solve_graph_cut},
      {"graphcut_two", defaults(2.0, 0.2, 0.0, 0, 0.0), &solve_graph_cut},
      {"lee_rosenfeld", defaults(2.0, 0.0, 0.0, 0, 0.0), &solve_lee_rosenfeld},
      {"brooks_horn", defaults(0.0, 0.0, 1e-5, 8000, 0.3), &solve_brooks_horn},
      {"tsai_shah", defaults(0.0, 0.0, 0.0, 1, 0.0), &solve_tsai_shah},
      {"upwind", defaults(0.0, 0.0, 0.0, 3, 0.0), &solve_upwind},
      {"pentland", defaults(0.0, 0.0, 0.0, 4, 3.0), &solve_pentland},
  };
  return registry;
}

const MethodEntry& method_entry(Method method) {
  const auto index = std::size_t(method);
  if (index >= method_registry().size()) throw InvalidArgument("shadecut: unknown method");
  return method_registry()[index];
}

}  // namespace detail

const std::vector<std::string>& method_names() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> all;
    for (const detail::MethodEntry& entry : detail::method_registry()) all.emplace_back(entry.name);
    return all;
  }();
  return names;
}

Method parse_method(const std::string& name) { return parse_enum<Method>(method_names(), name, "method"); }

std::string to_string(Method method) { return method_names().at(std::size_t(method)); }

MethodDefaults method_defaults(Method method) { return detail::method_entry(method).defaults; }

}  // namespace shadecut
