#include <shadecut/alpha_expansion.hpp>

#include <shadecut/errors.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>

namespace shadecut {

namespace {

// Builds the s-t graph of the expansion of `alpha` (node on the sink side = pixel switches to alpha)
// and returns whether any pixel can switch. Kolmogorov & Zabih: a pairwise term with values
// A = V(lp, lq), B = V(lp, alpha), C = V(alpha, lq), D = V(alpha, alpha) = 0 becomes
// A + (C - A) x_p + (D - C) x_q + (B + C - A - D) (1 - x_p) x_q, the last an edge p -> q.
bool build_move(const TiltEnergy& energy, const std::vector<int>& labelling, int alpha, GridGraph& graph,
                std::vector<std::uint8_t>& variable) {
  const int rows = energy.rows(), cols = energy.cols(), n = rows * cols;
  const Mask& mask = energy.mask();
  bool any = false;
  for (int p = 0; p < n; ++p) {
    variable[std::size_t(p)] = mask.data()[p] && labelling[std::size_t(p)] != alpha && energy.allowed(p, alpha);
    any = any || variable[std::size_t(p)];
  }
  if (!any) return false;

  // Unary terms are accumulated as the cost of switching (x_p = 1) minus the cost of staying, in the
  // source capacities themselves (saves a buffer); the last loop turns them into terminal capacities.
  std::vector<float>& switch_cost = graph.source_cap;
  std::fill(switch_cost.begin(), switch_cost.end(), 0.0f);
  std::fill(graph.right_cap.begin(), graph.right_cap.end(), 0.0f);
  std::fill(graph.down_cap.begin(), graph.down_cap.end(), 0.0f);
  std::fill(graph.right_rev_cap.begin(), graph.right_rev_cap.end(), 0.0f);
  std::fill(graph.down_rev_cap.begin(), graph.down_rev_cap.end(), 0.0f);

  auto add_pair = [&](int p, int q, float weight, std::vector<float>& cap) {
    const bool vp = variable[std::size_t(p)], vq = variable[std::size_t(q)];
    if (!vp && !vq) return;
    const int lp = labelling[std::size_t(p)], lq = labelling[std::size_t(q)];
    const float a = weight * energy.label_distance(lp, lq);
    const float b = weight * energy.label_distance(lp, alpha);
    const float c = weight * energy.label_distance(alpha, lq);
    if (vp && vq) {
      switch_cost[std::size_t(p)] += c - a;
      switch_cost[std::size_t(q)] -= c;
      cap[std::size_t(p)] = std::max(0.0f, b + c - a);
    } else if (vp) {
      switch_cost[std::size_t(p)] += c - a;  // q stays lq: V(alpha, lq) against V(lp, lq)
    } else {
      switch_cost[std::size_t(q)] += b - a;  // p stays lp: V(lp, alpha) against V(lp, lq)
    }
  };
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) {
      const int p = r * cols + c;
      if (!mask.data()[p]) continue;
      if (energy.weight_right(p) > 0.0f) add_pair(p, p + 1, energy.weight_right(p), graph.right_cap);
      if (energy.weight_down(p) > 0.0f) add_pair(p, p + cols, energy.weight_down(p), graph.down_cap);
    }
  }
  for (int p = 0; p < n; ++p) {
    float delta = 0.0f;
    if (variable[std::size_t(p)])
      delta = switch_cost[std::size_t(p)] + energy.data_cost(p, alpha) - energy.data_cost(p, labelling[std::size_t(p)]);
    graph.source_cap[std::size_t(p)] = std::max(0.0f, delta);
    graph.sink_cap[std::size_t(p)] = std::max(0.0f, -delta);
  }
  return true;
}

// Energy change of switching the pixels in `changed` to alpha, exactly in double precision.
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

}  // namespace

AlphaExpansionStats alpha_expansion(const TiltEnergy& energy, std::vector<int>& labelling, MaxFlowSolver& solver,
                                    int max_cycles, double tolerance, const MoveCallback& on_move) {
  if (max_cycles < 1) throw InvalidArgument("shadecut: max_cycles must be at least 1");
  if (!(tolerance >= 0.0) || !std::isfinite(tolerance)) throw InvalidArgument("shadecut: tolerance must be finite and >= 0");
  const int n = energy.rows() * energy.cols(), labels = energy.labels();
  if (labelling.size() != std::size_t(n)) throw InvalidArgument("shadecut: the labelling has the wrong size");
  for (int p = 0; p < n; ++p)
    if (energy.mask().data()[p] && (labelling[std::size_t(p)] < 0 || labelling[std::size_t(p)] >= labels ||
                                    !energy.allowed(p, labelling[std::size_t(p)])))
      throw InvalidArgument("shadecut: the initial labelling uses a prohibited label");

  AlphaExpansionStats stats;
  double current = energy.energy(labelling);
  stats.energy_per_cycle.push_back(current);
  GridGraph graph;
  graph.reset(energy.rows(), energy.cols());
  const std::size_t pixels = std::size_t(n);
  std::vector<std::uint8_t> variable(pixels), sink_side, is_changed(pixels, 0);
  std::vector<int> changed;

  // An expansion of a label that nothing has changed since its last expansion would find the same
  // cut, and so would one whose own move was the last change (expansion moves are idempotent): both
  // are skipped. `step` counts label visits; -1 = never.
  std::vector<long> solved_at(std::size_t(labels), -1);
  long step = 0, last_change = -1;
  for (int cycle = 0; cycle < max_cycles; ++cycle) {
    bool improved = false;
    for (int alpha = 0; alpha < labels; ++alpha, ++step) {
      const bool nothing_new = solved_at[std::size_t(alpha)] >= 0 && solved_at[std::size_t(alpha)] >= last_change;
      if (!nothing_new && build_move(energy, labelling, alpha, graph, variable)) {
        solved_at[std::size_t(alpha)] = step;
        const auto start = std::chrono::steady_clock::now();
        solver.solve(graph, sink_side);
        stats.maxflow_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        ++stats.moves;

        changed.clear();
        for (int p = 0; p < n; ++p)
          if (variable[std::size_t(p)] && sink_side[std::size_t(p)]) changed.push_back(p);
        for (int p : changed) is_changed[std::size_t(p)] = 1;
        const double delta = move_delta(energy, labelling, alpha, changed, is_changed);
        for (int p : changed) is_changed[std::size_t(p)] = 0;
        // Float capacities can make a cut that is optimal up to rounding raise the energy by a hair;
        // such a move is refused, which keeps the energy monotone.
        if (!changed.empty() && delta < -1e-9 * std::max(1.0, std::abs(current))) {
          for (int p : changed) labelling[std::size_t(p)] = alpha;
          current += delta;
          improved = true;
          ++stats.accepted_moves;
          last_change = step;
        }
      }
      if (on_move && !on_move((cycle + double(alpha + 1) / labels) / max_cycles)) throw Cancelled();
    }
    ++stats.cycles;
    const double before = stats.energy_per_cycle.back();
    current = energy.energy(labelling);
    stats.energy_per_cycle.push_back(current);
    if (!improved || before - current <= tolerance * std::abs(before)) break;
  }
  return stats;
}

}  // namespace shadecut
