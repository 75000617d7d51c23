// Minimum s-t cut on a GridGraph, behind one small interface so that the tests and benchmarks can put
// reference solvers beside the core's.
#pragma once

#include <shadecut/graphcut/grid_graph.hpp>

#include <cstdint>
#include <memory>
#include <vector>

namespace shadecut {

/// A reusable maximum-flow solver. Implementations keep their buffers between calls, so one solver
/// serves all moves of an alpha-expansion without reallocating.
class MaxFlowSolver {
 public:
  virtual ~MaxFlowSolver() = default;

  /// Computes a maximum flow / minimum cut of `graph`.
  ///
  /// @param[in,out] graph  capacities (all >= 0); on return they may hold residual capacities.
  /// @param[out] sink_side resized to graph.size(); 1 where the node lies on the sink side of a
  ///                       minimum cut, 0 on the source side (isolated nodes: 0).
  /// @return the maximum flow value, i.e. the capacity of the minimum cut.
  virtual double solve(GridGraph& graph, std::vector<std::uint8_t>& sink_side) = 0;

  /// True when solve() always leaves exactly the residual capacities of a maximum flow in `graph`
  /// and reports as the sink side exactly the nodes that can still reach the sink through them. A
  /// caller can then keep the flow and start a later, slightly different cut from it.
  virtual bool leaves_residuals() const { return false; }
};

/// Creates ShadeCut's Boykov-Kolmogorov solver specialized to the 4-connected grid. (The general
/// graph solvers it is tested and benchmarked against live in native/reference/, outside the core.)
std::unique_ptr<MaxFlowSolver> make_maxflow_solver();

}  // namespace shadecut
