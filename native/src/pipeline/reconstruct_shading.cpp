#include "pipeline/reconstruct_shading.hpp"

#include <shadecut/integrate/surface_from_normals.hpp>
#include <shadecut/pipeline/relief.hpp>
#include <shadecut/integrate/shadow_fill.hpp>
#include <shadecut/pipeline/stage_params.hpp>
#include <shadecut/refine/fit_shading.hpp>
#include <shadecut/support/errors.hpp>
#include <shadecut/support/render.hpp>
#include <shadecut/support/validate.hpp>

#include "pipeline/lighting.hpp"
#include "pipeline/method_registry.hpp"
#include "pipeline/option_checks.hpp"
#include "pipeline/orientation.hpp"
#include "pipeline/surface_rules.hpp"
#include "support/stopwatch.hpp"

#include <iomanip>
#include <optional>
#include <sstream>

namespace shadecut::detail {

namespace {

// The shares of the call's progress spent on the normals and on them plus the integration (graphcut
// with the Poisson integrator at a megapixel, docs/benchmarks.md); fit_shading takes the rest.
constexpr double kNormalsShare = 0.6;
constexpr double kIntegratedShare = 0.8;

// Whether the depth is fitted to the image after integration: graphcut only, where it was tuned
// (graphcut_two's integrated depth is a worse start: the fit raised its evaluation mean; the
// comparison methods stay as published), and not for a tiling surface.
bool fits_shading(const ReconstructOptions& options) {
  return options.fit_shading && options.method == Method::GraphCut && !options.seamless;
}

// fit_shading on result.depth (the integrated depth), over the `fitted` pixels; the normals become
// the fitted depth's.
void fit_depth_to_image(const ImageF& image, const Mask& fitted, const LightFrame& frame, const ReconstructOptions& options,
                        const Progress& progress, Reconstruction& result) {
  const Stopwatch stopwatch;
  const FitShadingStats stats = fit_shading(result.depth, image, result.mask, fitted, frame.direction, result.albedo,
                                            fit_shading_params(options), progress);
  result.normals = normals_from_depth(result.depth, result.mask);
  result.stats.shading_residual_before = stats.residual_before;
  result.stats.shading_residual_after = stats.residual_after;
  result.stats.fit_steps = stats.steps;
  result.stats.seconds["fit_shading"] = stopwatch.seconds();
}

// The image every stage reads: a relief's thin bright lines are paint (bright_lines), and the image
// says nothing of the slope there, as in a shadow, so every stage reads them as one (light, albedo,
// normals, the fill).
ImageF stage_image(const ImageF& input, const Mask& mask, const ReconstructOptions& options) {
  if (options.scene != SceneKind::Relief) return input;
  return bright_lines(input, mask, options.paint_line_width, options.paint_line_contrast)
      .select(ImageF::Zero(input.rows(), input.cols()), input);
}

// A relief's depth finished (finish_relief) and its normals made its finished depth's: what the mesh
// shows. The labelling's own normals carry the convex/concave creases it puts on flat ground, on the
// coarse levels' grid, which the integration smooths away (docs/method.md, Reliefs). A seamless
// relief's already are its depth's.
void finish_surface(ImageF& depth, NormalMap& normals, const Mask& mask, const ReconstructOptions& options,
                    double detail_size) {
  finish_relief(depth, mask, options, detail_size);
  if (options.scene == SceneKind::Relief && !options.seamless) normals = normals_from_depth(depth, mask);
}

// The chosen method's normals made a surface (filled, integrated, fitted when asked, finished as a
// relief) in `result`. With the fit, returns the surface before it, finished alike: what the
// orientation is judged on (judge_orientation).
std::optional<Surface> make_surface(const ImageF& image, const Mask& unreliable, const LightFrame& frame,
                                    const ReconstructOptions& options, const Progress& progress, Reconstruction& result) {
  const Mask& mask = result.mask;
  NormalMap normals = method_entry(options.method)
                          .solve({image, mask, unreliable, frame, result.albedo, options, progress.range(0.0, kNormalsShare)}, result.stats);
  progress.report(kNormalsShare, "integration");
  const Stopwatch integration;
  Surface surface = surface_from_normals(std::move(normals), mask, unreliable, edge_is_outline(options), options.integrator,
                                         options.seamless, options.max_slope, progress.range(kNormalsShare, kIntegratedShare));
  result.stats.seconds["integration"] = integration.seconds();
  result.stats.shadow_pixels = surface.filled_pixels;
  result.stats.detail_size = detail_size_used(image, mask, options);
  if (!fits_shading(options)) {
    progress.report(1.0, "integration");
    finish_surface(surface.depth, surface.normals, mask, options, result.stats.detail_size);
    result.normals = std::move(surface.normals);
    result.depth = std::move(surface.depth);
    return std::nullopt;
  }
  result.depth = surface.depth;  // fit_depth_to_image makes the normals the fitted depth's
  fit_depth_to_image(image, mask && !unreliable, frame, options, progress.range(kIntegratedShare, 1.0), result);
  finish_surface(result.depth, result.normals, mask, options, result.stats.detail_size);
  finish_surface(surface.depth, surface.normals, mask, options, result.stats.detail_size);
  return surface;
}

// ReconstructStats::brighter_than_albedo and albedo_message.
void judge_albedo(const ImageF& image, const Mask& mask, bool given, double albedo, ReconstructStats& stats) {
  stats.brighter_than_albedo = double((mask && image > float(albedo)).count()) / double(mask.count());
  if (!given || stats.brighter_than_albedo <= kBrighterThanAlbedoShare) return;
  std::ostringstream message;
  message << std::fixed << std::setprecision(0) << 100.0 * stats.brighter_than_albedo
          << " % of the pixels reconstructed are brighter than the albedo given (" << std::setprecision(3) << albedo
          << "), which no surface of that albedo can be: they were read as facing the light. Give a larger albedo, or "
             "let it be read from the image";
  stats.albedo_message = message.str();
}

}  // namespace

Reconstruction reconstruct_shading(const ImageF& input, const std::optional<Eigen::Vector3d>& light, const Mask* mask_in,
                                   std::optional<double> albedo, const ReconstructOptions& options) {
  const Stopwatch total;
  check_image(input);
  const Mask mask = mask_in ? *mask_in : Mask::Constant(input.rows(), input.cols(), true);
  check_mask(mask, input);
  if (input.minCoeff() < 0.0f) throw InvalidArgument("shadecut: the image has negative intensities; linear intensity is >= 0");
  check_options(options, mask);
  const ImageF image = stage_image(input, mask, options);
  // Cheap, and before the estimates that cost a pass of median filtering over the image.
  const float brightest = mask.select(image, 0.0f).maxCoeff();
  if (!(brightest > 0.0f))
    throw InvalidArgument("shadecut: the image is dark everywhere in the mask (zero); nothing to reconstruct");
  const Progress progress(options.progress);

  Reconstruction result;
  result.mask = mask;
  const LightFrame frame = choose_lighting(image, mask, brightest, light, albedo, options, progress, result);
  judge_albedo(image, mask, albedo.has_value(), result.albedo, result.stats);
  const Mask unreliable =
      unreliable_pixels(image, mask, result.albedo, shadow_threshold_used(options), highlight_threshold_used(options));
  const std::optional<Surface> before_fit = make_surface(image, unreliable, frame, options, progress, result);
  const Stopwatch orientation;
  judge_orientation(image, unreliable, frame, options, before_fit ? before_fit->depth : result.depth,
                    before_fit ? before_fit->normals : result.normals, result);
  result.stats.seconds["orientation"] = orientation.seconds();
  result.stats.seconds["total"] = total.seconds();
  return result;
}

}  // namespace shadecut::detail
