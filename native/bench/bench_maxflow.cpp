// Max-flow solvers on graphs shaped like ShadeCut's expansion moves, synthetic and real.
#include <shadecut/graphcut/alpha_expansion.hpp>
#include <shadecut/graphcut/convexity_cut.hpp>
#include <shadecut/graphcut/grid_graph.hpp>
#include <shadecut/support/light.hpp>
#include <shadecut/local/local_shape.hpp>
#include <reference_maxflow.hpp>
#include <shadecut/pipeline/reconstruct.hpp>
#include <shadecut/support/render.hpp>
#include <shadecut/graphcut/tilt_energy.hpp>

#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <map>
#include <memory>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

namespace shadecut {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr int kLabels = 36;

// Chord distance between two tilts, scaled by the slant: the style of ShadeCut's pairwise term.
double tilt_cost(double slant, int label_a, int label_b) {
  return std::sin(slant) * std::abs(std::sin((label_a - label_b) * kPi / kLabels));
}

// The expansion move of one tilt label on a noisy sphere seen from above, late in the optimization:
// tilt is the azimuth around the centre (36 labels) and slant grows towards the rim. The background
// in the corners and the pixels that already have the label take no part (isolated nodes), about
// 12% of the grid. Most other pixels strongly prefer to keep their label
// (large sink capacity, source capacity ~0); the rest are undecided. Pairwise capacities follow the
// expansion construction V(l_p, a) + V(a, l_q) - V(l_p, l_q), with each direction using its own
// pixel's slant, so they lie in [0, 2] and differ between the two directions.
GridGraph expansion_graph(int side) {
  std::mt19937 rng(12345);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::normal_distribution<double> tilt_noise(0.0, 0.15);
  const int alpha = 7;
  const double centre = 0.5 * (side - 1);
  const double radius = 0.56 * side;

  const int n = side * side;
  std::vector<int> label(n);
  std::vector<double> slant(n);
  std::vector<bool> in_move(n);
  for (int r = 0; r < side; ++r) {
    for (int c = 0; c < side; ++c) {
      const int i = r * side + c;
      const double dx = c - centre;
      const double dy = centre - r;
      const double rho = std::hypot(dx, dy) / radius;
      const double tilt = std::atan2(dy, dx) + tilt_noise(rng);
      label[i] = int(std::lround(tilt / (2 * kPi) * kLabels) % kLabels + kLabels) % kLabels;
      in_move[i] = rho < 1.0 && label[i] != alpha;
      slant[i] = std::asin(std::min(rho, 0.999));
    }
  }

  GridGraph g;
  g.reset(side, side);
  for (int i = 0; i < n; ++i) {
    if (!in_move[i]) continue;
    if (unit(rng) < 0.8) {
      g.sink_cap[i] = float(2.0 + 6.0 * unit(rng));
      g.source_cap[i] = unit(rng) < 0.5 ? 0.0f : float(0.02 * unit(rng));
    } else {
      g.sink_cap[i] = float(2.0 * unit(rng));
      g.source_cap[i] = float(2.0 * unit(rng));
    }
  }
  const auto pair_caps = [&](int p, int q, float& forward, float& reverse) {
    if (!in_move[p] || !in_move[q]) return;
    const auto cap = [&](double s) {
      return float(tilt_cost(s, label[p], alpha) + tilt_cost(s, alpha, label[q]) - tilt_cost(s, label[p], label[q]));
    };
    forward = std::max(0.0f, cap(slant[p]));
    reverse = std::max(0.0f, cap(slant[q]));
  };
  for (int r = 0; r < side; ++r) {
    for (int c = 0; c < side; ++c) {
      const int i = r * side + c;
      if (c + 1 < side) pair_caps(i, i + 1, g.right_cap[i], g.right_rev_cap[i]);
      if (r + 1 < side) pair_caps(i, i + side, g.down_cap[i], g.down_rev_cap[i]);
    }
  }
  return g;
}

const GridGraph& cached_expansion_graph(int side) {
  static std::map<int, GridGraph> cache;
  auto it = cache.find(side);
  if (it == cache.end()) it = cache.emplace(side, expansion_graph(side)).first;
  return it->second;
}

void BM_MaxFlow(benchmark::State& state, MaxFlowKind kind, int side) {
  const GridGraph& original = cached_expansion_graph(side);
  const auto solver = make_maxflow_solver(kind);
  GridGraph graph;
  std::vector<std::uint8_t> sink_side;
  for (auto _ : state) {
    // solve() may overwrite the capacities with residuals, so every run gets a fresh copy.
    state.PauseTiming();
    graph = original;
    state.ResumeTiming();
    benchmark::DoNotOptimize(solver->solve(graph, sink_side));
    benchmark::ClobberMemory();
  }
  state.counters["nodes/s"] = benchmark::Counter(double(side) * side, benchmark::Counter::kIsIterationInvariantRate);
}

// Keeps a copy of every graph it is asked to cut, then lets a real solver cut it, so that the
// expansion moves of a reconstruction can be replayed outside it.
class RecordingSolver final : public MaxFlowSolver {
 public:
  explicit RecordingSolver(std::vector<GridGraph>& graphs)
      : graphs_(graphs), solver_(make_maxflow_solver()) {}
  double solve(GridGraph& graph, std::vector<std::uint8_t>& sink_side) override {
    graphs_.push_back(graph);
    return solver_->solve(graph, sink_side);
  }

 private:
  std::vector<GridGraph>& graphs_;
  std::unique_ptr<MaxFlowSolver> solver_;
};

// Reconstructing Mozart (256 x 256, light (1, 0, 1), K = 36, graphcut's default parameters): its
// energy and the labelling after the convexity cut, where alpha-expansion starts.
// The benchmark binary has no data directory compiled in, so the file is found next to this source.
struct MozartProblem {
  LocalShape local;
  TiltEnergy energy;
  std::vector<int> start;
};

const MozartProblem& mozart_problem() {
  static const MozartProblem problem = [] {
    const std::string file = __FILE__;
    const std::string path = file.substr(0, file.rfind("native/bench/")) + "data/mozart/moz256.depth";
    std::ifstream in(path);
    if (!in) throw std::runtime_error("cannot open " + path);
    constexpr int kSize = 256;
    ImageF depth = ImageF::Zero(kSize, kSize);
    for (Eigen::Index i = 0; i < depth.size(); ++i) {
      if (!(in >> depth.data()[i])) throw std::runtime_error("short depth file " + path);
    }
    const Mask mask = depth > 0.0f;
    const Eigen::Vector3d light(1, 0, 1);
    const ImageF image = render_lambertian(normals_from_depth(depth, mask), light, 1.0, mask);
    const LightFrame frame = LightFrame::from_direction(light);
    const MethodDefaults defaults = method_defaults(Method::GraphCut);
    LocalShape local = local_shape(image, mask, frame, 1.0, defaults.min_curvature);
    TiltEnergyParams params;
    params.labels = kLabels;
    params.data_weight = ReconstructOptions().data_weight * unary_scale(mask);
    params.undefined_weight = defaults.undefined_weight * unary_scale(mask);
    params.data_term = DataTerm::Soft;
    TiltEnergy energy(local, frame, mask, params);
    std::vector<int> labelling = energy.convex_labelling();
    const auto solver = make_maxflow_solver();
    convexity_cut(energy, local, labelling, *solver);
    return MozartProblem{std::move(local), std::move(energy), std::move(labelling)};
  }();
  return problem;
}

// The expansion moves of the first two cycles of that reconstruction: these, not the synthetic
// graphs, are what the solvers face in practice (each one cut from scratch).
const std::vector<GridGraph>& mozart_move_graphs() {
  static const std::vector<GridGraph> graphs = [] {
    const MozartProblem& problem = mozart_problem();
    std::vector<int> labelling = problem.start;
    std::vector<GridGraph> recorded;
    RecordingSolver recorder(recorded);
    alpha_expansion(problem.energy, labelling, recorder, 2);
    return recorded;
  }();
  return graphs;
}

// The grid solver without the promise that lets alpha-expansion keep flows between moves.
class ColdSolver final : public MaxFlowSolver {
 public:
  double solve(GridGraph& graph, std::vector<std::uint8_t>& sink_side) override { return grid_->solve(graph, sink_side); }

 private:
  std::unique_ptr<MaxFlowSolver> grid_ = make_maxflow_solver();
};

// The whole alpha-expansion of that reconstruction, to convergence: every move cut from scratch
// (cold) or from the label's kept flow, finished by a sparse repair where few pixels changed (kept).
void BM_AlphaExpansionMozart(benchmark::State& state, bool keep_flows) {
  const MozartProblem& problem = mozart_problem();
  const auto grid = make_maxflow_solver();
  ColdSolver cold;
  AlphaExpansionStats stats;
  for (auto _ : state) {
    std::vector<int> labelling = problem.start;
    stats = alpha_expansion(problem.energy, labelling, keep_flows ? *grid : static_cast<MaxFlowSolver&>(cold), 20);
    benchmark::DoNotOptimize(labelling.data());
  }
  state.counters["moves"] = stats.moves;
  state.counters["repaired"] = stats.repaired_moves;
  state.counters["energy"] = stats.energy_per_cycle.back();
}

// One iteration solves every recorded move once.
void BM_MaxFlowRealMoves(benchmark::State& state, MaxFlowKind kind) {
  const std::vector<GridGraph>& originals = mozart_move_graphs();
  const auto solver = make_maxflow_solver(kind);
  std::vector<GridGraph> graphs;
  std::vector<std::uint8_t> sink_side;
  double total_flow = 0.0;
  for (auto _ : state) {
    state.PauseTiming();
    graphs = originals;
    state.ResumeTiming();
    total_flow = 0.0;
    for (GridGraph& graph : graphs) total_flow += solver->solve(graph, sink_side);
    benchmark::DoNotOptimize(total_flow);
  }
  state.counters["moves"] = double(originals.size());
  // Printed so that a solver skipping work shows up as a different total.
  state.counters["total_flow"] = total_flow;
}

const bool registered = [] {
  for (const MaxFlowKind kind : {MaxFlowKind::Grid, MaxFlowKind::OpenCV, MaxFlowKind::Boost}) {
    for (const int side : {256, 512, 1024}) {
      const std::string name = "BM_MaxFlow/" + to_string(kind) + "/" + std::to_string(side);
      benchmark::RegisterBenchmark(name.c_str(), BM_MaxFlow, kind, side)->Unit(benchmark::kMillisecond);
    }
  }
  benchmark::RegisterBenchmark("BM_AlphaExpansionMozart/cold", BM_AlphaExpansionMozart, false)->Unit(benchmark::kMillisecond);
  benchmark::RegisterBenchmark("BM_AlphaExpansionMozart/kept", BM_AlphaExpansionMozart, true)->Unit(benchmark::kMillisecond);
  // Boost takes seconds per move on these graphs, too slow to replay them all.
  for (const MaxFlowKind kind : {MaxFlowKind::Grid, MaxFlowKind::OpenCV}) {
    const std::string name = "BM_MaxFlowRealMoves/" + to_string(kind);
    benchmark::RegisterBenchmark(name.c_str(), BM_MaxFlowRealMoves, kind)->Unit(benchmark::kMillisecond);
  }
  return true;
}();

}  // namespace
}  // namespace shadecut
