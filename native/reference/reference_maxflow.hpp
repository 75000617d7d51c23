// The maximum-flow solvers that the core's grid solver is tested and benchmarked against: OpenCV's
// GCGraph and Boost's boykov_kolmogorov_max_flow, both on a general graph. They live outside the core
// so that the module the Blender add-on ships links neither library; the tests and the benchmark
// program link this one.
#pragma once

#include <shadecut/graphcut/maxflow.hpp>

#include <memory>
#include <string>

namespace shadecut {

/// Which maximum-flow implementation solves a cut.
enum class MaxFlowKind {
  Grid,    ///< the core's Boykov-Kolmogorov solver specialized to the 4-connected grid.
  OpenCV,  ///< cv::detail::GCGraph (Boykov-Kolmogorov on a general adjacency list).
  Boost,   ///< boost::boykov_kolmogorov_max_flow on a boost::adjacency_list.
};

/// Parses "grid", "opencv" or "boost"; throws InvalidArgument otherwise.
MaxFlowKind parse_maxflow_kind(const std::string& name);
std::string to_string(MaxFlowKind kind);

/// Creates a solver of the given kind.
std::unique_ptr<MaxFlowSolver> make_maxflow_solver(MaxFlowKind kind);

}  // namespace shadecut
