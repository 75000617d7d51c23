// lee_rosenfeld: the local step alone, every pixel's convex candidate (local/local_shape.hpp).
#include <shadecut/local/local_shape.hpp>

#include "pipeline/method_registry.hpp"
#include "support/stopwatch.hpp"

namespace shadecut::detail {

NormalMap solve_lee_rosenfeld(const MethodInput& input, ReconstructStats& stats) {
  const Stopwatch stopwatch;
  input.progress.report(0.0, "local");
  const double min_curvature = input.options.min_curvature.value_or(method_defaults(Method::LeeRosenfeld).min_curvature);
  const LocalShape local = local_shape(input.image, input.mask, input.frame, input.albedo, min_curvature);
  stats.seconds["local"] = stopwatch.seconds();
  return convex_normals(local, input.frame, input.mask);
}

}  // namespace shadecut::detail
