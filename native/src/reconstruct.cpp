#include <shadecut/reconstruct.hpp>

#include <shadecut/alpha_expansion.hpp>
#include <shadecut/convexity_cut.hpp>
#include <shadecut/errors.hpp>
#include <shadecut/light.hpp>
#include <shadecut/local_shape.hpp>
#include <shadecut/shadow_fill.hpp>
#include <shadecut/tilt_energy.hpp>
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

Method parse_method(const std::string& name) {
  if (name == "graphcut") return Method::GraphCut;
  if (name == "graphcut_two") return Method::GraphCutTwo;
  if (name == "lee_rosenfeld") return Method::LeeRosenfeld;
  throw InvalidArgument("shadecut: unknown method '" + name + "'; choose graphcut, graphcut_two or lee_rosenfeld");
}

std::string to_string(Method method) {
  switch (method) {
    case Method::GraphCut: return "graphcut";
    case Method::GraphCutTwo: return "graphcut_two";
    case Method::LeeRosenfeld: return "lee_rosenfeld";
  }
  return "unknown";
}

MethodDefaults method_defaults(Method method) {
  switch (method) {
    case Method::GraphCut: return {3e-3, 0.2};
    case Method::GraphCutTwo: return {1e-2, 0.05};
    case Method::LeeRosenfeld: return {1e-2, 0.0};
  }
  return {1e-2, 0.0};
}

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

Reconstruction reconstruct(const ImageF& image, const Eigen::Vector3d& light, const Mask* mask_in,
                           std::optional<double> albedo_in, const ReconstructOptions& options) {
  const auto start = Clock::now();
  check_image(image);
  const Mask mask = mask_in ? *mask_in : Mask::Constant(image.rows(), image.cols(), true);
  check_mask(mask, image);
  if (image.minCoeff() < 0.0f) throw InvalidArgument("shadecut: the image has negative intensities; linear intensity is >= 0");
  const LightFrame frame = LightFrame::from_direction(light);
  if (options.threads < 0) throw InvalidArgument("shadecut: threads must be >= 0 (0 = all cores)");
  if (options.labels < 4) throw InvalidArgument("shadecut: labels must be at least 4 (got " + std::to_string(options.labels) + ")");

  Reconstruction result;
  result.mask = mask;
  result.light = frame.direction;
  result.albedo = albedo_in ? *albedo_in : estimate_albedo(image, mask);
  if (!(result.albedo > 0.0) || !std::isfinite(result.albedo)) throw InvalidArgument("shadecut: the albedo must be finite and > 0");
  if ((image * mask.cast<float>()).maxCoeff() <= 1e-6f * result.albedo)
    throw InvalidArgument("shadecut: the image is dark everywhere in the mask; nothing to reconstruct");
  ReconstructStats& stats = result.stats;
  const int threads = options.threads > 0 ? options.threads : omp_get_max_threads();
  const int saved_threads = omp_get_max_threads();
  omp_set_num_threads(threads);
  struct RestoreThreads {
    int n;
    ~RestoreThreads() { omp_set_num_threads(n); }
  } restore{saved_threads};

  report(options.progress, 0.0, 0.05, 0.0, "local");
  auto stage_start = Clock::now();
  const MethodDefaults defaults = method_defaults(options.method);
  const LocalShape local =
      local_shape(image, mask, frame, result.albedo, options.min_gradient.value_or(defaults.min_gradient));
  stats.seconds["local"] = seconds_since(stage_start);

  if (options.method == Method::LeeRosenfeld) {
    result.normals = convex_normals(local, frame, mask);
  } else {
    report(options.progress, 0.05, 0.1, 0.0, "energy");
    stage_start = Clock::now();
    TiltEnergyParams params;
    params.labels = options.labels;
    params.data_weight = options.data_weight;
    params.undefined_weight = options.undefined_weight.value_or(defaults.undefined_weight);
    params.data_term = options.method == Method::GraphCut ? DataTerm::Soft : DataTerm::TwoCandidates;
    params.threads = threads;
    const TiltEnergy energy(local, frame, mask, params);
    std::vector<int> labelling = energy.convex_labelling();
    stats.seconds["energy"] = seconds_since(stage_start);
    stats.allowed_label_fraction = double(energy.allowed_count()) / (double(mask.count()) * options.labels);

    stage_start = Clock::now();
    auto solver = make_maxflow_solver(options.maxflow);
    convexity_cut(energy, local, labelling, *solver);
    const AlphaExpansionStats expansion =
        alpha_expansion(energy, labelling, *solver, options.max_cycles, options.tolerance, [&](double fraction) {
          return !options.progress || options.progress(0.1 + 0.8 * fraction, "graphcut");
        });
    stats.seconds["graphcut"] = seconds_since(stage_start);
    stats.energy_per_cycle = expansion.energy_per_cycle;
    stats.cycles = expansion.cycles;
    stats.moves = expansion.moves;
    stats.accepted_moves = expansion.accepted_moves;
    stats.maxflow_seconds = expansion.maxflow_seconds;
    result.normals = labelling_normals(labelling, energy, local, frame, options.refine);
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
