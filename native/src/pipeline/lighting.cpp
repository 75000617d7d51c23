#include "pipeline/lighting.hpp"

#include <shadecut/estimate/estimate_albedo.hpp>
#include <shadecut/estimate/estimate_light.hpp>
#include <shadecut/pipeline/relief.hpp>
#include <shadecut/support/errors.hpp>
#include <shadecut/support/validate.hpp>

#include "support/stopwatch.hpp"

#include <cmath>

namespace shadecut::detail {

LightFrame choose_lighting(const ImageF& image, const Mask& mask, float brightest, const std::optional<Eigen::Vector3d>& light,
                           std::optional<double> albedo, const ReconstructOptions& options, const Progress& progress,
                           Reconstruction& result) {
  Eigen::Vector3d direction;
  if (light) {
    direction = *light;
  } else {
    progress.report(0.0, "light");
    const Stopwatch stopwatch;
    const LightMethod method = light_method_used(options);
    // The relief estimator takes its albedo from the relief's own brightest pixels.
    const std::optional<double> ceiling =
        albedo || method == LightMethod::Relief ? albedo : estimate_albedo(image, mask, options.albedo_method);
    const LightEstimate estimate = estimate_light(image, mask, method, ceiling);
    result.stats.seconds["light"] = stopwatch.seconds();
    result.stats.light_estimated = true;
    result.stats.light_uncertainty = estimate.uncertainty * 180.0 / M_PI;
    direction = estimate.light;
    // The estimators' albedo assumes a sphere's normals; a relief's comes from its median.
    if (!albedo && options.scene == SceneKind::Object) albedo = estimate.albedo;
  }
  const LightFrame frame = LightFrame::from_direction(direction);
  result.light = frame.direction;
  result.lights = {frame.direction};
  if (albedo) result.albedo = *albedo;
  else if (options.scene == SceneKind::Relief) result.albedo = relief_albedo(image, mask, frame.direction);
  else result.albedo = estimate_albedo(image, mask, options.albedo_method);
  check_albedo(result.albedo);
  if (brightest <= 1e-6f * result.albedo)
    throw InvalidArgument("shadecut: the image is dark everywhere in the mask compared with the albedo " +
                          number_text(result.albedo) + "; nothing to reconstruct");
  return frame;
}

}  // namespace shadecut::detail
