#include "pipeline/photographs.hpp"

#include <shadecut/integrate/surface_from_normals.hpp>
#include <shadecut/photometric/choose_candidates.hpp>
#include <shadecut/photometric/colour_albedo.hpp>
#include <shadecut/photometric/estimate_lights.hpp>
#include <shadecut/photometric/photometric_stereo.hpp>
#include <shadecut/photometric/residual_map.hpp>
#include <shadecut/pipeline/relief.hpp>
#include <shadecut/support/errors.hpp>
#include <shadecut/support/validate.hpp>

#include "pipeline/option_checks.hpp"
#include "pipeline/surface_rules.hpp"
#include "pipeline/two_photographs.hpp"
#include "support/contour.hpp"
#include "support/parallel.hpp"
#include "support/stopwatch.hpp"

#include <algorithm>
#include <cmath>
#include <string>

namespace shadecut::detail {

namespace {

// The shares of the call's progress: the per-pixel fits, the cut, the integration.
constexpr double kFitShare = 0.4;
constexpr double kCutShare = 0.7;
// Two photographs: the share of their per-pixel fits (the photographs alone take the rest to kCutShare).
constexpr double kTwoFitShare = 0.05;
// Near lamps: the photographs are read again on the depth the reading before found, since the lamps'
// directions at a pixel depend on where the surface is.
constexpr int kNearLampPasses = 3;
// Estimated lights and an outline: the share of the first reading (the second, if the outline turns
// the lights, takes the rest).
constexpr double kOutlineShare = 0.5;

// The photographs' images in order: what the photometric functions read.
std::vector<ImageF> grey_images(const std::vector<Observation>& photographs) {
  std::vector<ImageF> images;
  for (const Observation& photograph : photographs) images.push_back(photograph.image);
  return images;
}

void check_photographs(const std::vector<Observation>& photographs, const Mask* mask) {
  const Observation& first = photographs.front();
  for (std::size_t k = 0; k < photographs.size(); ++k) {
    const Observation& photograph = photographs[k];
    check_image(photograph.image);
    check_same_size(photograph.image, k, first.image);
    if (photograph.has_colour() != first.has_colour())
      throw InvalidArgument("shadecut: " + photograph_name(k) + " is " + (photograph.has_colour() ? "colour" : "grey") +
                            " but the first is not; give all in colour or all grey");
    if (photograph.image.minCoeff() < 0.0f)
      throw InvalidArgument("shadecut: " + photograph_name(k) + " has negative intensities; linear intensity is >= 0");
    if (photograph.light.has_value() != first.light.has_value())
      throw InvalidArgument("shadecut: the light of " + photograph_name(photograph.light ? 0 : k) +
                            " is not given but others are; give every photograph's light, or none to have them "
                            "estimated");
  }
  if (mask) check_mask(*mask, first.image);
}

// The albedo per pixel (and channel) fitted to the chosen normals over the photographs usable there
// (photometric_colour_albedo), and how far the photographs are from the result.
void fit_albedo_and_residual(const std::vector<Observation>& photographs, const std::vector<ImageF>& images,
                             const LightDirections& lights,
                             const PhotometricStereoParams& params, Reconstruction& result) {
  if (photographs.front().has_colour()) {
    std::vector<ColourImage> colours;
    for (const Observation& photograph : photographs) colours.push_back(photograph.colour);
    result.albedo_colour = photometric_colour_albedo(colours, lights, result.normals, result.mask, {}, params);
    result.albedo_map = luminance(result.albedo_colour);
  } else {
    result.albedo_map = photometric_albedo(images, lights, result.normals, result.mask, {}, params);
  }
  result.residual = residual_map(images, result.lights, params.lamps, result.normals, result.albedo_map, result.mask);
}

// How many pixels were lit in two, one or no photograph, and how many chose which of four to leave
// out, into the call's stats.
void count_usable(const PhotometricStereoResult& fitted, ReconstructStats& stats) {
  stats.pair_pixels = fitted.pair_pixels;
  stats.four_fit_pixels = std::int64_t(fitted.four_fits.size());
  stats.single_pixels = fitted.single_pixels;
  stats.dark_pixels = fitted.dark_pixels;
}

// The normals the photographs give: fitted where three or more are usable, chosen by the graph cut
// where two leave two; `fill` marks the pixels with fewer, whose normals the surface fills in.
NormalMap photographs_normals(const std::vector<ImageF>& images, const LightDirections& directions,
                              const Mask& mask, const PhotometricStereoParams& params, const ReconstructOptions& options,
                              const Progress& progress, Mask& fill, ReconstructStats& stats) {
  Stopwatch stage;
  PhotometricStereoResult fitted = photometric_stereo(images, directions, mask, {}, params, progress.range(0.0, kFitShare));
  stats.seconds["photometric stereo"] += stage.seconds();
  count_usable(fitted, stats);
  fill = mask && (fitted.usable < 2);
  stage.restart();
  CandidateCutParams cut_params;
  cut_params.smoothness = options.candidate_smoothness;
  CandidateCutResult chosen =
      choose_candidates(photometric_candidates(std::move(fitted)), cut_params, progress.range(kFitShare, kCutShare));
  stats.seconds["candidate cut"] += stage.seconds();
  stats.cycles = chosen.cycles;
  stats.accepted_moves = chosen.accepted_moves;
  NormalMap normals = std::move(chosen.normals);
  // A pixel to fill needs a normal to start from: facing the viewer.
  for (Eigen::Index i = 0; i < fill.size(); ++i)
    if (fill.data()[i]) normals.xyz.row(i) << 0.0f, 0.0f, 1.0f;
  return normals;
}

// The photographs' lights, normalized: given, or estimated from them (estimate_photometric_lights)
// with the options' hint, the stats saying so.
std::vector<Eigen::Vector3d> photographs_lights(const std::vector<Observation>& photographs,
                                                const std::vector<ImageF>& images, const Mask& mask,
                                                const ReconstructOptions& options, const Progress& progress,
                                                ReconstructStats& stats) {
  std::vector<Eigen::Vector3d> lights;
  if (!photographs.front().light && options.light_distance > 0.0)
    throw InvalidArgument("shadecut: light_distance places the lamps along the photographs' lights; give their "
                          "lights, or leave light_distance at 0 to have distant lights estimated");
  if (photographs.front().light) {
    for (const Observation& photograph : photographs) lights.push_back(photograph.light->normalized());
    return lights;
  }
  progress.report(0.0, "light");
  const Stopwatch stage;
  LightHint hint;
  hint.slant = options.light_slant;
  hint.first_tilt = options.first_light_tilt;
  const PhotometricLights estimate = estimate_photometric_lights(images, mask, hint);
  stats.seconds["light"] = stage.seconds();
  stats.light_estimated = true;
  stats.light_uncertainty = *std::max_element(estimate.uncertainty.begin(), estimate.uncertainty.end());
  for (Eigen::Index k = 0; k < estimate.lights.rows(); ++k) lights.push_back(estimate.lights.row(k).transpose());
  return lights;
}

// Two photographs: every pixel both light keeps a circle of normals whatever its albedo, and nothing in
// the pair says where on it; the photographs read alone by the paper's graph cut anchor it (the
// nearest point). Pixels lit in fewer keep the anchor.
Surface two_photographs_surface(const std::vector<Observation>& photographs, const std::vector<ImageF>& images,
                                const LightDirections& directions,
                                const Mask& mask, const PhotometricStereoParams& params,
                                const ReconstructOptions& options, const Progress& progress, ReconstructStats& stats) {
  Stopwatch stage;
  const PhotometricStereoResult fitted =
      photometric_stereo(images, directions, mask, {}, params, progress.range(0.0, kTwoFitShare));
  stats.seconds["photometric stereo"] += stage.seconds();
  count_usable(fitted, stats);
  stage.restart();
  const std::vector<NormalMap> alone = photographs_read_alone(photographs, mask, options, progress.range(kTwoFitShare, kCutShare));
  stats.seconds["photographs alone"] += stage.seconds();
  std::vector<Eigen::Vector3d> lights;
  for (Eigen::Index k = 0; k < directions.rows(); ++k) lights.push_back(directions.row(k).transpose().normalized());
  // The anchor: their mean, or one of the two read alone where the other took a bump for a dent (the
  // mean then halves the bump, far from what the photographs allow): whichever lies nearest the circles.
  const std::vector<NormalMap> anchors{mean_normals(alone[0], alone[1], mask), alone[0], alone[1]};
  const NormalMap& anchor = nearest_to_circles(anchors, images, lights, params.lamps, mask && (fitted.usable == 2));
  progress.report(kCutShare, "integration");
  stage.restart();
  Surface surface = surface_from_normals(nearest_on_circles(images, lights, params.lamps, fitted.usable, anchor, mask),
                                         mask, Mask::Constant(mask.rows(), mask.cols(), false), edge_is_outline(options),
                                         options.integrator, options.seamless, options.max_slope,
                                         progress.range(kCutShare, 1.0));
  stats.seconds["integration"] += stage.seconds();
  return surface;
}

// The surface of one reading of the photographs: their normals, then the depth.
Surface photographs_surface(const std::vector<Observation>& photographs, const std::vector<ImageF>& images,
                            const LightDirections& directions,
                            const Mask& mask, const PhotometricStereoParams& params, const ReconstructOptions& options,
                            const Progress& progress, ReconstructStats& stats) {
  if (photographs.size() == 2)
    return two_photographs_surface(photographs, images, directions, mask, params, options, progress, stats);
  Mask fill;
  NormalMap normals = photographs_normals(images, directions, mask, params, options, progress, fill, stats);
  progress.report(kCutShare, "integration");
  const Stopwatch integration;
  Surface surface = surface_from_normals(std::move(normals), mask, fill, edge_is_outline(options), options.integrator,
                                         options.seamless, options.max_slope, progress.range(kCutShare, 1.0));
  stats.seconds["integration"] += integration.seconds();
  return surface;
}

// Whether the mask's edge runs inside the frame somewhere (the frame's own border is no outline).
bool has_outline(const Mask& mask) {
  for (int r = 1; r + 1 < mask.rows(); ++r)
    for (int c = 1; c + 1 < mask.cols(); ++c)
      if (mask(r, c) && contour_outward(mask, r, c).squaredNorm() > 0.0) return true;
  return false;
}

// The mean over the outline's pixels of the normals' image-plane part along the outline's outward
// direction: positive where they turn outward, as an object's do toward its occluding contour,
// negative for its inversion (which turns each of them inward by as much).
double outline_agreement(const NormalMap& normals, const Mask& mask) {
  double sum = 0.0;
  std::int64_t count = 0;
  for (int r = 1; r + 1 < mask.rows(); ++r)
    for (int c = 1; c + 1 < mask.cols(); ++c) {
      if (!mask(r, c)) continue;
      const Eigen::Vector2d outward = contour_outward(mask, r, c);
      if (outward.squaredNorm() == 0.0) continue;
      sum += normals.xyz.row(Eigen::Index(r) * mask.cols() + c).head<2>().cast<double>().dot(outward);
      ++count;
    }
  return count > 0 ? sum / double(count) : 0.0;
}

// Lamps `distance` frame widths from the frame's centre at the surface's mean depth (ReconstructOptions::
// light_distance), the surface's points at `depth`.
NearLamps lamps_around(double distance, const Mask& mask, ImageF depth) {
  NearLamps lamps;
  lamps.distance = distance * double(mask.cols());
  const double mean_depth = double(mask.select(depth, 0.0f).sum()) / double(std::max<Eigen::Index>(1, mask.count()));
  lamps.centre = Eigen::Vector3d(0.5 * double(mask.cols() - 1), -0.5 * double(mask.rows() - 1), mean_depth);
  lamps.depth = std::move(depth);
  return lamps;
}

}  // namespace

Reconstruction reconstruct_photographs(const std::vector<Observation>& photographs, const Mask* mask_in,
                                       std::optional<double> albedo, const ReconstructOptions& options) {
  const Stopwatch total;
  check_photographs(photographs, mask_in);
  if (albedo) check_albedo(*albedo);
  const ImageF& first = photographs.front().image;
  const Mask mask = mask_in ? *mask_in : Mask::Constant(first.rows(), first.cols(), true);
  check_options(options, mask);
  const Progress progress(options.progress);
  const ThreadCountScope threads(options.threads);
  Reconstruction result;
  result.mask = mask;
  // The photographs' grey images, copied once for the photometric functions, which read them all.
  const std::vector<ImageF> images = grey_images(photographs);
  result.lights = photographs_lights(photographs, images, mask, options, progress, result.stats);
  result.light = result.lights.front();
  result.stats.photographs = int(photographs.size());
  LightDirections directions(Eigen::Index(photographs.size()), 3);
  for (std::size_t k = 0; k < photographs.size(); ++k) directions.row(Eigen::Index(k)) = result.lights[k].transpose();
  PhotometricStereoParams params;
  params.shadow_fraction = options.photometric_shadow_fraction;
  params.outlier_tolerance = options.photometric_outlier_tolerance;
  params.albedo = albedo.value_or(0.0);
  Surface surface;
  // Two photographs' depth leans on their anchor, read under distant lights: it would move the lamps wrongly.
  const int passes = options.light_distance > 0.0 && photographs.size() > 2 ? kNearLampPasses : 1;
  // Estimated lights leave the surface's inversion open (the hint's first tilt chose); an object's
  // outline settles it, read once more under the lights turned by half a circle where it disagrees.
  const bool outline_decides = result.stats.light_estimated && edge_is_outline(options) && has_outline(mask);
  const Progress reading = outline_decides ? progress.range(0.0, kOutlineShare) : progress;
  for (int pass = 0; pass < passes; ++pass) {
    if (options.light_distance > 0.0)
      params.lamps = lamps_around(options.light_distance, mask,
                                  pass > 0 ? std::move(surface.depth) : ImageF(ImageF::Zero(mask.rows(), mask.cols())));
    surface = photographs_surface(photographs, images, directions, mask, params, options,
                                  reading.range(double(pass) / passes, double(pass + 1) / passes), result.stats);
  }
  if (outline_decides && outline_agreement(surface.normals, mask) < 0.0) {
    directions.leftCols(2) *= -1.0;
    for (Eigen::Vector3d& light : result.lights) light.head<2>() *= -1.0;
    result.light = result.lights.front();
    result.stats.lights_turned_by_outline = true;
    surface = photographs_surface(photographs, images, directions, mask, params, options,
                                  progress.range(kOutlineShare, 1.0), result.stats);
  }
  if (options.light_distance > 0.0) params.lamps = lamps_around(options.light_distance, mask, surface.depth);
  result.normals = std::move(surface.normals);
  result.depth = std::move(surface.depth);
  result.stats.shadow_pixels = surface.filled_pixels;
  // A relief sits on a flat carrier; its normals stay the photographs', which hold its large forms too.
  if (options.scene == SceneKind::Relief && !options.seamless) flatten_relief(result.depth, mask);
  const Stopwatch albedo_fit;
  fit_albedo_and_residual(photographs, images, directions, params, result);
  result.stats.seconds["albedo"] = albedo_fit.seconds();
  const ImageF fitted_albedo = mask.select(result.albedo_map, 0.0f);
  std::vector<float> values;
  for (Eigen::Index i = 0; i < fitted_albedo.size(); ++i)
    if (mask.data()[i] && fitted_albedo.data()[i] > 0.0f) values.push_back(fitted_albedo.data()[i]);
  if (values.empty()) throw InvalidArgument("shadecut: every photograph is dark everywhere in the mask; nothing to reconstruct");
  std::nth_element(values.begin(), values.begin() + std::ptrdiff_t(values.size() / 2), values.end());
  result.albedo = albedo.value_or(double(values[values.size() / 2]));
  progress.report(1.0, "integration");
  result.stats.seconds["total"] = total.seconds();
  return result;
}

}  // namespace shadecut::detail
