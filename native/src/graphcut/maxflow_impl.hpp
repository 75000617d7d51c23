// Internal to the max-flow layer: the grid solver's factory and the input check that it shares with
// the reference solvers (native/reference/). Not part of the public API.
#pragma once

#include <shadecut/graphcut/grid_graph.hpp>
#include <shadecut/graphcut/maxflow.hpp>

#include <cstdint>
#include <memory>
#include <vector>

namespace shadecut::maxflow_internal {

std::unique_ptr<MaxFlowSolver> make_grid_solver();

/// Throws InvalidArgument unless rows, cols >= 0 and every capacity array has rows * cols entries.
void check_shape(const GridGraph& graph);

/// check_shape, and throws InvalidArgument unless every capacity is finite and >= 0.
void check_capacities(const GridGraph& graph);

/// check_capacities, and every node on the source side to begin with; returns the node count.
int start_solve(const GridGraph& graph, std::vector<std::uint8_t>& sink_side);

/// The message check_capacities throws; the grid solver checks the values while it copies them.
extern const char* const bad_capacity_message;

}  // namespace shadecut::maxflow_internal
