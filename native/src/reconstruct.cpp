#include <shadecut/reconstruct.hpp>

#include <shadecut/brooks_horn.hpp>
#include <shadecut/global_step.hpp>
#include <shadecut/errors.hpp>
#include <shadecut/light.hpp>
#include <shadecut/local_shape.hpp>
#include <shadecut/render.hpp>
#include <shadecut/shadow_fill.hpp>
#include <shadecut/tilt_energy.hpp>
#include <shadecut/tsai_shah.hpp>
#include <shadecut/validate.hpp>

#include <opencv2/imgproc.hpp>
#include <omp.h>

#include <chrono>

namespace shadecut {

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

// Reports progress within a stage that spans [begin, end] of the whole call.
void report(const ProgressCallback& progress, double begin, double end, double within, const char* stage) {
  if (progress && !progress(begin + (end - begin) * within, stage)) throw Cancelled();
}

}  // namespace

const std::vector<std::string>& method_names() {
  static const std::vector<std::string> names{"graphcut", "graphcut_two", "lee_rosenfeld", "brooks_horn", "tsai_shah"};
  return names;
}

Method parse_method(const std::string& name) {
  const std::vector<std::string>& names = method_names();
  for (std::size_t i = 0; i < names.size(); ++i)
    if (names[i] == name) return Method(i);
  std::string choices;
  for (std::size_t i = 0; i < names.size(); ++i) choices += (i ? ", " : "") + names[i];
  throw InvalidArgument("shadecut: unknown method '" + name + "'; choose one of " + choices);
}

std::string to_string(Method method) { return method_names().at(std::size_t(method)); }

MethodDefaults method_defaults(Method method) {
  switch (method) {
    case Method::GraphCut: return {1.0, 0.5, 0.0, 0, 0.0};
    case Method::GraphCutTwo: return {2.0, 0.05, 0.0, 0, 0.0};
    case Method::LeeRosenfeld: return {2.0, 0.0, 0.0, 0, 0.0};
    case Method::BrooksHorn: return {0.0, 0.0, 1e-5, 8000, 0.3};
    case Method::TsaiShah: return {0.0, 0.0, 0.0, 1, 0.0};
  }
  throw InvalidArgument("shadecut: unknown method");
}

double unary_scale(const Mask& mask) { return kReferenceObjectSize / object_size(mask); }

double estimate_albedo(const ImageF& image, const Mask& mask) {
  check_image(image);
  check_mask(mask, image);
  ImageF filtered(image.rows(), image.cols());
  const cv::Mat source(int(image.rows()), int(image.cols()), CV_32F, const_cast<float*>(image.data()));
  cv::Mat target(int(image.rows()), int(image.cols()), CV_32F, filtered.data());
  cv::medianBlur(source, target, 3);
  float brightest = 0.0f;
  for (Eigen::Index i = 0; i < image.size(); ++i)
    if (mask.data()[i]) brightest = std::max(brightest, filtered.data()[i]);
  if (!(brightest > 0.0f)) throw InvalidArgument("shadecut: the image is dark everywhere in the mask; nothing to reconstruct");
  return brightest;
}

Reconstruction reconstruct(const ImageF& image, const std::optional<Eigen::Vector3d>& light, const Mask* mask_in,
                           std::optional<double> albedo_in, const ReconstructOptions& options) {
  const auto start = Clock::now();
  check_image(image);
  const Mask mask = mask_in ? *mask_in : Mask::Constant(image.rows(), image.cols(), true);
  check_mask(mask, image);
  if (image.minCoeff() < 0.0f) throw InvalidArgument("shadecut: the image has negative intensities; linear intensity is >= 0");
  if (options.threads < 0) throw InvalidArgument("shadecut: threads must be >= 0 (0 = all cores)");
  if (options.labels < 4) throw InvalidArgument("shadecut: labels must be at least 4 (got " + std::to_string(options.labels) + ")");

  Reconstruction result;
  ReconstructStats& stats = result.stats;
  result.mask = mask;
  std::optional<double> albedo = albedo_in;
  Eigen::Vector3d light_used;
  if (light) {
    light_used = *light;
  } else {
    report(options.progress, 0.0, 0.0, 0.0, "light");
    const auto light_start = Clock::now();
    const LightEstimate estimate = estimate_light(image, mask, options.light_estimator);
    stats.seconds["light"] = seconds_since(light_start);
    stats.light_estimated = true;
    light_used = estimate.light;
    if (!albedo) albedo = estimate.albedo;
  }
  const LightFrame frame = LightFrame::from_direction(light_used);
  result.light = frame.direction;
  result.albedo = albedo ? *albedo : estimate_albedo(image, mask);
  if (!(result.albedo > 0.0) || !std::isfinite(result.albedo)) throw InvalidArgument("shadecut: the albedo must be finite and > 0");
  if ((image * mask.cast<float>()).maxCoeff() <= 1e-6f * result.albedo)
    throw InvalidArgument("shadecut: the image is dark everywhere in the mask; nothing to reconstruct");
  const int threads = options.threads > 0 ? options.threads : omp_get_max_threads();
  const int saved_threads = omp_get_max_threads();
  omp_set_num_threads(threads);
  struct RestoreThreads {
    int n;
    ~RestoreThreads() { omp_set_num_threads(n); }
  } restore{saved_threads};

  const MethodDefaults defaults = method_defaults(options.method);
  const double tolerance = options.tolerance.value_or(defaults.tolerance);
  const int iterations = options.iterations.value_or(defaults.iterations);
  auto stage_start = Clock::now();
  auto iteration_progress = [&](const char* stage) {
    return [&options, stage](double fraction) { return !options.progress || options.progress(0.9 * fraction, stage); };
  };

  if (options.method == Method::BrooksHorn) {
    report(options.progress, 0.0, 0.9, 0.0, "brooks_horn");
    BrooksHornParams params;
    const double smoothness = options.smoothness.value_or(defaults.smoothness);
    if (!(smoothness > 0.0) || !std::isfinite(smoothness))
      throw InvalidArgument("shadecut: the smoothness of brooks_horn must be finite and > 0");
    // Per pixel the smoothness term reads |grad n|^2 h^2 while the brightness term stays put, so the
    // weight grows with the object's area to keep the same minimum at every resolution; small objects
    // are held at the weight where the sweeps still converge.
    const double per_pixel = 1.0 / (unary_scale(mask) * unary_scale(mask));
    params.smoothness = std::max(kStableSmoothness, smoothness * per_pixel);
    params.iterations = iterations;
    params.tolerance = tolerance;
    params.occluding_contour = options.occluding_contour;
    BrooksHornResult solved = brooks_horn(image, mask, frame, result.albedo, params, iteration_progress("brooks_horn"));
    stats.seconds["brooks_horn"] = seconds_since(stage_start);
    stats.iterations = solved.iterations;
    result.normals = std::move(solved.normals);
  } else if (options.method == Method::TsaiShah) {
    report(options.progress, 0.0, 0.9, 0.0, "tsai_shah");
    const TsaiShahResult solved = tsai_shah(image, mask, frame, result.albedo, iterations, iteration_progress("tsai_shah"));
    stats.seconds["tsai_shah"] = seconds_since(stage_start);
    stats.iterations = solved.iterations;
    result.normals = normals_from_depth(solved.depth, mask);
  } else if (options.method == Method::LeeRosenfeld) {
    report(options.progress, 0.0, 0.9, 0.0, "local");
    const LocalShape local =
        local_shape(image, mask, frame, result.albedo, options.min_curvature.value_or(defaults.min_curvature));
    stats.seconds["local"] = seconds_since(stage_start);
    result.normals = convex_normals(local, frame, mask);
  } else {
    GlobalStepParams params;
    params.energy.labels = options.labels;
    params.energy.data_weight = options.data_weight;
    params.energy.undefined_weight = options.undefined_weight.value_or(defaults.undefined_weight);
    params.energy.data_term = options.method == Method::GraphCut ? DataTerm::Soft : DataTerm::TwoCandidates;
    params.energy.threads = threads;
    params.min_curvature = options.min_curvature.value_or(defaults.min_curvature);
    params.max_cycles = options.max_cycles;
    params.tolerance = tolerance;
    params.band = options.coarse_to_fine_band;
    params.refine = options.refine;
    auto solver = make_maxflow_solver(options.maxflow);
    GlobalStepResult solved =
        global_step(image, mask, frame, result.albedo, params, *solver, [&](double fraction, const char* stage) {
          return !options.progress || options.progress(0.9 * fraction, stage);
        });
    for (const auto& [stage, seconds] : solved.seconds) stats.seconds[stage] = seconds;
    stats.allowed_label_fraction = solved.allowed_label_fraction;
    stats.energy_per_cycle = solved.expansion.energy_per_cycle;
    stats.cycles = solved.expansion.cycles;
    stats.iterations = solved.expansion.cycles;
    stats.moves = solved.expansion.moves;
    stats.accepted_moves = solved.expansion.accepted_moves;
    stats.maxflow_seconds = solved.expansion.maxflow_seconds;
    stats.levels = solved.levels;
    result.normals = std::move(solved.normals);
  }

  report(options.progress, 0.9, 1.0, 0.0, "integration");
  stage_start = Clock::now();
  if (options.fill_shadows)
    stats.shadow_pixels = fill_attached_shadows(result.normals, image, mask, result.albedo, options.shadow_threshold,
                                                options.occluding_contour);
  result.depth = integrate_normals(result.normals, mask, options.integrator, options.max_slope);
  stats.seconds["integration"] = seconds_since(stage_start);
  report(options.progress, 0.9, 1.0, 1.0, "integration");
  stats.seconds["total"] = seconds_since(start);
  return result;
}

}  // namespace shadecut
