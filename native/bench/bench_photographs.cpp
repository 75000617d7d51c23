// Several photographs (issue 45: "eight 4-megapixel photographs in at most 2 s after reading them"):
// the benchmarks' bump field, full frame, rendered Lambertian (albedo 0.8) under 4 or 8 lights at
// slant 40 degrees evenly around the viewer, and reconstruct() given the photographs and their lights,
// timed from the observations in memory to the result; counters: the stage milliseconds of
// result.stats.
//
// Run: ./build/native/shadecut_bench --benchmark_filter=BM_Photographs --benchmark_repetitions=3
#include "bench_bump_field.hpp"
#include "bench_stages.hpp"

#include <shadecut/pipeline/reconstruct.hpp>
#include <shadecut/support/render.hpp>

#include <benchmark/benchmark.h>

#include <cmath>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace {

using namespace shadecut;

constexpr double kSlantDegrees = 40.0;
constexpr double kAlbedo = 0.8;

// `count` photographs of the bump field at `size` pixels, the first lit from the top; cached.
const std::vector<Observation>& photographs(int count, int size) {
  static std::map<std::pair<int, int>, std::vector<Observation>> cache;
  const auto found = cache.find({count, size});
  if (found != cache.end()) return found->second;
  const Mask mask = Mask::Constant(size, size, true);
  const NormalMap normals = normals_from_depth(bench::bump_field_depth(size), mask);
  std::vector<Observation> observations;
  const double slant = kSlantDegrees * M_PI / 180.0;
  for (int k = 0; k < count; ++k) {
    const double azimuth = M_PI / 2.0 + 2.0 * M_PI * k / count;
    const Eigen::Vector3d light(std::sin(slant) * std::cos(azimuth), std::sin(slant) * std::sin(azimuth), std::cos(slant));
    Observation photograph;
    photograph.image = render_lambertian(normals, light, kAlbedo, mask);
    photograph.light = light;
    observations.push_back(std::move(photograph));
  }
  return cache.emplace(std::make_pair(count, size), std::move(observations)).first->second;
}

void BM_Photographs(benchmark::State& state) {
  const std::vector<Observation>& observations = photographs(int(state.range(0)), int(state.range(1)));
  std::map<std::string, double> stages;
  for (auto _ : state) {
    const Reconstruction result = reconstruct(observations, nullptr, std::nullopt, ReconstructOptions{});
    bench::add_stages(result.stats, stages);
    benchmark::DoNotOptimize(result.depth.data());
  }
  bench::report_stages(state, stages);
}

BENCHMARK(BM_Photographs)->ArgNames({"photographs", "size"})->Args({4, 1024})->Args({8, 1024})->Args({8, 2048})
    ->Unit(benchmark::kMillisecond)->Iterations(1)->UseRealTime();

}  // namespace
