// Whole-call and per-stage timings of reconstruct() at 256, 512 and 1024 pixels square (the
// comparison methods brooks_horn and tsai_shah at 256 and 512), default parameters of each method;
// upwind: the viscosity-solution baseline (to 1024: it is meant for photographs too);
// *_exact: one level, every label (coarse_to_fine_band = -1); graphcut_band2: a band of two label steps;
// graphcut_fit: fit_shading on (its stage's share in the fit_shading_ms counter);
// graphcut_one_labelling: viscosity_weight 0 (the pulled labelling's share; pulled_kept counts its wins).
//
// Run: ./build/native/shadecut_bench --benchmark_filter=Reconstruct --benchmark_repetitions=3
//        --benchmark_report_aggregates_only=true
#include "bench_stages.hpp"

#include <shadecut/pipeline/reconstruct.hpp>
#include <shadecut/support/render.hpp>

#include <benchmark/benchmark.h>

#include <cmath>
#include <map>
#include <string>

namespace {

using namespace shadecut;

// A sphere carrying bumps and dents, so that every stage has real work: convex and concave regions,
// attached shadow and a round silhouette. Cached per size.
struct BenchScene {
  ImageF image;
  Mask mask;
};

const BenchScene& scene_of_size(int size) {
  static std::map<int, BenchScene> cache;
  auto found = cache.find(size);
  if (found != cache.end()) return found->second;
  const double radius = 0.45 * size, centre = 0.5 * (size - 1);
  ImageF depth = ImageF::Zero(size, size);
  Mask mask = Mask::Constant(size, size, false);
  for (int r = 0; r < size; ++r) {
    for (int c = 0; c < size; ++c) {
      const double x = c - centre, y = centre - r, h2 = radius * radius - x * x - y * y;
      if (h2 <= 0.0) continue;
      mask(r, c) = true;
      double z = std::sqrt(h2);
      for (int k = 0; k < 6; ++k) {
        const double angle = k * M_PI / 3.0, bx = 0.5 * radius * std::cos(angle), by = 0.5 * radius * std::sin(angle);
        const double sigma = 0.12 * radius, amplitude = (k % 2 ? -0.1 : 0.1) * radius;
        z += amplitude * std::exp(-((x - bx) * (x - bx) + (y - by) * (y - by)) / (2 * sigma * sigma));
      }
      depth(r, c) = float(z);
    }
  }
  const Eigen::Vector3d light(1, 0, 1);
  BenchScene scene{render_lambertian(normals_from_depth(depth, mask), light, 1.0, mask), mask};
  return cache.emplace(size, std::move(scene)).first->second;
}

void BM_Reconstruct(benchmark::State& state, Method method, Integrator integrator, int band, bool fit, double viscosity) {
  const int size = int(state.range(0));
  const BenchScene& scene = scene_of_size(size);
  ReconstructOptions options;
  options.method = method;
  options.integrator = integrator;
  options.coarse_to_fine_band = band;
  options.fit_shading = fit;
  options.viscosity_weight = viscosity;
  std::map<std::string, double> stage_seconds;
  int iterations = 0;
  bool pulled_kept = false;
  for (auto _ : state) {
    const Reconstruction result = reconstruct(scene.image, Eigen::Vector3d(1, 0, 1), &scene.mask, 1.0, options);
    bench::add_stages(result.stats, stage_seconds);
    iterations = result.stats.iterations;
    pulled_kept = result.stats.pulled_kept;
    benchmark::DoNotOptimize(result.depth.data());
  }
  bench::report_stages(state, stage_seconds);
  state.counters["iterations"] = iterations;
  state.counters["pulled_kept"] = pulled_kept;
}

void register_reconstruct_benchmarks() {
  struct Case {
    const char* name;
    Method method;
    Integrator integrator;
    std::initializer_list<int> sizes;
    int band = ReconstructOptions{}.coarse_to_fine_band;
    bool fit = ReconstructOptions{}.fit_shading;
    double viscosity = ReconstructOptions{}.viscosity_weight;
  };
  const Case cases[] = {
      {"graphcut/frankot_chellappa", Method::GraphCut, Integrator::FrankotChellappa, {256, 512, 1024}},
      {"graphcut/poisson", Method::GraphCut, Integrator::Poisson, {256, 512, 1024}},
      {"graphcut_one_labelling/poisson", Method::GraphCut, Integrator::Poisson, {256, 512, 1024},
       ReconstructOptions{}.coarse_to_fine_band, false, 0.0},
      {"graphcut_fit/poisson", Method::GraphCut, Integrator::Poisson, {256, 512, 1024}, ReconstructOptions{}.coarse_to_fine_band, true},
      {"graphcut_exact/frankot_chellappa", Method::GraphCut, Integrator::FrankotChellappa, {256, 512, 1024}, -1},
      {"graphcut_band2/frankot_chellappa", Method::GraphCut, Integrator::FrankotChellappa, {256, 512, 1024}, 2},
      {"graphcut_two_exact/frankot_chellappa", Method::GraphCutTwo, Integrator::FrankotChellappa, {256, 512}, -1},
      {"graphcut_two/frankot_chellappa", Method::GraphCutTwo, Integrator::FrankotChellappa, {256, 512, 1024}},
      {"lee_rosenfeld/frankot_chellappa", Method::LeeRosenfeld, Integrator::FrankotChellappa, {256, 512, 1024}},
      {"brooks_horn/frankot_chellappa", Method::BrooksHorn, Integrator::FrankotChellappa, {256, 512}},
      {"tsai_shah/frankot_chellappa", Method::TsaiShah, Integrator::FrankotChellappa, {256, 512}},
      {"upwind/frankot_chellappa", Method::Upwind, Integrator::FrankotChellappa, {256, 512, 1024}},
  };
  for (const Case& c : cases) {
    auto* bench = benchmark::RegisterBenchmark((std::string("BM_Reconstruct/") + c.name).c_str(), BM_Reconstruct,
                                               c.method, c.integrator, c.band, c.fit, c.viscosity);
    for (int size : c.sizes) bench->Arg(size);
    bench->Unit(benchmark::kMillisecond)->Iterations(1)->UseRealTime();
  }
}

const bool registered = (register_reconstruct_benchmarks(), true);

}  // namespace
