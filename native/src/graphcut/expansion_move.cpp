#include "graphcut/expansion_move.hpp"

#include <algorithm>

namespace shadecut::detail {

// One sweep, on one core: the flows into a node are cut back by the time it is reached, and on a
// shared machine waiting for a second core at every sweep cost more than it saved.
bool build_move(MoveTerms& terms, maxflow_internal::KeptFlows* flows, GridGraph& graph,
                std::vector<std::uint8_t>& variable) {
  const int rows = terms.rows(), cols = terms.cols();
  bool any = false;
  for (int p = 0; p < rows * cols; ++p) {
    variable[std::size_t(p)] = terms.variable(p);
    any = any || variable[std::size_t(p)];
  }
  if (!any) return false;
  terms.cache_variables(variable.data());
  struct Uncache {
    MoveTerms& terms;
    ~Uncache() { terms.cache_variables(nullptr); }
  } uncache{terms};
  for (int r = 0; r < rows; ++r) {
    for (int c = 0, p = r * cols; c < cols; ++c, ++p) {
      const bool v = variable[std::size_t(p)];
      const float right = v && c + 1 < cols ? terms.right_arc(p) : 0.0f;
      const float down = v && r + 1 < rows ? terms.down_arc(p) : 0.0f;
      float excess = v ? terms.terminal(p, r, c) : 0.0f;
      float flow_right = 0.0f, flow_down = 0.0f;
      if (flows) {
        flow_right = std::min(flows->right(p), right);
        flow_down = std::min(flows->down(p), down);
        flows->set_right(p, flow_right);
        flows->set_down(p, flow_down);
        float out = flow_right + flow_down;
        if (c > 0) out -= flows->right(p - 1);
        if (r > 0) out -= flows->down(p - cols);
        excess -= out;
      }
      graph.right_cap[std::size_t(p)] = right - flow_right;
      graph.right_rev_cap[std::size_t(p)] = flow_right;
      graph.down_cap[std::size_t(p)] = down - flow_down;
      graph.down_rev_cap[std::size_t(p)] = flow_down;
      graph.source_cap[std::size_t(p)] = std::max(0.0f, excess);
      graph.sink_cap[std::size_t(p)] = std::max(0.0f, -excess);
    }
  }
  return true;
}

double move_delta(const TiltEnergy& energy, const std::vector<int>& labelling, int alpha,
                  const std::vector<int>& changed, const std::vector<std::uint8_t>& is_changed) {
  const int rows = energy.rows(), cols = energy.cols();
  const Mask& mask = energy.mask();
  auto new_label = [&](int q) { return is_changed[std::size_t(q)] ? alpha : labelling[std::size_t(q)]; };
  double delta = 0.0;
  for (int p : changed) {
    delta += double(energy.data_cost(p, alpha)) - energy.data_cost(p, labelling[std::size_t(p)]);
    const int r = p / cols, c = p % cols;
    auto edge = [&](int q, float weight) {
      // An edge between two switching pixels is counted once, from its lower index.
      if (weight <= 0.0f || !mask.data()[q] || (is_changed[std::size_t(q)] && q < p)) return;
      delta += double(weight) * (energy.label_distance(alpha, new_label(q)) -
                                 energy.label_distance(labelling[std::size_t(p)], labelling[std::size_t(q)]));
    };
    if (c + 1 < cols) edge(p + 1, energy.weight_right(p));
    if (c > 0) edge(p - 1, energy.weight_right(p - 1));
    if (r + 1 < rows) edge(p + cols, energy.weight_down(p));
    if (r > 0) edge(p - cols, energy.weight_down(p - cols));
  }
  return delta;
}

}  // namespace shadecut::detail
