// The paint separated from the shading first when the albedo method reads it per pixel, the shape
// then read from the shading image of one albedo; how far the photograph is from the result last.
#include "pipeline/paint.hpp"

#include <shadecut/estimate/estimate_reflectance.hpp>
#include <shadecut/photometric/residual_map.hpp>
#include <shadecut/pipeline/stage_params.hpp>
#include <shadecut/support/render.hpp>
#include <shadecut/support/validate.hpp>

#include "pipeline/option_checks.hpp"
#include "pipeline/reconstruct_shading.hpp"
#include "support/parallel.hpp"
#include "support/stopwatch.hpp"

#include <map>
#include <string>

namespace shadecut::detail {

namespace {

// retinex: options.retinex_passes times the paint read (after the first pass against the surface
// the pass before found) and the shape read from the shading image it leaves.
Reconstruction read_paint_and_shape(const ImageF& image, const ColourImage* colour, const std::optional<Eigen::Vector3d>& light,
                                    const Mask& mask, std::optional<double> albedo, const ReconstructOptions& options) {
  ReconstructOptions shading_options = options;
  shading_options.highlight_threshold = highlight_threshold_used(options);
  shading_options.albedo_method = AlbedoMethod::TopFit;
  // Every stage's seconds summed over the passes, the paint's as "albedo".
  std::map<std::string, double> seconds;
  ImageF relative;
  Reconstruction result;
  const int passes = options.retinex_passes;
  for (int pass = 0; pass < passes; ++pass) {
    const Stopwatch stopwatch;
    std::optional<ImageF> shading;
    if (pass > 0)
      shading = render_lambertian(normals_from_depth(result.depth, result.mask), result.light, 1.0, result.mask);
    const double start = double(pass) / passes;
    relative = estimate_reflectance(image, colour, mask, reflectance_params(options), Progress(options.progress).range(start, start),
                                    shading ? &*shading : nullptr)
                   .relative;
    // Each pass reports its reconstruction as its own share of the call.
    if (options.progress)
      shading_options.progress = [callback = options.progress, start, passes](double fraction, const std::string& stage) {
        return callback(start + fraction / passes, stage);
      };
    const double paint_seconds = stopwatch.seconds();
    seconds["albedo"] += paint_seconds;
    seconds["total"] += paint_seconds;
    result = reconstruct_shading(mask.select(image / relative, 0.0f), light, &mask, albedo, shading_options);
    for (const auto& [stage, stage_seconds] : result.stats.seconds) seconds[stage] += stage_seconds;
  }
  result.albedo_map = mask.select(relative * float(result.albedo), 0.0f);
  result.stats.seconds = seconds;
  return result;
}

}  // namespace

Reconstruction reconstruct_painted(const ImageF& image, const ColourImage* colour, const std::optional<Eigen::Vector3d>& light,
                                   const Mask* mask_in, std::optional<double> albedo, const ReconstructOptions& options) {
  // Every stage of the call, the paint and the residual included, on the threads the options ask for.
  const ThreadCountScope threads(options.threads);
  // Before the estimates, whose own complaint about a bad albedo ("the image is dark everywhere")
  // would name the wrong problem.
  if (albedo) check_albedo(*albedo);
  Reconstruction result;
  if (!albedo && options.albedo_method == AlbedoMethod::Retinex) {
    check_image(image);
    const Mask mask = mask_in ? *mask_in : Mask::Constant(image.rows(), image.cols(), true);
    check_mask(mask, image);
    check_options(options, mask);  // before the paint is read, not after
    result = read_paint_and_shape(image, colour, light, mask, albedo, options);
  } else {
    result = reconstruct_shading(image, light, mask_in, albedo, options);
    result.albedo_map = result.mask.select(ImageF::Constant(image.rows(), image.cols(), float(result.albedo)), 0.0f);
  }
  if (colour) result.albedo_colour = reflectance_colour(image, *colour, result.mask, result.albedo_map);
  result.residual = residual_map({image}, {result.light}, NearLamps{}, result.normals, result.albedo_map, result.mask);
  return result;
}

}  // namespace shadecut::detail
