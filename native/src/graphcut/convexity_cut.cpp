#include <shadecut/graphcut/convexity_cut.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>

namespace shadecut {

void convexity_cut(const TiltEnergy& energy, const LocalShape& local, std::vector<int>& labelling,
                   MaxFlowSolver& solver) {
  const int rows = energy.rows(), cols = energy.cols(), n = rows * cols;
  const Mask& mask = energy.mask();
  // candidate[p][0] = concave, [1] = convex; -1 where that candidate is not allowed.
  std::vector<std::array<int, 2>> candidate(std::size_t(n), {-1, -1});
  std::vector<std::uint8_t> variable(std::size_t(n), 0);
  for (int p = 0; p < n; ++p) {
    if (!mask.data()[p] || !local.tilt_defined.data()[p]) continue;
    const double t = local.tilt.data()[p];
    const int concave = energy.nearest_label(t), convex = energy.nearest_label(t + M_PI);
    candidate[std::size_t(p)] = {energy.allowed(p, concave) ? concave : -1, energy.allowed(p, convex) ? convex : -1};
    const bool has_concave = candidate[std::size_t(p)][0] >= 0, has_convex = candidate[std::size_t(p)][1] >= 0;
    variable[std::size_t(p)] = has_concave && has_convex;
    if (has_concave != has_convex) labelling[std::size_t(p)] = has_concave ? concave : convex;
  }
  auto takes_part = [&](int p) { return candidate[std::size_t(p)][0] >= 0 || candidate[std::size_t(p)][1] >= 0; };

  // x_p = 0: concave, x_p = 1: convex (sink side). Unary terms accumulate as cost(1) - cost(0).
  GridGraph graph;
  graph.reset(rows, cols);
  std::vector<float> convex_extra(std::size_t(n), 0.0f);
  auto add_pair = [&](int p, int q, float weight, std::vector<float>& cap) {
    if (!takes_part(p) || !takes_part(q) || (!variable[std::size_t(p)] && !variable[std::size_t(q)])) return;
    const auto& cp = candidate[std::size_t(p)];
    const auto& cq = candidate[std::size_t(q)];
    // Fixed pixels use their one candidate whatever x says.
    auto label_of = [](const std::array<int, 2>& c, int x) { return c[std::size_t(x)] >= 0 ? c[std::size_t(x)] : c[std::size_t(1 - x)]; };
    const float e00 = weight * energy.label_distance(label_of(cp, 0), label_of(cq, 0));
    const float e01 = weight * energy.label_distance(label_of(cp, 0), label_of(cq, 1));
    const float e10 = weight * energy.label_distance(label_of(cp, 1), label_of(cq, 0));
    const float e11 = weight * energy.label_distance(label_of(cp, 1), label_of(cq, 1));
    // E = e00 + (e10 - e00) x_p + (e11 - e10) x_q + (e01 + e10 - e00 - e11) (1 - x_p) x_q
    convex_extra[std::size_t(p)] += e10 - e00;
    convex_extra[std::size_t(q)] += e11 - e10;
    if (variable[std::size_t(p)] && variable[std::size_t(q)]) cap[std::size_t(p)] = std::max(0.0f, e01 + e10 - e00 - e11);
  };
  for (int p = 0; p < n; ++p) {
    if (!mask.data()[p]) continue;
    if (energy.weight_right(p) > 0.0f) add_pair(p, p + 1, energy.weight_right(p), graph.right_cap);
    if (energy.weight_down(p) > 0.0f) add_pair(p, p + cols, energy.weight_down(p), graph.down_cap);
  }
  for (int p = 0; p < n; ++p) {
    if (!variable[std::size_t(p)]) continue;
    const auto& c = candidate[std::size_t(p)];
    const float delta = convex_extra[std::size_t(p)] + energy.data_cost(p, c[1]) - energy.data_cost(p, c[0]);
    graph.source_cap[std::size_t(p)] = std::max(0.0f, delta);
    graph.sink_cap[std::size_t(p)] = std::max(0.0f, -delta);
  }
  std::vector<std::uint8_t> convex;
  solver.solve(graph, convex);
  for (int p = 0; p < n; ++p)
    if (variable[std::size_t(p)]) labelling[std::size_t(p)] = candidate[std::size_t(p)][convex[std::size_t(p)] ? 1 : 0];
}

}  // namespace shadecut
