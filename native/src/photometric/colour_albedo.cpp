#include <shadecut/photometric/colour_albedo.hpp>

#include "photometric/pixel_fit.hpp"
#include "support/parallel.hpp"

#include <shadecut/support/errors.hpp>
#include <shadecut/support/validate.hpp>

#include <algorithm>
#include <cmath>
#include <string>

namespace shadecut {
namespace {

std::vector<ImageF> luminances(const std::vector<ColourImage>& photographs) {
  std::vector<ImageF> grey;
  for (std::size_t k = 0; k < photographs.size(); ++k) {
    const ColourImage& photo = photographs[k];
    for (int c = 1; c < 3; ++c)
      if (photo.channel[std::size_t(c)].rows() != photo.rows() || photo.channel[std::size_t(c)].cols() != photo.cols())
        throw InvalidArgument("shadecut: the colour channels of " + photograph_name(k) + " differ in size");
    ImageF y = ImageF::Zero(photo.rows(), photo.cols());
    for (int c = 0; c < 3; ++c) y += float(kLuminanceWeights[std::size_t(c)]) * photo.channel[std::size_t(c)];
    grey.push_back(std::move(y));
  }
  return grey;
}

// The albedo of one pixel (r, c) with normal n in each of `Channels` channels; channel(k, ch) is
// photograph k's channel ch, grey[k] its luminance. `usable` and `ratio` are buffers.
template <int Channels, class Channel>
Eigen::Matrix<float, Channels, 1> pixel_albedo(Channel channel, const std::vector<ImageF>& grey,
                                               const detail::PixelLights& lights, const Eigen::Vector3d& normal,
                                               const std::vector<Mask>& clipped, const PhotometricStereoParams& params,
                                               int r, int c, std::vector<int>& usable, std::vector<double>& ratio) {
  using Albedo = Eigen::Matrix<float, Channels, 1>;
  usable.clear();
  ratio.clear();
  const std::vector<Eigen::Vector3d>& directions = lights.directions();
  for (std::size_t k = 0; k < directions.size(); ++k) {
    const double cosine = normal.dot(directions[k]);
    if ((!clipped.empty() && clipped[k](r, c)) || cosine < params.shadow_fraction || !(cosine > 0.0)) continue;
    usable.push_back(int(k));
    ratio.push_back(grey[k](r, c) / (cosine * lights.strength(k)));
  }
  if (usable.empty()) return Albedo::Zero();
  std::nth_element(ratio.begin(), ratio.begin() + std::ptrdiff_t(ratio.size() / 2), ratio.end());
  const double median = ratio[ratio.size() / 2];
  Eigen::Matrix<double, Channels, 1> numerator = Eigen::Matrix<double, Channels, 1>::Zero();
  double denominator = 0.0;
  for (const int k : usable) {
    const double shade = normal.dot(directions[std::size_t(k)]) * lights.strength(std::size_t(k));
    if (std::abs(grey[std::size_t(k)](r, c) - median * shade) > params.outlier_tolerance * median) continue;
    for (int ch = 0; ch < Channels; ++ch) numerator(ch) += channel(std::size_t(k), ch, r, c) * shade;
    denominator += shade * shade;
  }
  return denominator > 0.0 ? Albedo((numerator / denominator).template cast<float>()) : Albedo::Zero();
}

// Every masked pixel's albedo, stored by store(r, c, albedo).
template <int Channels, class Channel, class Store>
void fit_albedo(Channel channel, const std::vector<ImageF>& grey, const LightDirections& lights, const NormalMap& normals,
                const Mask& mask, const std::vector<Mask>& clipped, const PhotometricStereoParams& params, Store store) {
  const std::vector<Eigen::Vector3d> unit = detail::checked_photometric_input(grey, lights, mask, clipped);
  check_normals(normals, int(mask.rows()), int(mask.cols()));
  const int rows = int(mask.rows()), cols = int(mask.cols());
  detail::check_lamps(params.lamps, rows, cols);
  detail::parallel_ranges(rows, 8, params.threads, [&](int begin, int end) {
    detail::PixelLights lights_here(unit, params.lamps);
    std::vector<int> usable;
    std::vector<double> ratio;
    for (int r = begin; r < end; ++r)
      for (int c = 0; c < cols; ++c) {
        const Eigen::Vector3d normal = normals.xyz.row(Eigen::Index(r) * cols + c).cast<double>().transpose();
        if (!mask(r, c) || normal.isZero()) continue;
        lights_here.at(r, c);
        store(r, c, pixel_albedo<Channels>(channel, grey, lights_here, normal, clipped, params, r, c, usable, ratio));
      }
  });
}

}  // namespace

ColourImage photometric_colour_albedo(const std::vector<ColourImage>& photographs, const LightDirections& lights,
                                      const NormalMap& normals, const Mask& mask, const std::vector<Mask>& clipped,
                                      const PhotometricStereoParams& params) {
  const std::vector<ImageF> grey = luminances(photographs);
  ColourImage albedo;
  for (auto& channel : albedo.channel) channel = ImageF::Zero(mask.rows(), mask.cols());
  fit_albedo<3>([&](std::size_t k, int ch, int r, int c) { return photographs[k].channel[std::size_t(ch)](r, c); },
                grey, lights, normals, mask, clipped, params, [&](int r, int c, const Eigen::Vector3f& rho) {
                  for (int ch = 0; ch < 3; ++ch) albedo.channel[std::size_t(ch)](r, c) = rho(ch);
                });
  return albedo;
}

ImageF photometric_albedo(const std::vector<ImageF>& photographs, const LightDirections& lights, const NormalMap& normals,
                          const Mask& mask, const std::vector<Mask>& clipped, const PhotometricStereoParams& params) {
  ImageF albedo = ImageF::Zero(mask.rows(), mask.cols());
  fit_albedo<1>([&](std::size_t k, int, int r, int c) { return photographs[k](r, c); }, photographs, lights, normals,
                mask, clipped, params, [&](int r, int c, const Eigen::Matrix<float, 1, 1>& rho) { albedo(r, c) = rho(0); });
  return albedo;
}

}  // namespace shadecut
