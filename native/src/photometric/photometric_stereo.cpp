#include <shadecut/photometric/photometric_stereo.hpp>

#include "photometric/pixel_fit.hpp"
#include "support/parallel.hpp"

#include <shadecut/support/errors.hpp>
#include <shadecut/support/light.hpp>
#include <shadecut/support/validate.hpp>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <mutex>
#include <string>
#include <utility>

namespace shadecut {
namespace {

void check_params(const PhotometricStereoParams& params, const Mask& mask) {
  const ImageF& map = params.albedo_map;
  if (map.size() > 0 && (map.rows() != mask.rows() || map.cols() != mask.cols()))
    throw InvalidArgument("shadecut: the albedo map does not have the photographs' size");
  if (map.size() > 0 && !map.isFinite().all())
    throw InvalidArgument("shadecut: the albedo map holds a NaN or infinite value");
  if (!(params.shadow_fraction >= 0.0 && params.shadow_fraction < 1.0))
    throw InvalidArgument("shadecut: shadow_fraction must lie in [0, 1), got " + number_text(params.shadow_fraction));
  if (!(params.outlier_tolerance > 0.0) || !std::isfinite(params.outlier_tolerance))
    throw InvalidArgument("shadecut: outlier_tolerance must be > 0, got " + number_text(params.outlier_tolerance));
  if (!(params.albedo >= 0.0) || !std::isfinite(params.albedo))
    throw InvalidArgument("shadecut: the albedo must be >= 0 (0 = estimated), got " + number_text(params.albedo));
  detail::check_lamps(params.lamps, int(mask.rows()), int(mask.cols()));
}

// The unit light directions; refuses lights below the horizon and pairs that add nothing.
std::vector<Eigen::Vector3d> checked_lights(const LightDirections& lights) {
  std::vector<Eigen::Vector3d> unit;
  for (Eigen::Index k = 0; k < lights.rows(); ++k) {
    try {
      unit.push_back(LightFrame::from_direction(lights.row(k).transpose()).direction);
    } catch (const InvalidArgument& error) {
      throw InvalidArgument(std::string(error.what()) + " (the light of " + photograph_name(std::size_t(k)) + ")");
    }
  }
  const double same = std::cos(kSameLightDegrees * M_PI / 180.0);
  for (std::size_t a = 0; a < unit.size(); ++a)
    for (std::size_t b = a + 1; b < unit.size(); ++b)
      if (unit[a].dot(unit[b]) > same)
        throw InvalidArgument("shadecut: the lights of " + photograph_name(a) + " and " + photograph_name(b) +
                              " are the same direction: " + photograph_name(b) + " adds nothing to " +
                              photograph_name(a) + "; leave one out");
  return unit;
}

void check_inputs(const std::vector<ImageF>& images, const LightDirections& lights, const Mask& mask,
                  const std::vector<Mask>& clipped) {
  if (images.size() < 2)
    throw InvalidArgument("shadecut: photometric stereo needs two or more photographs, got " +
                          std::to_string(images.size()));
  if (Eigen::Index(images.size()) != lights.rows())
    throw InvalidArgument("shadecut: " + std::to_string(lights.rows()) + " lights for " +
                          std::to_string(images.size()) + " photographs; give one light per photograph");
  for (std::size_t k = 0; k < images.size(); ++k) {
    check_image(images[k], photograph_name(k));
    check_same_size(images[k], k, images[0]);
  }
  check_mask(mask, images[0]);
  if (!clipped.empty() && clipped.size() != images.size())
    throw InvalidArgument("shadecut: " + std::to_string(clipped.size()) + " clipped masks for " +
                          std::to_string(images.size()) + " photographs; give none or one per photograph");
  for (std::size_t k = 0; k < clipped.size(); ++k)
    if (clipped[k].rows() != mask.rows() || clipped[k].cols() != mask.cols())
      throw InvalidArgument("shadecut: the clipped mask of " + photograph_name(k) +
                            " does not have the photographs' size");
}

}  // namespace

std::vector<Eigen::Vector3d> detail::checked_photometric_input(const std::vector<ImageF>& images,
                                                               const LightDirections& lights, const Mask& mask,
                                                               const std::vector<Mask>& clipped) {
  check_inputs(images, lights, mask, clipped);
  return checked_lights(lights);
}

namespace {

PhotometricStereoResult empty_result(int rows, int cols) {
  PhotometricStereoResult result;
  result.normals = NormalMap(rows, cols);
  result.first_candidate = NormalMap(rows, cols);
  result.second_candidate = NormalMap(rows, cols);
  result.first_shadow_conflict = ImageF::Zero(rows, cols);
  result.second_shadow_conflict = ImageF::Zero(rows, cols);
  result.albedo = ImageF::Zero(rows, cols);
  result.residual = ImageF::Zero(rows, cols);
  result.usable = CountImage::Zero(rows, cols);
  return result;
}

void store_fit(const detail::PixelFit& fit, int r, int c, PhotometricStereoResult& result,
               std::vector<detail::UsablePair>& pairs, std::vector<FourFits>& four_fits) {
  const int p = r * int(result.usable.cols()) + c;
  result.usable(r, c) = fit.usable;
  if (fit.usable >= 3) {
    result.normals.xyz.row(p) = fit.scaled_normal.normalized().cast<float>().transpose();
    result.albedo(r, c) = float(fit.scaled_normal.norm());
    result.residual(r, c) = float(fit.rms);
    if (fit.has_four_fits) {
      four_fits.push_back(fit.four_fits);
      four_fits.back().pixel = p;
    }
  } else if (fit.usable == 2) {
    pairs[std::size_t(p)] = fit.pair;
  }
}

// Fits every masked pixel; records the fits of three or more and the pairs of two.
void fit_pixels(const std::vector<ImageF>& images, const std::vector<Eigen::Vector3d>& lights, const Mask& mask,
                const std::vector<Mask>& clipped, const PhotometricStereoParams& params, const Progress& progress,
                PhotometricStereoResult& result, std::vector<detail::UsablePair>& pairs) {
  const int rows = int(mask.rows()), cols = int(mask.cols());
  pairs.assign(std::size_t(rows) * std::size_t(cols), detail::UsablePair{});
  // Gathered per range of rows, in the ranges' order of finishing, then put in pixel order.
  std::vector<FourFits> four_fits;
  std::mutex four_fits_lock;
  // Blocks of rows, so that progress is reported (and Cancelled thrown) on the calling thread.
  constexpr int kBlockRows = 64;
  for (int first = 0; first < rows; first += kBlockRows) {
    const int last = std::min(rows, first + kBlockRows);
    detail::parallel_ranges(last - first, 4, params.threads, [&](int begin, int end) {
      detail::PixelLights pixel_lights(lights, params.lamps);
      detail::PixelFitter fitter(pixel_lights, params.shadow_fraction, params.outlier_tolerance);
      std::vector<FourFits> found;
      for (int r = first + begin; r < first + end; ++r)
        for (int c = 0; c < cols; ++c)
          if (mask(r, c)) store_fit(fitter.fit(images, clipped, r, c), r, c, result, pairs, found);
      const std::lock_guard<std::mutex> hold(four_fits_lock);
      four_fits.insert(four_fits.end(), found.begin(), found.end());
    });
    progress.report(double(last) / rows, "photometric stereo");
  }
  std::sort(four_fits.begin(), four_fits.end(), [](const FourFits& a, const FourFits& b) { return a.pixel < b.pixel; });
  result.four_fits = std::move(four_fits);
}

}  // namespace

PhotometricStereoResult photometric_stereo(const std::vector<ImageF>& images, const LightDirections& lights,
                                           const Mask& mask, const std::vector<Mask>& clipped,
                                           const PhotometricStereoParams& params, const Progress& progress) {
  const std::vector<Eigen::Vector3d> unit = detail::checked_photometric_input(images, lights, mask, clipped);
  check_params(params, mask);
  const int rows = int(mask.rows()), cols = int(mask.cols());
  PhotometricStereoResult result = empty_result(rows, cols);
  std::vector<detail::UsablePair> pairs;
  fit_pixels(images, unit, mask, clipped, params, progress, result, pairs);
  for (int p = 0; p < rows * cols; ++p) {
    if (!mask.data()[p]) continue;
    const int usable = result.usable.data()[p];
    result.dark_pixels += usable == 0;
    result.single_pixels += usable == 1;
    result.pair_pixels += usable == 2;
  }
  if (result.pair_pixels > 0) {
    detail::PixelLights pixel_lights(unit, params.lamps);
    detail::resolve_pairs(pairs, images, clipped, pixel_lights, mask, params, result);
  }
  return result;
}

}  // namespace shadecut
