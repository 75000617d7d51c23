#include <shadecut/support/errors.hpp>
#include <shadecut/graphcut/grid_graph.hpp>
#include <reference_maxflow.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

namespace shadecut {
namespace {

const MaxFlowKind kAllKinds[] = {MaxFlowKind::Grid, MaxFlowKind::OpenCV, MaxFlowKind::Boost};

struct Solution {
  double flow = 0.0;
  std::vector<std::uint8_t> sink_side;
};

// Solves a copy, so the caller keeps the original capacities to check the cut against.
Solution solve_copy(MaxFlowSolver& solver, const GridGraph& graph) {
  GridGraph scratch = graph;
  Solution s;
  s.flow = solver.solve(scratch, s.sink_side);
  return s;
}

Solution solve_fresh(MaxFlowKind kind, const GridGraph& graph) {
  return solve_copy(*make_maxflow_solver(kind), graph);
}

// Capacity of the s-t cut whose sink side is given, from the original capacities.
double cut_capacity(const GridGraph& g, const std::vector<std::uint8_t>& sink_side) {
  double cut = 0.0;
  for (int r = 0; r < g.rows; ++r) {
    for (int c = 0; c < g.cols; ++c) {
      const int i = r * g.cols + c;
      cut += sink_side[i] ? g.source_cap[i] : g.sink_cap[i];
      if (c + 1 < g.cols) {
        if (!sink_side[i] && sink_side[i + 1]) cut += g.right_cap[i];
        if (sink_side[i] && !sink_side[i + 1]) cut += g.right_rev_cap[i];
      }
      if (r + 1 < g.rows) {
        if (!sink_side[i] && sink_side[i + g.cols]) cut += g.down_cap[i];
        if (sink_side[i] && !sink_side[i + g.cols]) cut += g.down_rev_cap[i];
      }
    }
  }
  return cut;
}

double tolerance(double reference) { return 1e-4 * std::max(1.0, std::abs(reference)); }

struct RandomGraphSpec {
  int rows = 1;
  int cols = 1;
  double zero_fraction = 0.0;      // capacities drawn as zero
  double isolated_fraction = 0.0;  // nodes with every capacity zero
  bool integer_caps = false;       // small integers make ties and exact cancellations common
  float max_cap = 10.0f;
};

// Also fills the entries the grid does not use (right_cap of the last column, down_cap of the last
// row) with junk, which every solver must ignore.
GridGraph random_graph(const RandomGraphSpec& spec, std::mt19937& rng) {
  GridGraph g;
  g.reset(spec.rows, spec.cols);
  std::uniform_real_distribution<float> uniform(0.0f, spec.max_cap);
  std::uniform_int_distribution<int> small_int(0, 5);
  std::bernoulli_distribution zero(spec.zero_fraction);
  const auto draw = [&] {
    if (zero(rng)) return 0.0f;
    return spec.integer_caps ? float(small_int(rng)) : uniform(rng);
  };
  for (auto* v : {&g.source_cap, &g.sink_cap, &g.right_cap, &g.right_rev_cap, &g.down_cap, &g.down_rev_cap}) {
    for (float& x : *v) x = draw();
  }
  std::bernoulli_distribution isolated(spec.isolated_fraction);
  for (int r = 0; r < spec.rows; ++r) {
    for (int c = 0; c < spec.cols; ++c) {
      if (!isolated(rng)) continue;
      const int i = r * spec.cols + c;
      g.source_cap[i] = g.sink_cap[i] = 0.0f;
      if (c + 1 < spec.cols) g.right_cap[i] = g.right_rev_cap[i] = 0.0f;
      if (c > 0) g.right_cap[i - 1] = g.right_rev_cap[i - 1] = 0.0f;
      if (r + 1 < spec.rows) g.down_cap[i] = g.down_rev_cap[i] = 0.0f;
      if (r > 0) g.down_cap[i - spec.cols] = g.down_rev_cap[i - spec.cols] = 0.0f;
    }
  }
  return g;
}

bool is_isolated(const GridGraph& g, int r, int c) {
  const int i = r * g.cols + c;
  float sum = g.source_cap[i] + g.sink_cap[i];
  if (c + 1 < g.cols) sum += g.right_cap[i] + g.right_rev_cap[i];
  if (c > 0) sum += g.right_cap[i - 1] + g.right_rev_cap[i - 1];
  if (r + 1 < g.rows) sum += g.down_cap[i] + g.down_rev_cap[i];
  if (r > 0) sum += g.down_cap[i - g.cols] + g.down_rev_cap[i - g.cols];
  return sum == 0.0f;
}

// Every solver must find the reference flow and report a cut whose capacity equals its own flow.
void expect_all_solvers_agree(const GridGraph& graph) {
  const Solution reference = solve_fresh(MaxFlowKind::Boost, graph);
  for (const MaxFlowKind kind : kAllKinds) {
    SCOPED_TRACE(to_string(kind));
    const Solution s = solve_fresh(kind, graph);
    ASSERT_EQ(s.sink_side.size(), std::size_t(graph.size()));
    EXPECT_NEAR(s.flow, reference.flow, tolerance(reference.flow));
    const double cut = cut_capacity(graph, s.sink_side);
    if (kind == MaxFlowKind::OpenCV) {
      // GCGraph leaves a node that drops out of a search tree labelled with that tree, so its cut can
      // exceed the flow; it can never be below it.
      EXPECT_GE(cut, s.flow - tolerance(s.flow));
    } else {
      EXPECT_NEAR(cut, s.flow, tolerance(s.flow));
    }
    for (int r = 0; r < graph.rows; ++r) {
      for (int c = 0; c < graph.cols; ++c) {
        if (is_isolated(graph, r, c)) {
          EXPECT_EQ(s.sink_side[r * graph.cols + c], 0) << "isolated node " << r << "," << c;
        }
      }
    }
  }
}

TEST(MaxFlow, HandComputedTwoByTwo) {
  // Nodes 0 1 / 2 3. Source feeds 0 (5) and 2 (2); 1 (3) and 3 (6) drain to the sink; arcs 0->1 (4),
  // 2->3 (1), 0->2 (2), 1->3 (3). The unique minimum cut separates {0, 2} from {1, 3}: 4 + 1 = 5.
  GridGraph g;
  g.reset(2, 2);
  g.source_cap = {5, 0, 2, 0};
  g.sink_cap = {0, 3, 0, 6};
  g.right_cap[0] = 4;
  g.right_cap[2] = 1;
  g.down_cap[0] = 2;
  g.down_cap[1] = 3;
  for (const MaxFlowKind kind : kAllKinds) {
    SCOPED_TRACE(to_string(kind));
    const Solution s = solve_fresh(kind, g);
    EXPECT_DOUBLE_EQ(s.flow, 5.0);
    EXPECT_EQ(s.sink_side, (std::vector<std::uint8_t>{0, 1, 0, 1}));
  }
}

TEST(MaxFlow, HandComputedRowWithReverseArcsAndIsolatedNode) {
  // 1 x 4: node 0 <- source 4; 0 -> 1 (1), 1 -> 0 (7); node 1 -> sink 2; node 2 isolated; node 3 has
  // source 1 and sink 3, so 1 unit goes straight through it. Max flow 1 + 1 = 2; the cut puts 0 on
  // the source side and 1, 3 on the sink side.
  GridGraph g;
  g.reset(1, 4);
  g.source_cap = {4, 0, 0, 1};
  g.sink_cap = {0, 2, 0, 3};
  g.right_cap[0] = 1;
  g.right_rev_cap[0] = 7;
  for (const MaxFlowKind kind : kAllKinds) {
    SCOPED_TRACE(to_string(kind));
    const Solution s = solve_fresh(kind, g);
    EXPECT_DOUBLE_EQ(s.flow, 2.0);
    EXPECT_EQ(s.sink_side, (std::vector<std::uint8_t>{0, 1, 0, 1}));
  }
}

TEST(MaxFlow, EmptyAndSingleNodeGraphs) {
  for (const MaxFlowKind kind : kAllKinds) {
    SCOPED_TRACE(to_string(kind));
    GridGraph empty;
    empty.reset(0, 7);
    Solution s = solve_fresh(kind, empty);
    EXPECT_EQ(s.flow, 0.0);
    EXPECT_TRUE(s.sink_side.empty());

    GridGraph single;
    single.reset(1, 1);
    single.source_cap[0] = 2.5f;
    single.sink_cap[0] = 1.5f;
    s = solve_fresh(kind, single);
    EXPECT_DOUBLE_EQ(s.flow, 1.5);
    EXPECT_EQ(s.sink_side, std::vector<std::uint8_t>{0});
  }
}

TEST(MaxFlow, RandomGridsAgreeWithBoost) {
  std::mt19937 rng(20240611);
  const double zero_fractions[] = {0.0, 0.3, 0.7, 0.9};
  for (int trial = 0; trial < 300; ++trial) {
    RandomGraphSpec spec;
    std::uniform_int_distribution<int> side(1, 40);
    switch (trial % 6) {
      case 0: spec.rows = 1; spec.cols = side(rng); break;
      case 1: spec.rows = side(rng); spec.cols = 1; break;
      default: spec.rows = side(rng); spec.cols = side(rng); break;
    }
    spec.zero_fraction = zero_fractions[trial % 4];
    spec.isolated_fraction = (trial / 4) % 3 == 0 ? 0.0 : 0.15;
    spec.integer_caps = (trial / 12) % 2 == 1;
    SCOPED_TRACE("trial " + std::to_string(trial) + ": " + std::to_string(spec.rows) + " x " +
                 std::to_string(spec.cols));
    expect_all_solvers_agree(random_graph(spec, rng));
    if (HasFailure()) return;
  }
}

// The nodes that can reach the sink through arcs of positive capacity.
std::vector<std::uint8_t> reaching_the_sink(const GridGraph& g) {
  std::vector<std::uint8_t> reached(std::size_t(g.size()), 0);
  std::vector<int> queue;
  for (int i = 0; i < g.size(); ++i)
    if (g.sink_cap[i] > 0.0f) reached[i] = 1, queue.push_back(i);
  for (std::size_t k = 0; k < queue.size(); ++k) {
    const int v = queue[k], r = v / g.cols, c = v % g.cols;
    const auto visit = [&](int u, float capacity_into_v) {
      if (!reached[u] && capacity_into_v > 0.0f) reached[u] = 1, queue.push_back(u);
    };
    if (c > 0) visit(v - 1, g.right_cap[v - 1]);
    if (c + 1 < g.cols) visit(v + 1, g.right_rev_cap[v]);
    if (r > 0) visit(v - g.cols, g.down_cap[v - g.cols]);
    if (r + 1 < g.rows) visit(v + g.cols, g.down_rev_cap[v]);
  }
  return reached;
}

// The contract alpha-expansion relies on to keep flows between moves: the graph is left holding the
// residual capacities of a maximum flow (a flow: each arc pair keeps its total, each node conserves)
// and the sink side is exactly what can still reach the sink, so solving the residual graph again
// pushes nothing and finds the same cut.
TEST(MaxFlow, GridLeavesTheResidualsOfAMaximumFlow) {
  const auto solver = make_maxflow_solver();
  ASSERT_TRUE(solver->leaves_residuals());
  std::mt19937 rng(777);
  for (int trial = 0; trial < 200; ++trial) {
    RandomGraphSpec spec;
    std::uniform_int_distribution<int> side(1, 30);
    spec.rows = side(rng);
    spec.cols = side(rng);
    spec.zero_fraction = trial % 3 == 0 ? 0.0 : 0.4;
    spec.isolated_fraction = trial % 2 == 0 ? 0.0 : 0.15;
    spec.integer_caps = trial % 4 >= 2;
    SCOPED_TRACE("trial " + std::to_string(trial) + ": " + std::to_string(spec.rows) + " x " +
                 std::to_string(spec.cols));
    const GridGraph g = random_graph(spec, rng);
    GridGraph residual = g;
    std::vector<std::uint8_t> sink_side;
    const double flow = solver->solve(residual, sink_side);
    EXPECT_NEAR(flow, solve_fresh(MaxFlowKind::Boost, g).flow, tolerance(flow));
    EXPECT_EQ(sink_side, reaching_the_sink(residual));

    std::vector<double> net_out(std::size_t(g.size()), 0.0);
    for (int r = 0; r < g.rows; ++r) {
      for (int c = 0; c < g.cols; ++c) {
        const int i = r * g.cols + c;
        for (const auto* v : {&residual.source_cap, &residual.sink_cap, &residual.right_cap, &residual.right_rev_cap,
                              &residual.down_cap, &residual.down_rev_cap}) {
          ASSERT_GE((*v)[i], 0.0f);
        }
        const auto arc_pair = [&](int j, float forward, float reverse, float residual_forward, float residual_reverse) {
          EXPECT_NEAR(residual_forward + residual_reverse, forward + reverse, 1e-4 * (1.0 + forward + reverse));
          const double pushed = double(forward) - residual_forward;
          net_out[std::size_t(i)] += pushed;
          net_out[std::size_t(j)] -= pushed;
        };
        if (c + 1 < g.cols)
          arc_pair(i + 1, g.right_cap[i], g.right_rev_cap[i], residual.right_cap[i], residual.right_rev_cap[i]);
        if (r + 1 < g.rows)
          arc_pair(i + g.cols, g.down_cap[i], g.down_rev_cap[i], residual.down_cap[i], residual.down_rev_cap[i]);
      }
    }
    for (int i = 0; i < g.size(); ++i) {
      const double from_terminals = (double(g.source_cap[i]) - g.sink_cap[i]) -
                                    (double(residual.source_cap[i]) - residual.sink_cap[i]);
      EXPECT_NEAR(from_terminals, net_out[std::size_t(i)], 1e-3) << "node " << i;
    }

    GridGraph again = residual;
    std::vector<std::uint8_t> sink_side_again;
    EXPECT_NEAR(solver->solve(again, sink_side_again), 0.0, tolerance(flow));
    EXPECT_EQ(sink_side_again, sink_side);
    if (HasFailure()) return;
  }
}

// Like an expansion move: most nodes strongly prefer one side, the rest are undecided, and some are
// background. Both orientations, since the solver treats the two trees differently when it starts.
TEST(MaxFlow, ExpansionLikeGridsAgreeWithBoost) {
  std::mt19937 rng(31);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  for (int trial = 0; trial < 12; ++trial) {
    RandomGraphSpec spec;
    spec.rows = 48 + 7 * trial;
    spec.cols = 90 - 5 * trial;
    spec.zero_fraction = 0.2;
    spec.isolated_fraction = 0.1;
    spec.max_cap = 2.0f;
    GridGraph g = random_graph(spec, rng);
    const bool prefer_sink = trial % 2 == 0;
    for (int i = 0; i < g.size(); ++i) {
      if (g.source_cap[i] == 0.0f && g.sink_cap[i] == 0.0f) continue;  // keeps isolated nodes isolated
      if (unit(rng) < 0.85f) {
        const float strong = 2.0f + 6.0f * unit(rng);
        const float weak = unit(rng) < 0.5f ? 0.0f : 0.02f * unit(rng);
        g.sink_cap[i] = prefer_sink ? strong : weak;
        g.source_cap[i] = prefer_sink ? weak : strong;
      }
    }
    SCOPED_TRACE("trial " + std::to_string(trial));
    expect_all_solvers_agree(g);
  }
}

// Like the expansion moves of a real reconstruction, whose data term is weak: terminal arcs are small
// next to the arcs between pixels, so the flow travels long paths between many small roots, which is
// where the solver moves terminal flow between neighbouring roots.
TEST(MaxFlow, WeakTerminalGridsAgreeWithBoost) {
  std::mt19937 rng(47);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  for (int trial = 0; trial < 16; ++trial) {
    RandomGraphSpec spec;
    spec.rows = 20 + 5 * trial;
    spec.cols = 95 - 4 * trial;
    spec.zero_fraction = trial % 4 == 0 ? 0.0 : 0.1;
    spec.isolated_fraction = trial % 2 == 0 ? 0.0 : 0.1;
    spec.integer_caps = trial % 3 == 2;
    spec.max_cap = 2.0f;
    GridGraph g = random_graph(spec, rng);
    // Integer terminals stay integers (0 or 1) so that exact ties remain common.
    for (int i = 0; i < g.size(); ++i) {
      const bool to_source = unit(rng) < 0.5f;
      float& kept = to_source ? g.source_cap[i] : g.sink_cap[i];
      float& dropped = to_source ? g.sink_cap[i] : g.source_cap[i];
      kept = spec.integer_caps ? float(kept > 3.0f) : 0.05f * kept;
      dropped = 0.0f;
    }
    SCOPED_TRACE("trial " + std::to_string(trial));
    expect_all_solvers_agree(g);
  }
}

// Deep trees and many orphans: a single source corner and a single sink corner force every unit of
// flow across the whole grid.
TEST(MaxFlow, CornerToCornerGridsAgreeWithBoost) {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 20; ++trial) {
    RandomGraphSpec spec;
    spec.rows = 20 + trial;
    spec.cols = 40 - trial;
    spec.zero_fraction = trial % 2 ? 0.2 : 0.0;
    GridGraph g = random_graph(spec, rng);
    std::fill(g.source_cap.begin(), g.source_cap.end(), 0.0f);
    std::fill(g.sink_cap.begin(), g.sink_cap.end(), 0.0f);
    g.source_cap.front() = 1000.0f;
    g.sink_cap.back() = 1000.0f;
    SCOPED_TRACE("trial " + std::to_string(trial));
    expect_all_solvers_agree(g);
  }
}

// Capacities over many orders of magnitude, with non-representable decimals and exact ties, check
// that float rounding neither stalls nor breaks the solvers.
TEST(MaxFlow, WideDynamicRangeAgreesWithBoost) {
  std::mt19937 rng(99);
  std::uniform_int_distribution<int> exponent(-20, 8);
  std::uniform_int_distribution<int> tenths(0, 9);
  for (int trial = 0; trial < 40; ++trial) {
    GridGraph g;
    g.reset(1 + trial % 30, 30 - trial % 20);
    for (auto* v : {&g.source_cap, &g.sink_cap, &g.right_cap, &g.right_rev_cap, &g.down_cap, &g.down_rev_cap}) {
      for (float& x : *v) x = trial % 2 ? std::ldexp(1.0f, exponent(rng)) : 0.1f * float(tenths(rng));
    }
    SCOPED_TRACE("trial " + std::to_string(trial));
    expect_all_solvers_agree(g);
  }
}

// One solver object must give exactly what a fresh one gives, whatever it solved before.
TEST(MaxFlow, ReusedSolverMatchesFreshSolver) {
  std::mt19937 rng(4242);
  const int sizes[][2] = {{40, 40}, {3, 50}, {50, 3}, {1, 1}, {40, 40}, {0, 0}, {17, 23}, {23, 17}, {1, 40},
                          {40, 1}, {31, 31}, {2, 2}, {40, 40}};
  for (const MaxFlowKind kind : kAllKinds) {
    SCOPED_TRACE(to_string(kind));
    const auto reused = make_maxflow_solver(kind);
    for (int round = 0; round < 3; ++round) {
      for (const auto& size : sizes) {
        RandomGraphSpec spec;
        spec.rows = size[0];
        spec.cols = size[1];
        spec.zero_fraction = 0.3 * round;
        spec.isolated_fraction = 0.1;
        spec.integer_caps = round == 1;
        const GridGraph g = random_graph(spec, rng);
        const Solution expected = solve_fresh(kind, g);
        const Solution got = solve_copy(*reused, g);
        EXPECT_EQ(got.flow, expected.flow) << size[0] << " x " << size[1];
        EXPECT_EQ(got.sink_side, expected.sink_side) << size[0] << " x " << size[1];
      }
    }
  }
}

TEST(MaxFlow, SolverRecoversAfterRejectingAGraph) {
  std::mt19937 rng(5);
  RandomGraphSpec spec;
  spec.rows = 30;
  spec.cols = 20;
  spec.zero_fraction = 0.2;
  const GridGraph valid = random_graph(spec, rng);
  GridGraph invalid = valid;
  invalid.right_cap[spec.cols * 20 + 3] = -0.5f;  // found only after two thirds of the rows
  for (const MaxFlowKind kind : kAllKinds) {
    SCOPED_TRACE(to_string(kind));
    const auto solver = make_maxflow_solver(kind);
    GridGraph scratch = invalid;
    std::vector<std::uint8_t> sink_side;
    EXPECT_THROW(solver->solve(scratch, sink_side), InvalidArgument);
    const Solution expected = solve_fresh(kind, valid);
    const Solution got = solve_copy(*solver, valid);
    EXPECT_EQ(got.flow, expected.flow);
    EXPECT_EQ(got.sink_side, expected.sink_side);
  }
}

TEST(MaxFlow, RejectsBadCapacitiesAndShapes) {
  for (const MaxFlowKind kind : kAllKinds) {
    SCOPED_TRACE(to_string(kind));
    const auto solver = make_maxflow_solver(kind);
    std::vector<std::uint8_t> sink_side;
    GridGraph g;
    g.reset(3, 4);
    g.down_rev_cap[5] = -1.0f;
    EXPECT_THROW(solver->solve(g, sink_side), InvalidArgument);
    g.reset(3, 4);
    g.sink_cap[11] = std::nanf("");
    EXPECT_THROW(solver->solve(g, sink_side), InvalidArgument);
    g.reset(3, 4);
    g.source_cap[0] = INFINITY;
    EXPECT_THROW(solver->solve(g, sink_side), InvalidArgument);
    g.reset(3, 4);
    g.right_cap.pop_back();
    EXPECT_THROW(solver->solve(g, sink_side), InvalidArgument);
  }
}

TEST(MaxFlow, ParsesKindNames) {
  for (const MaxFlowKind kind : kAllKinds) EXPECT_EQ(parse_maxflow_kind(to_string(kind)), kind);
  EXPECT_EQ(parse_maxflow_kind("grid"), MaxFlowKind::Grid);
  EXPECT_EQ(parse_maxflow_kind("opencv"), MaxFlowKind::OpenCV);
  EXPECT_EQ(parse_maxflow_kind("boost"), MaxFlowKind::Boost);
  EXPECT_THROW(parse_maxflow_kind("foo"), InvalidArgument);
  EXPECT_THROW(parse_maxflow_kind("Grid"), InvalidArgument);
  try {
    parse_maxflow_kind("foo");
  } catch (const InvalidArgument& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("foo"), std::string::npos) << message;
    EXPECT_NE(message.find("grid, opencv, boost"), std::string::npos) << message;
  }
}

}  // namespace
}  // namespace shadecut
