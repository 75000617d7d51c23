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

// The albedo of one pixel (r, c) with normal n; `usable` and `ratio` are buffers.
Eigen::Vector3f pixel_albedo(const std::vector<ColourImage>& photographs, const std::vector<ImageF>& grey,
                             const std::vector<Eigen::Vector3d>& lights, const Eigen::Vector3d& normal,
                             const std::vector<Mask>& clipped, const PhotometricStereoParams& params, int r, int c,
                             std::vector<int>& usable, std::vector<double>& ratio) {
  usable.clear();
  ratio.clear();
  for (std::size_t k = 0; k < lights.size(); ++k) {
    const double shade = normal.dot(lights[k]);
    if ((!clipped.empty() && clipped[k](r, c)) || shade < params.shadow_fraction || !(shade > 0.0)) continue;
    usable.push_back(int(k));
    ratio.push_back(grey[k](r, c) / shade);
  }
  if (usable.empty()) return Eigen::Vector3f::Zero();
  std::nth_element(ratio.begin(), ratio.begin() + std::ptrdiff_t(ratio.size() / 2), ratio.end());
  const double median = ratio[ratio.size() / 2];
  Eigen::Vector3d numerator = Eigen::Vector3d::Zero();
  double denominator = 0.0;
  for (const int k : usable) {
    const double shade = normal.dot(lights[std::size_t(k)]);
    if (std::abs(grey[std::size_t(k)](r, c) - median * shade) > params.outlier_tolerance * median) continue;
    for (int ch = 0; ch < 3; ++ch) numerator(ch) += photographs[std::size_t(k)].channel[std::size_t(ch)](r, c) * shade;
    denominator += shade * shade;
  }
  return denominator > 0.0 ? Eigen::Vector3f((numerator / denominator).cast<float>()) : Eigen::Vector3f::Zero();
}

}  // namespace

ColourImage photometric_colour_albedo(const std::vector<ColourImage>& photographs, const LightDirections& lights,
                                      const NormalMap& normals, const Mask& mask, const std::vector<Mask>& clipped,
                                      const PhotometricStereoParams& params) {
  const std::vector<ImageF> grey = luminances(photographs);
  const std::vector<Eigen::Vector3d> unit = detail::checked_photometric_input(grey, lights, mask, clipped);
  check_normals(normals, int(mask.rows()), int(mask.cols()));
  const int rows = int(mask.rows()), cols = int(mask.cols());
  ColourImage albedo;
  for (auto& channel : albedo.channel) channel = ImageF::Zero(rows, cols);
  detail::parallel_ranges(rows, 8, params.threads, [&](int begin, int end) {
    std::vector<int> usable;
    std::vector<double> ratio;
    for (int r = begin; r < end; ++r)
      for (int c = 0; c < cols; ++c) {
        const Eigen::Vector3d normal = normals.xyz.row(Eigen::Index(r) * cols + c).cast<double>().transpose();
        if (!mask(r, c) || normal.isZero()) continue;
        const Eigen::Vector3f rho = pixel_albedo(photographs, grey, unit, normal, clipped, params, r, c, usable, ratio);
        for (int ch = 0; ch < 3; ++ch) albedo.channel[std::size_t(ch)](r, c) = rho(ch);
      }
  });
  return albedo;
}

}  // namespace shadecut
