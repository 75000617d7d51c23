// Adapter for boost::boykov_kolmogorov_max_flow on a boost::adjacency_list. It is the slowest solver
// and serves as the reference the others are tested against, so it computes in double.
#include "graphcut/maxflow_impl.hpp"

// GCC 12 mistakes the edge iterators' boost::optional members for uninitialized once inlined.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include <boost/graph/adjacency_list.hpp>
#include <boost/graph/boykov_kolmogorov_max_flow.hpp>
#pragma GCC diagnostic pop

namespace shadecut::maxflow_internal {
namespace {

using Traits = boost::adjacency_list_traits<boost::vecS, boost::vecS, boost::directedS>;

struct Arc {
  double capacity = 0.0;
  double residual = 0.0;
  Traits::edge_descriptor reverse;
};

using Graph = boost::adjacency_list<boost::vecS, boost::vecS, boost::directedS, boost::no_property, Arc>;
using Vertex = Graph::vertex_descriptor;

class BoostMaxFlow final : public MaxFlowSolver {
 public:
  double solve(GridGraph& graph, std::vector<std::uint8_t>& sink_side) override {
    const int n = start_solve(graph, sink_side);
    if (n == 0) return 0.0;
    const int rows = graph.rows, cols = graph.cols;

    // Vertices 0..n-1 are the pixels, n the source, n+1 the sink. Clearing only the out-edge lists
    // keeps their storage for the next graph of the same size.
    const std::size_t vertex_count = std::size_t(n) + 2;
    if (boost::num_vertices(g_) == vertex_count) {
      for (std::size_t v = 0; v < vertex_count; ++v) boost::clear_out_edges(v, g_);
    } else {
      g_ = Graph(vertex_count);
    }
    const Vertex source = Vertex(n);
    const Vertex sink = Vertex(n) + 1;
    for (int r = 0; r < rows; ++r) {
      for (int c = 0; c < cols; ++c) {
        const int i = r * cols + c;
        add_arc_pair(source, Vertex(i), graph.source_cap[i], 0.0f);
        add_arc_pair(Vertex(i), sink, graph.sink_cap[i], 0.0f);
        if (c + 1 < cols) add_arc_pair(Vertex(i), Vertex(i) + 1, graph.right_cap[i], graph.right_rev_cap[i]);
        if (r + 1 < rows) add_arc_pair(Vertex(i), Vertex(i + cols), graph.down_cap[i], graph.down_rev_cap[i]);
      }
    }

    predecessor_.resize(vertex_count);
    color_.resize(vertex_count);
    distance_.resize(vertex_count);
    const auto index = boost::get(boost::vertex_index, g_);
    const double flow = boost::boykov_kolmogorov_max_flow(
        g_, boost::get(&Arc::capacity, g_), boost::get(&Arc::residual, g_), boost::get(&Arc::reverse, g_),
        boost::make_iterator_property_map(predecessor_.begin(), index),
        boost::make_iterator_property_map(color_.begin(), index),
        boost::make_iterator_property_map(distance_.begin(), index), index, source, sink);
    // Boost colours the source tree black and the sink tree white; free vertices stay gray. The sink
    // tree is closed under non-saturated arcs entering it, so it is a valid sink side on its own.
    for (int i = 0; i < n; ++i) sink_side[std::size_t(i)] = color_[std::size_t(i)] == boost::white_color;
    return flow;
  }

 private:
  // Boost's BK needs every arc paired with its reverse; arcs zero both ways are left out.
  void add_arc_pair(Vertex u, Vertex v, float forward, float reverse) {
    if (!(forward > 0.0f || reverse > 0.0f)) return;
    const auto uv = boost::add_edge(u, v, g_).first;
    const auto vu = boost::add_edge(v, u, g_).first;
    g_[uv].capacity = forward;
    g_[uv].reverse = vu;
    g_[vu].capacity = reverse;
    g_[vu].reverse = uv;
  }

  Graph g_;
  std::vector<Graph::edge_descriptor> predecessor_;
  std::vector<boost::default_color_type> color_;
  std::vector<long> distance_;
};

}  // namespace

std::unique_ptr<MaxFlowSolver> make_boost_solver() { return std::make_unique<BoostMaxFlow>(); }

}  // namespace shadecut::maxflow_internal
