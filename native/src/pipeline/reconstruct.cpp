#include <shadecut/pipeline/reconstruct.hpp>

#include <shadecut/baselines/brooks_horn.hpp>
#include <shadecut/support/errors.hpp>
#include <shadecut/graphcut/global_step.hpp>
#include <shadecut/support/light.hpp>
#include <shadecut/local/local_shape.hpp>
#include <shadecut/refine/fit_shading.hpp>
#include <shadecut/pipeline/relief.hpp>
#include <shadecut/support/render.hpp>
#include <shadecut/pipeline/shadow_fill.hpp>
#include <shadecut/integrate/surface_from_normals.hpp>
#include <shadecut/baselines/tsai_shah.hpp>
#include <shadecut/baselines/upwind.hpp>
#include <shadecut/support/downsample.hpp>
#include <shadecut/support/memory.hpp>
#include <shadecut/support/validate.hpp>

#include "pipeline/reconstruct_shading.hpp"
#include "support/enum_names.hpp"
#include "support/parallel.hpp"
#include "support/stopwatch.hpp"


namespace shadecut {

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

// The relative intensity at or below which a pixel counts as shadow; < 0 (none) when shadows are not filled.
double shadow_threshold_used(const ReconstructOptions& options) {
  return options.fill_shadows ? options.shadow_threshold : -1.0;
}

// Whether the mask's edge is the object's outline (an occluding contour): never for a relief.
bool edge_is_outline(const ReconstructOptions& options) {
  return options.occluding_contour && options.scene == SceneKind::Object;
}

// The detail size of a relief's call (ReconstructStats::detail_size): NaN for objects, seamless
// output and detail_size < 0, and for a uniform image, which has no scale.
double detail_size_used(const ImageF& image, const Mask& mask, const ReconstructOptions& options) {
  const double none = std::numeric_limits<double>::quiet_NaN();
  if (options.scene != SceneKind::Relief || options.seamless || options.detail_size < 0.0) return none;
  if (options.detail_size > 0.0) return options.detail_size;
  const double size = options.detail_scale_factor * relief_scale(image, mask);
  return std::isfinite(size) ? size : none;
}

// A relief made what a relief is: on a flat carrier facing the viewer, without the forms larger than
// its detail (the integration's drift). Seamless output tiles as it is and is left alone.
void finish_relief(ImageF& depth, const Mask& mask, const ReconstructOptions& options, double detail_size) {
  if (options.seamless || options.scene != SceneKind::Relief) return;
  flatten_relief(depth, mask);
  if (std::isfinite(detail_size)) damp_large_forms(depth, mask, detail_size);
}

// The orientation is judged at an object size of at most this many pixels: a surface and its
// inversion differ in how their large forms render, which survives block means, and at full size the
// judgement cost as much as the call's integration (docs/benchmarks.md).
constexpr double kOrientationObjectSize = 256.0;

// Normals averaged over factor x factor blocks (where the whole block is in `mask`), renormalized.
NormalMap block_mean_normals(const NormalMap& normals, const Mask& mask, int factor) {
  std::array<ImageF, 3> small;
  Mask small_mask;
  for (int axis = 0; axis < 3; ++axis) {
    ImageF plane(normals.rows, normals.cols);
    for (Eigen::Index i = 0; i < normals.size(); ++i) plane.data()[i] = normals.xyz(i, axis);
    Downsampled shrunk = downsample(plane, mask, factor, 1.0);
    small[std::size_t(axis)] = std::move(shrunk.image);
    small_mask = std::move(shrunk.mask);
  }
  NormalMap out(int(small_mask.rows()), int(small_mask.cols()));
  for (Eigen::Index i = 0; i < out.size(); ++i) {
    const Eigen::Vector3f n(small[0].data()[i], small[1].data()[i], small[2].data()[i]);
    out.xyz.row(i) = small_mask.data()[i] && n.norm() > 0.0f ? n.normalized().transpose() : Eigen::RowVector3f(0, 0, 1);
  }
  return out;
}

// The orientation statistics of the result (ReconstructStats::orientation_residual, inverted_residual,
// orientation_ambiguous): its depth rendered, and the surface of its normals turned by pi about the
// light (n -> 2 (n . S) S - n, each normal's other one of the same brightness), made a surface as the
// result was (filled, integrated, flattened for a relief) and rendered, over the reliable pixels;
// both on block means when the object is larger than kOrientationObjectSize.
void judge_orientation(const ImageF& full_image, const Mask& full_unreliable, const LightFrame& frame,
                       const ReconstructOptions& options, Reconstruction& result) {
  const int factor = std::max(1, int(object_size(result.mask) / kOrientationObjectSize));
  // The block means, when there are blocks; the call's own images are only read.
  Downsampled small;
  ImageF small_depth;
  Mask small_unreliable;
  double detail_size = result.stats.detail_size;
  if (factor > 1) {
    // A block is unreliable when any of its pixels is; depth in pixel units shrinks with the pixels.
    small = downsample(full_image, result.mask, factor, 1.0);
    small_depth = downsample(result.depth, result.mask, factor, 1.0).image / float(factor);
    small_unreliable = downsample(full_unreliable.cast<float>(), result.mask, factor, 1.0).image > 0.0f && small.mask;
    detail_size /= factor;
  }
  NormalMap turned = factor > 1 ? block_mean_normals(result.normals, result.mask, factor) : result.normals;
  const ImageF& image = factor > 1 ? small.image : full_image;
  const ImageF& depth = factor > 1 ? small_depth : result.depth;
  const Mask& mask = factor > 1 ? small.mask : result.mask;
  const Mask& unreliable = factor > 1 ? small_unreliable : full_unreliable;
  const Eigen::Vector3f light = frame.direction.cast<float>();
  for (Eigen::Index i = 0; i < turned.size(); ++i) {
    if (!mask.data()[i]) continue;
    const Eigen::Vector3f n = turned.xyz.row(i).transpose();
    turned.xyz.row(i) = (2.0f * n.dot(light) * light - n).transpose();
  }
  Surface inverted = surface_from_normals(std::move(turned), mask, unreliable, edge_is_outline(options), options.integrator,
                                          options.seamless, options.max_slope);
  finish_relief(inverted.depth, mask, options, detail_size);
  const Mask counted = mask && !unreliable;
  auto residual = [&](const ImageF& rendered_depth) {
    return mean_brightness_residual(rendered_depth, image, mask, counted, frame.direction, result.albedo);
  };
  ReconstructStats& stats = result.stats;
  stats.orientation_residual = residual(depth);
  stats.inverted_residual = residual(inverted.depth);
  stats.orientation_ambiguous = stats.inverted_residual < kAmbiguousResidualRatio * stats.orientation_residual;
}

// The light frame and albedo used: given, or estimated from the image (an object's albedo with its
// estimated light; otherwise estimate_albedo's, or a relief's median). `brightest` is the largest
// masked intensity.
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
  if (albedo) result.albedo = *albedo;
  else if (options.scene == SceneKind::Relief) result.albedo = relief_albedo(image, mask, frame.direction);
  else result.albedo = estimate_albedo(image, mask, options.albedo_method);
  check_albedo(result.albedo);
  if (brightest <= 1e-6f * result.albedo)
    throw InvalidArgument("shadecut: the image is dark everywhere in the mask compared with the albedo " +
                          number_text(result.albedo) + "; nothing to reconstruct");
  return frame;
}

NormalMap brooks_horn_normals(const ImageF& image, const Mask& mask, const LightFrame& frame, double albedo,
                              const ReconstructOptions& options, const Progress& progress, ReconstructStats& stats) {
  const MethodDefaults defaults = method_defaults(Method::BrooksHorn);
  const double smoothness = options.smoothness.value_or(defaults.smoothness);
  if (!(smoothness > 0.0) || !std::isfinite(smoothness))
    throw InvalidArgument("shadecut: the smoothness of brooks_horn must be finite and > 0");
  BrooksHornParams params;
  // Per pixel the smoothness term reads |grad n|^2 h^2 while the brightness term stays put, so the
  // weight grows with the object's area to keep the same minimum at every resolution; small objects
  // are held at the weight where the sweeps still converge.
  const double per_pixel = 1.0 / (unary_scale(mask) * unary_scale(mask));
  params.smoothness = std::max(kStableSmoothness, smoothness * per_pixel);
  params.iterations = options.iterations.value_or(defaults.iterations);
  params.tolerance = options.tolerance.value_or(defaults.tolerance);
  params.occluding_contour = edge_is_outline(options);
  BrooksHornResult solved = brooks_horn(image, mask, frame, albedo, params, progress);
  stats.iterations = solved.iterations;
  return std::move(solved.normals);
}

}  // namespace

// A call's peak memory per pixel (docs/benchmarks.md, "Memory"): 120-167 bytes with coarse to
// fine, whatever the method; the exact alpha-expansion keeps every label's cost and flow per pixel too.
constexpr double kPeakBytesPerPixel = 180.0;
constexpr double kPeakBytesPerLabelPixel = 20.0;

std::uint64_t detail::estimated_peak_memory(const ReconstructOptions& options, std::int64_t pixels) {
  const bool graph_cut = options.method == Method::GraphCut || options.method == Method::GraphCutTwo;
  const bool every_label = graph_cut && options.coarse_to_fine_band < 0;
  return std::uint64_t(double(pixels) * (kPeakBytesPerPixel + (every_label ? options.labels * kPeakBytesPerLabelPixel : 0.0)));
}

void detail::check_options(const ReconstructOptions& options, const Mask& mask) {
  const std::uint64_t needed = estimated_peak_memory(options, std::int64_t(mask.size()));
  const std::uint64_t available = available_memory();
  if (needed > available)
    throw InvalidArgument("shadecut: this call needs about " + memory_text(needed) + " for " + std::to_string(mask.rows()) +
                          " x " + std::to_string(mask.cols()) + " pixels, but only " + memory_text(available) +
                          " can be allocated; give a smaller image (max_pixels, or the add-on's Max size)");
  if (options.threads < 0 || options.threads > kMaxThreads)
    throw InvalidArgument("shadecut: threads must be in 0 .. " + std::to_string(kMaxThreads) + " (0 = all cores); got " +
                          std::to_string(options.threads));
  if (options.labels < kMinLabels)
    throw InvalidArgument("shadecut: labels must be at least " + std::to_string(kMinLabels) + " (got " +
                          std::to_string(options.labels) + ")");
  if (!(options.viscosity_weight >= 0.0) || !std::isfinite(options.viscosity_weight))
    throw InvalidArgument("shadecut: viscosity_weight must be finite and >= 0; got " + number_text(options.viscosity_weight));
  if (!(options.fit_smoothness >= 0.0) || !std::isfinite(options.fit_smoothness))
    throw InvalidArgument("shadecut: fit_smoothness must be finite and >= 0; got " + number_text(options.fit_smoothness));
  // A NaN or negative threshold silently marked no pixel as shadow, 1 or more marked every pixel.
  if (!(options.shadow_threshold >= 0.0 && options.shadow_threshold < 1.0))
    throw InvalidArgument("shadecut: shadow_threshold must be in [0, 1) (a fraction of the albedo); got " +
                          number_text(options.shadow_threshold));
  if (options.highlight_threshold && !std::isfinite(*options.highlight_threshold))
    throw InvalidArgument("shadecut: highlight_threshold must be finite (<= 0: never); got " +
                          number_text(*options.highlight_threshold));
  if (options.paint_line_width < 0)
    throw InvalidArgument("shadecut: paint_line_width must be >= 0 pixels (< 2: off); got " + std::to_string(options.paint_line_width));
  if (!(options.paint_line_contrast > 1.0) || !std::isfinite(options.paint_line_contrast))
    throw InvalidArgument("shadecut: paint_line_contrast must be finite and > 1; got " + number_text(options.paint_line_contrast));
  if (!std::isfinite(options.detail_size))
    throw InvalidArgument("shadecut: detail_size must be finite (pixels; 0 = read from the image, < 0 = keep every form)");
  if (!(options.detail_scale_factor > 0.0) || !std::isfinite(options.detail_scale_factor))
    throw InvalidArgument("shadecut: detail_scale_factor must be finite and > 0; got " + number_text(options.detail_scale_factor));
  if (options.seamless && options.scene != SceneKind::Relief)
    throw InvalidArgument("shadecut: seamless output is for reliefs that fill the image; set scene to relief");
  if (options.seamless && !mask.all())
    throw InvalidArgument("shadecut: seamless output tiles the whole image, but the mask leaves " +
                          std::to_string(mask.size() - mask.count()) + " pixels out; give no mask");
}

GlobalStepParams global_step_params(const ReconstructOptions& options) {
  const MethodDefaults defaults = method_defaults(options.method);
  GlobalStepParams params;
  params.energy.labels = options.labels;
  params.energy.data_weight = options.data_weight;
  params.energy.undefined_weight = options.undefined_weight.value_or(defaults.undefined_weight);
  params.energy.contour_weight = edge_is_outline(options) ? options.contour_weight : 0.0;
  params.energy.data_term = options.method == Method::GraphCut ? DataTerm::Soft : DataTerm::TwoCandidates;
  params.energy.threads = detail::default_thread_count();
  params.min_curvature = options.min_curvature.value_or(defaults.min_curvature);
  params.max_cycles = options.max_cycles;
  params.tolerance = options.tolerance.value_or(defaults.tolerance);
  params.band = options.coarse_to_fine_band;
  params.band_radius = options.coarse_to_fine_radius;
  params.refine = options.refine;
  // Tuned for graphcut only (docs/parameters.md).
  params.viscosity_weight = options.method == Method::GraphCut ? options.viscosity_weight : 0.0;
  params.shadow_threshold = shadow_threshold_used(options);
  params.highlight_threshold = highlight_threshold_used(options);
  params.occluding_contour = edge_is_outline(options);
  params.max_slope = options.max_slope;
  return params;
}

FitShadingParams fit_shading_params(const ReconstructOptions& options) {
  FitShadingParams params;
  params.smoothness = options.fit_smoothness;
  return params;
}

namespace {

NormalMap graph_cut_normals(const ImageF& image, const Mask& mask, const LightFrame& frame, double albedo,
                            const ReconstructOptions& options, const Progress& progress, ReconstructStats& stats) {
  const auto solver = make_maxflow_solver();
  GlobalStepResult solved = global_step(image, mask, frame, albedo, global_step_params(options), *solver, progress);
  for (const auto& [stage, seconds] : solved.seconds) stats.seconds[stage] = seconds;
  stats.allowed_label_fraction = solved.allowed_label_fraction;
  stats.energy_per_cycle = solved.expansion.energy_per_cycle;
  stats.cycles = solved.expansion.cycles;
  stats.iterations = solved.expansion.cycles;
  stats.moves = solved.expansion.moves;
  stats.accepted_moves = solved.expansion.accepted_moves;
  stats.maxflow_seconds = solved.expansion.maxflow_seconds;
  stats.levels = solved.levels;
  stats.paper_residual = solved.paper_residual;
  stats.pulled_residual = solved.pulled_residual;
  stats.pulled_kept = solved.pulled_kept;
  stats.orientation_energy = solved.orientation_energy;
  stats.inverted_energy = solved.inverted_energy;
  return std::move(solved.normals);
}

// The normals of a method that solves for the depth (tsai_shah, upwind): `solve` is called with the
// iterations to run and returns its result; its stage is the method's name.
template <class Solve>
NormalMap depth_method_normals(Method method, const Mask& mask, const ReconstructOptions& options, const Progress& progress,
                               ReconstructStats& stats, Solve solve) {
  const Stopwatch stopwatch;
  const std::string stage = to_string(method);
  progress.report(0.0, stage);
  const auto solved = solve(options.iterations.value_or(method_defaults(method).iterations));
  stats.seconds[stage] = stopwatch.seconds();
  stats.iterations = solved.iterations;
  return normals_from_depth(solved.depth, mask);
}

// The normals of the chosen method; every stage's seconds go into the stats.
NormalMap solve_normals(const ImageF& image, const Mask& mask, const LightFrame& frame, double albedo,
                        const ReconstructOptions& options, const Progress& progress, ReconstructStats& stats) {
  const Stopwatch stopwatch;
  switch (options.method) {
    case Method::BrooksHorn: {
      progress.report(0.0, "brooks_horn");
      NormalMap normals = brooks_horn_normals(image, mask, frame, albedo, options, progress, stats);
      stats.seconds["brooks_horn"] = stopwatch.seconds();
      return normals;
    }
    case Method::TsaiShah:
      return depth_method_normals(Method::TsaiShah, mask, options, progress, stats, [&](int sweeps) {
        return tsai_shah(image, mask, frame, albedo, sweeps, progress);
      });
    case Method::Upwind:
      return depth_method_normals(Method::Upwind, mask, options, progress, stats, [&](int rounds) {
        return upwind(image, mask, frame, albedo, rounds, progress);
      });
    case Method::LeeRosenfeld: {
      progress.report(0.0, "local");
      const double min_curvature = options.min_curvature.value_or(method_defaults(Method::LeeRosenfeld).min_curvature);
      const LocalShape local = local_shape(image, mask, frame, albedo, min_curvature);
      stats.seconds["local"] = stopwatch.seconds();
      return convex_normals(local, frame, mask);
    }
    case Method::GraphCut:
    case Method::GraphCutTwo:
      return graph_cut_normals(image, mask, frame, albedo, options, progress, stats);
  }
  throw InvalidArgument("shadecut: unknown method");
}

}  // namespace

const std::vector<std::string>& scene_kind_names() {
  static const std::vector<std::string> names{"object", "relief"};
  return names;
}

SceneKind parse_scene_kind(const std::string& name) { return parse_enum<SceneKind>(scene_kind_names(), name, "scene kind"); }

std::string to_string(SceneKind kind) { return scene_kind_names().at(std::size_t(kind)); }

LightMethod light_method_used(const ReconstructOptions& options) {
  if (options.light_method) return *options.light_method;
  return options.scene == SceneKind::Relief ? LightMethod::Relief : LightMethod::ZhengChellappa;
}

const std::vector<std::string>& method_names() {
  static const std::vector<std::string> names{"graphcut", "graphcut_two", "lee_rosenfeld", "brooks_horn", "tsai_shah", "upwind"};
  return names;
}

Method parse_method(const std::string& name) { return parse_enum<Method>(method_names(), name, "method"); }

std::string to_string(Method method) { return method_names().at(std::size_t(method)); }

MethodDefaults method_defaults(Method method) {
  MethodDefaults defaults;
  switch (method) {
    case Method::GraphCut:
      defaults.min_curvature = 1.0;
      defaults.undefined_weight = 0.5;
      return defaults;
    case Method::GraphCutTwo:
      defaults.min_curvature = 2.0;
      defaults.undefined_weight = 0.2;
      return defaults;
    case Method::LeeRosenfeld:
      defaults.min_curvature = 2.0;
      return defaults;
    case Method::BrooksHorn:
      defaults.tolerance = 1e-5;
      defaults.iterations = 8000;
      defaults.smoothness = 0.3;
      return defaults;
    case Method::TsaiShah:
      defaults.iterations = 1;
      return defaults;
    case Method::Upwind:
      defaults.iterations = 3;
      return defaults;
  }
  throw InvalidArgument("shadecut: unknown method");
}

double highlight_threshold_used(const ReconstructOptions& options) {
  if (options.highlight_threshold) return *options.highlight_threshold;
  return options.albedo_method == AlbedoMethod::Retinex ? kRetinexHighlightThreshold : kHighlightThreshold;
}

Reconstruction detail::reconstruct_shading(const ImageF& input, const std::optional<Eigen::Vector3d>& light,
                                           const Mask* mask_in, std::optional<double> albedo,
                                           const ReconstructOptions& options) {
  const Stopwatch total;
  check_image(input);
  const Mask mask = mask_in ? *mask_in : Mask::Constant(input.rows(), input.cols(), true);
  check_mask(mask, input);
  if (input.minCoeff() < 0.0f) throw InvalidArgument("shadecut: the image has negative intensities; linear intensity is >= 0");
  detail::check_options(options, mask);
  // A relief's thin bright lines are paint (bright_lines): the image says nothing of the slope there,
  // as in a shadow, and every stage reads them as one (light, albedo, normals, the fill).
  const ImageF image =
      options.scene == SceneKind::Relief
          ? bright_lines(input, mask, options.paint_line_width, options.paint_line_contrast).select(ImageF::Zero(input.rows(), input.cols()), input)
          : input;
  // Cheap, and before the estimates that cost a pass of median filtering over the image.
  const float brightest = mask.select(image, 0.0f).maxCoeff();
  if (!(brightest > 0.0f))
    throw InvalidArgument("shadecut: the image is dark everywhere in the mask (zero); nothing to reconstruct");
  const Progress progress(options.progress);

  Reconstruction result;
  result.mask = mask;
  const LightFrame frame = choose_lighting(image, mask, brightest, light, albedo, options, progress, result);
  const detail::ThreadCountScope threads(options.threads);
  const Mask unreliable =
      unreliable_pixels(image, mask, result.albedo, shadow_threshold_used(options), highlight_threshold_used(options));
  NormalMap normals = solve_normals(image, mask, frame, result.albedo, options, progress.range(0.0, kNormalsShare), result.stats);
  progress.report(kNormalsShare, "integration");
  const Stopwatch integration;
  Surface surface = surface_from_normals(std::move(normals), mask, unreliable, edge_is_outline(options), options.integrator,
                                         options.seamless, options.max_slope, progress.range(kNormalsShare, kIntegratedShare));
  result.stats.seconds["integration"] = integration.seconds();
  result.normals = std::move(surface.normals);
  result.depth = std::move(surface.depth);
  result.stats.shadow_pixels = surface.filled_pixels;
  if (fits_shading(options)) {
    fit_depth_to_image(image, mask && !unreliable, frame, options, progress.range(kIntegratedShare, 1.0), result);
  } else {
    progress.report(1.0, "integration");
  }
  result.stats.detail_size = detail_size_used(image, mask, options);
  finish_relief(result.depth, mask, options, result.stats.detail_size);
  // A relief is a height field, and its normal map is its finished depth's: what the mesh shows. The
  // labelling's own normals carry the convex/concave creases it puts on flat ground, on the coarse
  // levels' grid, which the integration smooths away (docs/method.md, Reliefs). A seamless relief's
  // already are its depth's.
  if (options.scene == SceneKind::Relief && !options.seamless) result.normals = normals_from_depth(result.depth, mask);
  const Stopwatch orientation;
  judge_orientation(image, unreliable, frame, options, result);
  result.stats.seconds["orientation"] = orientation.seconds();
  result.stats.seconds["total"] = total.seconds();
  return result;
}

}  // namespace shadecut
