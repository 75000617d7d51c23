// brooks_horn: Brooks & Horn's variational iteration (baselines/brooks_horn.hpp).
#include <shadecut/baselines/brooks_horn.hpp>
#include <shadecut/local/local_shape.hpp>

#include "pipeline/method_registry.hpp"
#include "pipeline/surface_rules.hpp"
#include "support/stopwatch.hpp"

#include <algorithm>

namespace shadecut::detail {

NormalMap solve_brooks_horn(const MethodInput& input, ReconstructStats& stats) {
  const Stopwatch stopwatch;
  input.progress.report(0.0, "brooks_horn");
  const MethodDefaults defaults = method_defaults(Method::BrooksHorn);
  const ReconstructOptions& options = input.options;
  BrooksHornParams params;
  // Per pixel the smoothness term reads |grad n|^2 h^2 while the brightness term stays put, so the
  // weight grows with the object's area to keep the same minimum at every resolution; small objects
  // are held at the weight where the sweeps still converge.
  const double per_pixel = 1.0 / (unary_scale(input.mask) * unary_scale(input.mask));
  params.smoothness = std::max(kStableSmoothness, options.smoothness.value_or(defaults.smoothness) * per_pixel);
  params.iterations = options.iterations.value_or(defaults.iterations);
  params.tolerance = options.tolerance.value_or(defaults.tolerance);
  params.occluding_contour = edge_is_outline(options);
  BrooksHornResult solved = brooks_horn(input.image, input.mask, input.frame, input.albedo, params, input.progress);
  stats.iterations = solved.iterations;
  stats.seconds["brooks_horn"] = stopwatch.seconds();
  return std::move(solved.normals);
}

}  // namespace shadecut::detail
