// Several photographs (issue 45: "eight 4-megapixel photographs in at most 2 s after reading them"):
// the benchmarks' bump field, full frame, rendered Lambertian (albedo 0.8) under 4 or 8 lights at
// slant 40 degrees evenly around the viewer, and reconstruct() given the photographs and their lights,
// timed from the observations in memory to the result; counters: the stage milliseconds of
// result.stats. BM_PhotographsWithHighlights adds a Blinn-Phong highlight to each photograph, as real
// photographs have: where one of four lit photographs shines, its four fits go to the candidate cut.
//
// Run: ./build/native/shadecut_bench --benchmark_filter=BM_Photographs --benchmark_repetitions=3
#include "bench_bump_field.hpp"
#include "bench_stages.hpp"

#include <shadecut/pipeline/reconstruct.hpp>
#include <shadecut/support/render.hpp>

#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

namespace {

using namespace shadecut;

constexpr double kSlantDegrees = 40.0;
constexpr double kAlbedo = 0.8;
// The highlights of BM_PhotographsWithHighlights: peak intensity (the albedo is kAlbedo) and shininess.
constexpr double kHighlightStrength = 0.5;
constexpr double kShininess = 50.0;

// `count` photographs of the bump field at `size` pixels, the first lit from the top, with or without
// highlights; cached.
const std::vector<Observation>& photographs(int count, int size, bool highlights) {
  static std::map<std::tuple<int, int, bool>, std::vector<Observation>> cache;
  const auto found = cache.find({count, size, highlights});
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
    if (highlights) {
      const Eigen::Vector3f half = (light + Eigen::Vector3d::UnitZ()).normalized().cast<float>();
      for (Eigen::Index p = 0; p < normals.size(); ++p)
        photograph.image.data()[p] += float(kHighlightStrength *
                                            std::pow(std::max(0.0f, normals.xyz.row(p).dot(half.transpose())), kShininess));
    }
    photograph.light = light;
    observations.push_back(std::move(photograph));
  }
  return cache.emplace(std::make_tuple(count, size, highlights), std::move(observations)).first->second;
}

void time_reconstruct(benchmark::State& state, bool highlights) {
  const std::vector<Observation>& observations = photographs(int(state.range(0)), int(state.range(1)), highlights);
  std::map<std::string, double> stages;
  for (auto _ : state) {
    const Reconstruction result = reconstruct(observations, nullptr, std::nullopt, ReconstructOptions{});
    bench::add_stages(result.stats, stages);
    benchmark::DoNotOptimize(result.depth.data());
  }
  bench::report_stages(state, stages);
}

void BM_Photographs(benchmark::State& state) { time_reconstruct(state, false); }
void BM_PhotographsWithHighlights(benchmark::State& state) { time_reconstruct(state, true); }

BENCHMARK(BM_Photographs)->ArgNames({"photographs", "size"})->Args({4, 1024})->Args({8, 1024})->Args({8, 2048})
    ->Unit(benchmark::kMillisecond)->Iterations(1)->UseRealTime();
BENCHMARK(BM_PhotographsWithHighlights)->ArgNames({"photographs", "size"})->Args({4, 1024})->Args({8, 1024})
    ->Args({8, 2048})->Unit(benchmark::kMillisecond)->Iterations(1)->UseRealTime();

}  // namespace
