#include <shadecut/reconstruct.hpp>

#include <shadecut/brooks_horn.hpp>
#include <shadecut/errors.hpp>
#include <shadecut/global_step.hpp>
#include <shadecut/light.hpp>
#include <shadecut/local_shape.hpp>
#include <shadecut/fit_shading.hpp>
#include <shadecut/relief.hpp>
#include <shadecut/render.hpp>
#include <shadecut/shadow_fill.hpp>
#include <shadecut/tsai_shah.hpp>
#include <shadecut/upwind.hpp>
#include <shadecut/validate.hpp>

#include "enum_names.hpp"
#include "parallel.hpp"
#include "stopwatch.hpp"


namespace shadecut {

namespace {

// The shares of the call's progress spent on the normals and on them plus the integration (graphcut
// with the Poisson integrator at a megapixel: about 0.8 s and 0.5 s); fit_shading takes the rest.
constexpr double kNormalsShare = 0.6;
constexpr double kIntegratedShare = 0.8;

// Whether the depth is fitted to the image after integration: graphcut only, where it was tuned
// (graphcut_two's integrated depth is a worse start: the fit raised its evaluation mean, 22.97 ->
// 25.12 deg, docs/results.md; the comparison methods stay as published), and not for a tiling surface.
bool fits_shading(const ReconstructOptions& options) {
  return options.fit_shading && options.method == Method::GraphCut && !options.seamless;
}

// fit_shading on result.depth (the integrated depth), over the `fitted` pixels; the normals become
// the fitted depth's.
void fit_depth_to_image(const ImageF& image, const Mask& fitted, const LightFrame& frame, const ReconstructOptions& options,
                        const Progress& progress, Reconstruction& result) {
  const Stopwatch stopwatch;
  FitShadingParams params;
  params.smoothness = options.fit_smoothness;
  const FitShadingStats stats =
      fit_shading(result.depth, image, result.mask, fitted, frame.direction, result.albedo, params, progress);
  result.normals = normals_from_depth(result.depth, result.mask);
  result.stats.shading_residual_before = stats.residual_before;
  result.stats.shading_residual_after = stats.residual_after;
  result.stats.fit_steps = stats.steps;
  result.stats.seconds["fit_shading"] = stopwatch.seconds();
}

// Whether the mask's edge is the object's outline (an occluding contour): never for a relief.
bool edge_is_outline(const ReconstructOptions& options) {
  return options.occluding_contour && options.scene == SceneKind::Object;
}

void check_options(const ReconstructOptions& options, const Mask& mask) {
  if (options.threads < 0 || options.threads > kMaxThreads)
    throw InvalidArgument("shadecut: threads must be in 0 .. " + std::to_string(kMaxThreads) + " (0 = all cores); got " +
                          std::to_string(options.threads));
  if (options.labels < kMinLabels)
    throw InvalidArgument("shadecut: labels must be at least " + std::to_string(kMinLabels) + " (got " +
                          std::to_string(options.labels) + ")");
  if (!(options.viscosity_weight >= 0.0) || !std::isfinite(options.viscosity_weight))
    throw InvalidArgument("shadecut: viscosity_weight must be finite and >= 0; got " + std::to_string(options.viscosity_weight));
  if (!(options.fit_smoothness >= 0.0) || !std::isfinite(options.fit_smoothness))
    throw InvalidArgument("shadecut: fit_smoothness must be finite and >= 0; got " + std::to_string(options.fit_smoothness));
  if (options.seamless && options.scene != SceneKind::Relief)
    throw InvalidArgument("shadecut: seamless output is for reliefs that fill the image; set scene to relief");
  if (options.seamless && !mask.all())
    throw InvalidArgument("shadecut: seamless output tiles the whole image, but the mask leaves " +
                          std::to_string(mask.size() - mask.count()) + " pixels out; give no mask");
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
    direction = estimate.light;
    // The estimators' albedo assumes a sphere's normals; a relief's comes from its median.
    if (!albedo && options.scene == SceneKind::Object) albedo = estimate.albedo;
  }
  const LightFrame frame = LightFrame::from_direction(direction);
  result.light = frame.direction;
  if (albedo) result.albedo = *albedo;
  else if (options.scene == SceneKind::Relief) result.albedo = relief_albedo(image, mask, frame.direction);
  else result.albedo = estimate_albedo(image, mask, options.albedo_method);
  if (!(result.albedo > 0.0) || !std::isfinite(result.albedo)) throw InvalidArgument("shadecut: the albedo must be finite and > 0");
  if (brightest <= 1e-6f * result.albedo)
    throw InvalidArgument("shadecut: the image is dark everywhere in the mask compared with the albedo " +
                          std::to_string(result.albedo) + "; nothing to reconstruct");
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
  params.shadow_threshold = options.fill_shadows ? options.shadow_threshold : -1.0;
  params.highlight_threshold = options.highlight_threshold;
  params.occluding_contour = edge_is_outline(options);
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
  return std::move(solved.normals);
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
    case Method::TsaiShah: {
      progress.report(0.0, "tsai_shah");
      const int sweeps = options.iterations.value_or(method_defaults(Method::TsaiShah).iterations);
      const TsaiShahResult solved = tsai_shah(image, mask, frame, albedo, sweeps, progress);
      stats.seconds["tsai_shah"] = stopwatch.seconds();
      stats.iterations = solved.iterations;
      return normals_from_depth(solved.depth, mask);
    }
    case Method::Upwind: {
      progress.report(0.0, "upwind");
      const int rounds = options.iterations.value_or(method_defaults(Method::Upwind).iterations);
      const UpwindResult solved = upwind(image, mask, frame, albedo, rounds, progress);
      stats.seconds["upwind"] = stopwatch.seconds();
      stats.iterations = solved.iterations;
      return normals_from_depth(solved.depth, mask);
    }
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
  switch (method) {
    case Method::GraphCut: return {1.0, 0.5, 0.0, 0, 0.0};
    case Method::GraphCutTwo: return {2.0, 0.05, 0.0, 0, 0.0};
    case Method::LeeRosenfeld: return {2.0, 0.0, 0.0, 0, 0.0};
    case Method::BrooksHorn: return {0.0, 0.0, 1e-5, 8000, 0.3};
    case Method::TsaiShah: return {0.0, 0.0, 0.0, 1, 0.0};
    case Method::Upwind: return {0.0, 0.0, 0.0, 100, 0.0};
  }
  throw InvalidArgument("shadecut: unknown method");
}

Reconstruction reconstruct(const ImageF& image, const std::optional<Eigen::Vector3d>& light, const Mask* mask_in,
                           std::optional<double> albedo, const ReconstructOptions& options) {
  const Stopwatch total;
  check_image(image);
  const Mask mask = mask_in ? *mask_in : Mask::Constant(image.rows(), image.cols(), true);
  check_mask(mask, image);
  if (image.minCoeff() < 0.0f) throw InvalidArgument("shadecut: the image has negative intensities; linear intensity is >= 0");
  check_options(options, mask);
  // Cheap, and before the estimates that cost a pass of median filtering over the image.
  const float brightest = mask.select(image, 0.0f).maxCoeff();
  if (!(brightest > 0.0f))
    throw InvalidArgument("shadecut: the image is dark everywhere in the mask (zero); nothing to reconstruct");
  const Progress progress(options.progress);

  Reconstruction result;
  result.mask = mask;
  const LightFrame frame = choose_lighting(image, mask, brightest, light, albedo, options, progress, result);
  const detail::ThreadCountScope threads(options.threads);
  result.normals = solve_normals(image, mask, frame, result.albedo, options, progress.range(0.0, kNormalsShare), result.stats);

  progress.report(kNormalsShare, "integration");
  const Stopwatch integration;
  const double shadow_threshold = options.fill_shadows ? options.shadow_threshold : -1.0;
  const Mask unreliable = unreliable_pixels(image, mask, result.albedo, shadow_threshold, options.highlight_threshold);
  result.stats.shadow_pixels = fill_normals(result.normals, unreliable, mask, edge_is_outline(options));
  fold_back_facing(result.normals, mask);
  if (options.seamless) {
    // A tiling surface has no ramp to flatten: its mean gradient is dropped by the integration.
    result.depth = integrate_periodic(result.normals, options.max_slope);
    result.normals = normals_from_periodic_depth(result.depth);
  } else {
    result.depth = integrate_normals(result.normals, mask, options.integrator, options.max_slope,
                                     progress.range(kNormalsShare, kIntegratedShare));
  }
  result.stats.seconds["integration"] = integration.seconds();
  if (fits_shading(options)) {
    fit_depth_to_image(image, mask && !unreliable, frame, options, progress.range(kIntegratedShare, 1.0), result);
  } else {
    progress.report(1.0, "integration");
  }
  if (!options.seamless && options.scene == SceneKind::Relief) flatten_relief(result.depth, result.normals, mask);
  result.stats.seconds["total"] = total.seconds();
  return result;
}

}  // namespace shadecut
