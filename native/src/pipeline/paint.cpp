// reconstruct(): the paint separated from the shading first when the albedo method reads it per pixel,
// the shape then read from the shading image of one albedo.
#include <shadecut/estimate/estimate_reflectance.hpp>
#include <shadecut/pipeline/cut_out.hpp>
#include <shadecut/pipeline/reconstruct.hpp>
#include <shadecut/support/errors.hpp>
#include <shadecut/support/render.hpp>
#include <shadecut/support/validate.hpp>

#include "pipeline/reconstruct_shading.hpp"
#include "support/stopwatch.hpp"

#include <cmath>
#include <map>
#include <optional>

namespace shadecut {

namespace {

void check_paint_options(const ReconstructOptions& options) {
  auto finite = [](double value) { return std::isfinite(value); };
  if (!(options.retinex_chroma_edge >= 0.0) || !finite(options.retinex_chroma_edge))
    throw InvalidArgument("shadecut: retinex_chroma_edge must be finite and >= 0; got " + number_text(options.retinex_chroma_edge));
  if (!finite(options.retinex_intensity_edge))
    throw InvalidArgument("shadecut: retinex_intensity_edge must be finite (<= 0: off)");
  if (!finite(options.retinex_highlight))
    throw InvalidArgument("shadecut: retinex_highlight must be finite (<= 0: none)");
  if (!(options.retinex_shadow >= 0.0 && options.retinex_shadow < 1.0))
    throw InvalidArgument("shadecut: retinex_shadow must be in [0, 1) (a share of the albedo); got " + number_text(options.retinex_shadow));
  if (options.retinex_rim < 0)
    throw InvalidArgument("shadecut: retinex_rim must be >= 0; got " + std::to_string(options.retinex_rim));
  if (options.retinex_passes < 1)
    throw InvalidArgument("shadecut: retinex_passes must be >= 1; got " + std::to_string(options.retinex_passes));
}

Reconstruction reconstruct_masked(const ImageF& image, const ColourImage* colour, const std::optional<Eigen::Vector3d>& light,
                                  const Mask* mask_in, std::optional<double> albedo, const ReconstructOptions& options) {
  // Before the estimates, whose own complaint about a bad albedo ("the image is dark everywhere")
  // would name the wrong problem.
  if (albedo) check_albedo(*albedo);
  const bool painted = !albedo && options.albedo_method == AlbedoMethod::Retinex;
  Reconstruction result;
  if (painted) {
    check_image(image);
    const Mask mask = mask_in ? *mask_in : Mask::Constant(image.rows(), image.cols(), true);
    check_mask(mask, image);
    detail::check_options(options, mask);  // before the paint is read, not after
    ReconstructOptions shading_options = options;
    shading_options.highlight_threshold = highlight_threshold_used(options);
    shading_options.albedo_method = AlbedoMethod::TopFit;
    // Every stage's seconds summed over the passes, the paint's as "albedo".
    std::map<std::string, double> seconds;
    ImageF relative;
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
      result = detail::reconstruct_shading(mask.select(image / relative, 0.0f), light, &mask, albedo, shading_options);
      for (const auto& [stage, stage_seconds] : result.stats.seconds) seconds[stage] += stage_seconds;
    }
    result.albedo_map = mask.select(relative * float(result.albedo), 0.0f);
    result.stats.seconds = seconds;
  } else {
    result = detail::reconstruct_shading(image, light, mask_in, albedo, options);
    result.albedo_map = result.mask.select(ImageF::Constant(image.rows(), image.cols(), float(result.albedo)), 0.0f);
  }
  if (colour) result.albedo_colour = reflectance_colour(image, *colour, result.mask, result.albedo_map);
  return result;
}

// An object given without a mask is cut out of its background first (ReconstructOptions::cut_out).
Reconstruction reconstruct_image(const ImageF& image, const ColourImage* colour, const std::optional<Eigen::Vector3d>& light,
                                 const Mask* mask_in, std::optional<double> albedo, const ReconstructOptions& options) {
  check_paint_options(options);
  if (mask_in || options.scene != SceneKind::Object || !options.cut_out)
    return reconstruct_masked(image, colour, light, mask_in, albedo, options);
  // The options and the memory first: a call refused for its size is refused at once, not after the cut.
  detail::check_options(options, Mask::Constant(image.rows(), image.cols(), true));
  const Stopwatch stopwatch;
  const CutOut cut = cut_out(image, colour);
  const double seconds = stopwatch.seconds();
  Reconstruction result =
      reconstruct_masked(image, colour, light, cut.outcome == CutOutOutcome::Found ? &cut.mask : nullptr, albedo, options);
  result.stats.cut_out = cut.outcome;
  result.stats.cut_out_contrast = cut.outline_contrast;
  result.stats.cut_out_message = cut.message;
  result.stats.seconds["cut_out"] = seconds;
  result.stats.seconds["total"] += seconds;
  return result;
}

}  // namespace

ReflectanceParams reflectance_params(const ReconstructOptions& options) {
  ReflectanceParams params;
  params.chroma_edge = options.retinex_chroma_edge;
  params.intensity_edge = options.retinex_intensity_edge;
  params.rim = options.scene == SceneKind::Object ? options.retinex_rim : 0;
  params.highlight = options.retinex_highlight;
  params.shadow = options.retinex_shadow;
  return params;
}

ImageF luminance(const ColourImage& colour) {
  for (const ImageF& channel : colour.channel)
    if (channel.rows() != colour.rows() || channel.cols() != colour.cols())
      throw InvalidArgument("shadecut: the colour image's channels differ in shape");
  return (colour.channel[0].cast<double>() * kLuminanceWeights[0] + colour.channel[1].cast<double>() * kLuminanceWeights[1] +
          colour.channel[2].cast<double>() * kLuminanceWeights[2])
      .cast<float>();
}

Reconstruction reconstruct(const ImageF& image, const std::optional<Eigen::Vector3d>& light, const Mask* mask,
                           std::optional<double> albedo, const ReconstructOptions& options) {
  return reconstruct_image(image, nullptr, light, mask, albedo, options);
}

Reconstruction reconstruct(const ColourImage& image, const std::optional<Eigen::Vector3d>& light, const Mask* mask,
                           std::optional<double> albedo, const ReconstructOptions& options) {
  const ImageF intensity = luminance(image);
  for (const ImageF& channel : image.channel) {
    check_image(channel);
    if (channel.minCoeff() < 0.0f) throw InvalidArgument("shadecut: the image has negative values; linear RGB is >= 0");
  }
  return reconstruct_image(intensity, &image, light, mask, albedo, options);
}

}  // namespace shadecut
