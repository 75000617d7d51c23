// Adapter for cv::detail::GCGraph, OpenCV's Boykov-Kolmogorov implementation on a general graph.
#include "graphcut/maxflow_impl.hpp"

#include <opencv2/core.hpp>
#include <opencv2/imgproc/detail/gcgraph.hpp>

#include <algorithm>

namespace shadecut::maxflow_internal {
namespace {

class OpenCVMaxFlow final : public MaxFlowSolver {
 public:
  double solve(GridGraph& graph, std::vector<std::uint8_t>& sink_side) override {
    const int n = start_solve(graph, sink_side);
    if (n == 0) return 0.0;
    const int rows = graph.rows, cols = graph.cols;

    const auto nonzero = [](float forward, float reverse) { return forward > 0.0f || reverse > 0.0f; };
    unsigned edge_count = 0;
    for (int r = 0; r < rows; ++r) {
      for (int c = 0; c < cols; ++c) {
        const int i = r * cols + c;
        if (c + 1 < cols && nonzero(graph.right_cap[i], graph.right_rev_cap[i])) ++edge_count;
        if (r + 1 < rows && nonzero(graph.down_cap[i], graph.down_rev_cap[i])) ++edge_count;
      }
    }

    // GCGraph can neither be cleared nor refilled (its vectors are private and create() only
    // reserves), so a fresh one is built per call, reserved to the exact size.
    cv::detail::GCGraph<float> gc(unsigned(n) + 1, 2 * edge_count + 2);
    for (int i = 0; i < n; ++i) gc.addVtx();
    // GCGraph sums its flow in float; over a million nodes the terminal part alone drifts by ~1e-4.
    // Cancelling the two terminal capacities here, as addTermWeights would, keeps that part in double
    // and hands GCGraph the same residual weights.
    double terminal_flow = 0.0;
    for (int r = 0; r < rows; ++r) {
      for (int c = 0; c < cols; ++c) {
        const int i = r * cols + c;
        const float both = std::min(graph.source_cap[i], graph.sink_cap[i]);
        terminal_flow += both;
        gc.addTermWeights(i, graph.source_cap[i] - both, graph.sink_cap[i] - both);
        if (c + 1 < cols && nonzero(graph.right_cap[i], graph.right_rev_cap[i])) {
          gc.addEdges(i, i + 1, graph.right_cap[i], graph.right_rev_cap[i]);
        }
        if (r + 1 < rows && nonzero(graph.down_cap[i], graph.down_rev_cap[i])) {
          gc.addEdges(i, i + cols, graph.down_cap[i], graph.down_rev_cap[i]);
        }
      }
    }
    if (edge_count == 0) {
      // maxFlow() asserts that the graph has an edge; a zero one to a spare vertex changes nothing.
      gc.addEdges(n - 1, gc.addVtx(), 0.0f, 0.0f);
    }
    const double flow = terminal_flow + gc.maxFlow();
    // Caveat: GCGraph leaves a node that drops out of a search tree labelled with that tree, so a
    // node that ended free may be reported on the sink side and the cut can cost more than the flow.
    // The API offers no way to tell free nodes apart.
    for (int i = 0; i < n; ++i) sink_side[std::size_t(i)] = !gc.inSourceSegment(i);
    return flow;
  }
};

}  // namespace

std::unique_ptr<MaxFlowSolver> make_opencv_solver() { return std::make_unique<OpenCVMaxFlow>(); }

}  // namespace shadecut::maxflow_internal
