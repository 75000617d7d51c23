#include "graphcut/maxflow_impl.hpp"

#include <shadecut/support/errors.hpp>

#include <cmath>
#include <string>

namespace shadecut {

std::unique_ptr<MaxFlowSolver> make_maxflow_solver() { return maxflow_internal::make_grid_solver(); }

namespace maxflow_internal {

const char* const bad_capacity_message = "max-flow: every capacity must be finite and >= 0";

void check_shape(const GridGraph& graph) {
  if (graph.rows < 0 || graph.cols < 0) {
    throw InvalidArgument("max-flow: negative grid size " + std::to_string(graph.rows) + " x " +
                          std::to_string(graph.cols));
  }
  const std::size_t n = std::size_t(graph.rows) * std::size_t(graph.cols);
  for (const auto* v : {&graph.source_cap, &graph.sink_cap, &graph.right_cap, &graph.right_rev_cap, &graph.down_cap,
                        &graph.down_rev_cap}) {
    if (v->size() != n) {
      throw InvalidArgument("max-flow: a capacity array has " + std::to_string(v->size()) + " entries, expected " +
                            std::to_string(graph.rows) + " x " + std::to_string(graph.cols) + " = " +
                            std::to_string(n));
    }
  }
}

void check_capacities(const GridGraph& graph) {
  check_shape(graph);
  for (const auto* v : {&graph.source_cap, &graph.sink_cap, &graph.right_cap, &graph.right_rev_cap, &graph.down_cap,
                        &graph.down_rev_cap}) {
    for (const float c : *v) {
      if (!(c >= 0.0f && std::isfinite(c))) throw InvalidArgument(bad_capacity_message);
    }
  }
}

int start_solve(const GridGraph& graph, std::vector<std::uint8_t>& sink_side) {
  check_capacities(graph);
  sink_side.assign(std::size_t(graph.size()), 0);
  return graph.size();
}

}  // namespace maxflow_internal
}  // namespace shadecut
