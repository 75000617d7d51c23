// tsai_shah, upwind and pentland: methods that solve for the depth (baselines/tsai_shah.hpp, upwind.hpp,
// pentland.hpp); their normals are the depth's.
#include <shadecut/baselines/pentland.hpp>
#include <shadecut/baselines/tsai_shah.hpp>
#include <shadecut/baselines/upwind.hpp>
#include <shadecut/support/render.hpp>

#include "pipeline/method_registry.hpp"
#include "support/stopwatch.hpp"

namespace shadecut::detail {

namespace {

// `solve` is called with the iterations to run and returns its result; its stage is the method's name.
template <class Solve>
NormalMap depth_method_normals(const MethodInput& input, ReconstructStats& stats, Solve solve) {
  const Stopwatch stopwatch;
  const Method method = input.options.method;
  const std::string stage = to_string(method);
  input.progress.report(0.0, stage);
  const auto solved = solve(input.options.iterations.value_or(method_defaults(method).iterations));
  stats.seconds[stage] = stopwatch.seconds();
  stats.iterations = solved.iterations;
  return normals_from_depth(solved.depth, input.mask);
}

}  // namespace

// Shadows, highlights and a relief's paint lines (read as shadow) say nothing of the slope: pentland reads
// them as flat ground, where their darkness would be read as a slope along the whole line of the light.
NormalMap solve_pentland(const MethodInput& input, ReconstructStats& stats) {
  const double smoothness = input.options.smoothness.value_or(method_defaults(Method::Pentland).smoothness);
  const Mask read = input.mask && !input.unreliable;
  return depth_method_normals(input, stats, [&](int solves) {
    return pentland(input.image, read, input.frame, input.albedo, smoothness, solves, input.progress);
  });
}

NormalMap solve_tsai_shah(const MethodInput& input, ReconstructStats& stats) {
  return depth_method_normals(input, stats, [&input](int sweeps) {
    return tsai_shah(input.image, input.mask, input.frame, input.albedo, sweeps, input.progress);
  });
}

NormalMap solve_upwind(const MethodInput& input, ReconstructStats& stats) {
  return depth_method_normals(input, stats, [&input](int rounds) {
    return upwind(input.image, input.mask, input.frame, input.albedo, rounds, input.progress);
  });
}

}  // namespace shadecut::detail
