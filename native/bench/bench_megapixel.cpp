// The megapixel benchmark of the issue "A megapixel in about a second": a full-frame field of Gaussian
// bumps and dents (no mask: the whole frame), light (0.7, 0.2, 1), albedo 1, default settings, at 512,
// 1024 and 2048 pixels square, side by side in one run:
//   default_call         reconstruct() with ReconstructOptions{} (graph cut, coarse to fine, default
//                        integrator); counters: the stage milliseconds of result.stats;
//   fit_call             the default call with fit_shading on (the depth fitted to the image);
//   relief_call          the same as a relief (scene Relief, the light and albedo estimated), as
//                        the add-on's Subject Relief reads a photograph of a wall;
//   relief_light         the relief call's light estimate alone (estimate_light, LightMethod::Relief);
//   graph_cut            global_step() alone, with the parameters reconstruct() hands it;
//   reference_expansion  the straightforward alpha-expansion of the energy global_step minimizes at its
//                        finest level, at full resolution with every label: a fresh
//                        cv::detail::GCGraph per move, from the convex labelling, at most 3 cycles.
// graph_cut and reference_expansion are timed from the image to the labelling (local shape, energy,
// cuts); their counter "energy" is the full-resolution energy of the labelling they reach, taken
// outside the timing, so that the speed-up is read next to what it costs in energy.
//
// Run: ./build/native/shadecut_bench --benchmark_filter=BM_Megapixel --benchmark_repetitions=3
// or scripts/benchmark_megapixel.py, which prints the medians and their ratios as a table.
#include "bench_bump_field.hpp"
#include "bench_stages.hpp"

#include <shadecut/estimate/estimate_light.hpp>
#include <shadecut/graphcut/global_step.hpp>
#include <shadecut/graphcut/maxflow.hpp>
#include <shadecut/pipeline/reconstruct.hpp>
#include <shadecut/support/render.hpp>

#include <benchmark/benchmark.h>
#include <opencv2/core.hpp>  // before gcgraph.hpp, which uses CV_Assert without including it
#include <opencv2/imgproc/detail/gcgraph.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <random>
#include <string>
#include <vector>

namespace {

using namespace shadecut;
using Clock = std::chrono::steady_clock;

constexpr double kAlbedo = 1.0;
constexpr int kReferenceCycles = 3;

Eigen::Vector3d scene_light() { return {0.7, 0.2, 1.0}; }

double seconds_since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

struct BumpField {
  ImageF image;
  Mask mask;
};

// The benchmarks' bump field rendered under scene_light(); cached per size.
const BumpField& bump_field(int size) {
  static std::map<int, BumpField> cache;
  const auto found = cache.find(size);
  if (found != cache.end()) return found->second;
  const ImageF depth = bench::bump_field_depth(size);
  const Mask mask = Mask::Constant(size, size, true);
  BumpField field{render_lambertian(normals_from_depth(depth, mask), scene_light(), kAlbedo, mask), mask};
  return cache.emplace(size, std::move(field)).first->second;
}

std::unique_ptr<MaxFlowSolver> make_graph_cut_solver() { return make_maxflow_solver(); }

// The energy global_step builds at its finest level, every label open (no band).
TiltEnergy full_resolution_energy(const BumpField& field, const LightFrame& frame, const GlobalStepParams& params) {
  const LocalShape local = local_shape(field.image, field.mask, frame, kAlbedo, params.min_curvature);
  TiltEnergyParams energy_params = params.energy;
  const double scale = unary_scale(field.mask);
  energy_params.data_weight *= scale;
  energy_params.undefined_weight *= scale;
  return TiltEnergy(local, frame, field.mask, energy_params);
}

struct ReferenceStats {
  std::vector<double> energy_per_cycle;  // the start's, then after every cycle
  int accepted_moves = 0;
  double maxflow_seconds = 0.0;
};

// The labelling after the minimum cut of one expansion move of `alpha` (Boykov, Veksler & Zabih 2001),
// on a graph built from nothing. A node is a pixel that may switch to alpha: source side = it keeps
// its label, sink side = it takes alpha. Pixels where alpha is prohibited or already taken keep
// their label, and their pairwise terms fall on their neighbours' terminal weights.
std::vector<int> expansion_move(const TiltEnergy& energy, int alpha, const std::vector<int>& labelling,
                                double& maxflow_seconds) {
  const int rows = energy.rows(), cols = energy.cols(), pixels = rows * cols;
  std::vector<int> node(std::size_t(pixels), -1);
  int nodes = 0;
  for (int p = 0; p < pixels; ++p)
    if (energy.mask().data()[p] && labelling[std::size_t(p)] != alpha && energy.allowed(p, alpha))
      node[std::size_t(p)] = nodes++;
  if (nodes == 0) return labelling;

  // Per node, what taking alpha costs more than keeping the label.
  std::vector<double> switch_cost(static_cast<std::size_t>(nodes));
  for (int p = 0; p < pixels; ++p) {
    const int n = node[std::size_t(p)];
    if (n >= 0)
      switch_cost[std::size_t(n)] = double(energy.data_cost(p, alpha)) - energy.data_cost(p, labelling[std::size_t(p)]);
  }
  // Two grid edges per node at most, each stored by addEdges as two arcs.
  cv::detail::GCGraph<double> graph(unsigned(nodes), 4u * unsigned(nodes));
  for (int n = 0; n < nodes; ++n) graph.addVtx();
  auto add_pair = [&](int p, int q, double weight) {
    const int node_p = node[std::size_t(p)], node_q = node[std::size_t(q)];
    if (weight == 0.0 || (node_p < 0 && node_q < 0)) return;
    const int a = labelling[std::size_t(p)], b = labelling[std::size_t(q)];
    const double kept = weight * energy.label_distance(a, b);          // V(a, b)
    const double p_takes = weight * energy.label_distance(alpha, b);   // V(alpha, b)
    const double q_takes = weight * energy.label_distance(a, alpha);   // V(a, alpha)
    if (node_q < 0) {
      switch_cost[std::size_t(node_p)] += p_takes - kept;
    } else if (node_p < 0) {
      switch_cost[std::size_t(node_q)] += q_takes - kept;
    } else {
      // Kolmogorov & Zabih, with x = 1 for "takes alpha" and V(alpha, alpha) = 0:
      // V = kept + (p_takes - kept) x_p - p_takes x_q + (q_takes + p_takes - kept) (1 - x_p) x_q.
      // The last coefficient is >= 0 because V is a metric; the clamp only absorbs float rounding.
      switch_cost[std::size_t(node_p)] += p_takes - kept;
      switch_cost[std::size_t(node_q)] -= p_takes;
      graph.addEdges(node_p, node_q, std::max(0.0, q_takes + p_takes - kept), 0.0);
    }
  };
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) {
      const int p = r * cols + c;
      if (c + 1 < cols) add_pair(p, p + 1, energy.weight_right(p));
      if (r + 1 < rows) add_pair(p, p + cols, energy.weight_down(p));
    }
  }
  // A node on the sink side is cut from the source, paying the source arc: the cost of taking alpha.
  for (int n = 0; n < nodes; ++n)
    graph.addTermWeights(n, std::max(0.0, switch_cost[std::size_t(n)]), std::max(0.0, -switch_cost[std::size_t(n)]));
  const Clock::time_point start = Clock::now();
  graph.maxFlow();
  maxflow_seconds += seconds_since(start);

  std::vector<int> moved = labelling;
  for (int p = 0; p < pixels; ++p)
    if (node[std::size_t(p)] >= 0 && !graph.inSourceSegment(node[std::size_t(p)])) moved[std::size_t(p)] = alpha;
  return moved;
}

// Cycles over all labels until a cycle gains nothing or `max_cycles` cycles; a move is kept only if
// it lowers the energy.
ReferenceStats reference_expansion(const TiltEnergy& energy, std::vector<int>& labelling, int max_cycles) {
  ReferenceStats stats;
  double current = energy.energy(labelling);
  stats.energy_per_cycle.push_back(current);
  for (int cycle = 0; cycle < max_cycles; ++cycle) {
    for (int alpha = 0; alpha < energy.labels(); ++alpha) {
      std::vector<int> moved = expansion_move(energy, alpha, labelling, stats.maxflow_seconds);
      const double moved_energy = energy.energy(moved);
      if (moved_energy < current) {
        labelling = std::move(moved);
        current = moved_energy;
        ++stats.accepted_moves;
      }
    }
    const double before = stats.energy_per_cycle.back();
    stats.energy_per_cycle.push_back(current);
    if (!(current < before)) break;
  }
  return stats;
}

void time_call(benchmark::State& state, const ReconstructOptions& options) {
  const BumpField& field = bump_field(int(state.range(0)));
  std::map<std::string, double> stage_seconds;
  for (auto _ : state) {
    const Reconstruction result = reconstruct(field.image, scene_light(), &field.mask, kAlbedo, options);
    bench::add_stages(result.stats, stage_seconds);
    benchmark::DoNotOptimize(result.depth.data());
  }
  bench::report_stages(state, stage_seconds);
}

void BM_DefaultCall(benchmark::State& state) { time_call(state, ReconstructOptions{}); }

// The default call with the depth fitted to the image: what fit_shading on by default would cost.
void BM_FitCall(benchmark::State& state) {
  ReconstructOptions options;
  options.fit_shading = true;
  time_call(state, options);
}

// The same field as a photograph of a wall: Subject Relief, the light estimated (the add-on's relief).
void BM_ReliefCall(benchmark::State& state) {
  const BumpField& field = bump_field(int(state.range(0)));
  ReconstructOptions options;
  options.scene = SceneKind::Relief;
  std::map<std::string, double> stage_seconds;
  for (auto _ : state) {
    const Reconstruction result = reconstruct(field.image, std::nullopt, &field.mask, std::nullopt, options);
    bench::add_stages(result.stats, stage_seconds);
    benchmark::DoNotOptimize(result.depth.data());
  }
  bench::report_stages(state, stage_seconds);
}

void BM_ReliefLight(benchmark::State& state) {
  const BumpField& field = bump_field(int(state.range(0)));
  for (auto _ : state) {
    const LightEstimate estimate = estimate_light(field.image, field.mask, LightMethod::Relief, std::nullopt);
    benchmark::DoNotOptimize(estimate.light.data());
  }
}

void BM_GraphCut(benchmark::State& state) {
  const BumpField& field = bump_field(int(state.range(0)));
  const LightFrame frame = LightFrame::from_direction(scene_light());
  const GlobalStepParams params = global_step_params(ReconstructOptions{});
  GlobalStepResult solved;
  for (auto _ : state) {
    const auto solver = make_graph_cut_solver();
    const Clock::time_point start = Clock::now();
    solved = global_step(field.image, field.mask, frame, kAlbedo, params, *solver);
    state.SetIterationTime(seconds_since(start));
  }
  state.counters["levels"] = solved.levels;
  state.counters["cycles"] = solved.expansion.cycles;
  state.counters["energy"] = full_resolution_energy(field, frame, params).energy(solved.labelling);
}

void BM_ReferenceExpansion(benchmark::State& state) {
  const BumpField& field = bump_field(int(state.range(0)));
  const LightFrame frame = LightFrame::from_direction(scene_light());
  const GlobalStepParams params = global_step_params(ReconstructOptions{});
  ReferenceStats stats;
  double energy_seconds = 0.0, total_seconds = 0.0, maxflow_seconds = 0.0;
  for (auto _ : state) {
    const Clock::time_point start = Clock::now();
    const TiltEnergy energy = full_resolution_energy(field, frame, params);
    energy_seconds += seconds_since(start);
    std::vector<int> labelling = energy.convex_labelling();
    stats = reference_expansion(energy, labelling, kReferenceCycles);
    maxflow_seconds += stats.maxflow_seconds;
    const double seconds = seconds_since(start);
    total_seconds += seconds;
    state.SetIterationTime(seconds);
  }
  const double iterations = double(state.iterations());
  state.counters["energy_build_ms"] = 1e3 * energy_seconds / iterations;
  state.counters["expansion_ms"] = 1e3 * (total_seconds - energy_seconds) / iterations;
  state.counters["maxflow_ms"] = 1e3 * maxflow_seconds / iterations;
  state.counters["cycles"] = double(stats.energy_per_cycle.size() - 1);
  state.counters["accepted_moves"] = stats.accepted_moves;
  state.counters["start_energy"] = stats.energy_per_cycle.front();
  state.counters["energy"] = stats.energy_per_cycle.back();
}

void register_megapixel_benchmarks() {
  const struct {
    const char* name;
    void (*function)(benchmark::State&);
    bool manual_time;
  } variants[] = {
      {"default_call", BM_DefaultCall, false},
      {"fit_call", BM_FitCall, false},
      {"relief_call", BM_ReliefCall, false},
      {"relief_light", BM_ReliefLight, false},
      {"graph_cut", BM_GraphCut, true},
      {"reference_expansion", BM_ReferenceExpansion, true},
  };
  for (const auto& variant : variants) {
    auto* bench = benchmark::RegisterBenchmark((std::string("BM_Megapixel/") + variant.name).c_str(), variant.function);
    bench->Arg(512)->Arg(1024)->Arg(2048)->Unit(benchmark::kMillisecond)->Iterations(1);
    if (variant.manual_time) bench->UseManualTime();
    else bench->UseRealTime();
  }
}

const bool registered = (register_megapixel_benchmarks(), true);

}  // namespace
