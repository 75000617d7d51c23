#include "estimate/estimate_contour_light.hpp"

#include <shadecut/local/local_shape.hpp>
#include <shadecut/support/angular_error.hpp>

#include "support/contour.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace shadecut::detail {

namespace {

// Fewest ring pixels the line is fitted to: three unknowns, and an outline of a few pixels says
// nothing of the light.
constexpr int kMinRingPixels = 16;
// Relative intensity at or below which a ring pixel counts as in attached shadow.
constexpr double kShadow = 1e-3;
constexpr int kMaxRefits = 20;

struct RingPixel {
  Eigen::Vector3d basis;  // (1, o_x, o_y)
  double intensity;
};

}  // namespace

LightEstimate estimate_contour_light(const ImageF& image, const Mask& mask, double albedo, double ring) {
  const int depth = std::max(0, int(std::lround(ring * object_size(mask))));
  const Mask inner = depth > 0 ? erode_mask(mask, depth) : mask;
  std::vector<RingPixel> pixels;
  // erode_mask erodes the image's border too, which is no outline: the ring keeps clear of it.
  const int margin = depth + 1;
  for (int r = margin; r < inner.rows() - margin; ++r) {
    for (int c = margin; c < inner.cols() - margin; ++c) {
      if (!inner(r, c)) continue;
      const Eigen::Vector2d outward = contour_outward(inner, r, c);
      if (outward.isZero()) continue;
      pixels.push_back({Eigen::Vector3d(1.0, outward.x(), outward.y()), std::min(double(image(r, c)), albedo)});
    }
  }
  if (int(pixels.size()) < kMinRingPixels) {
    LightEstimate fallback = estimate_light(image, mask, LightMethod::ZhengChellappa, albedo);
    fallback.uncertainty = std::numeric_limits<double>::quiet_NaN();
    return fallback;
  }
  // Least squares of I = a + w . o over the pixels in use: the lit ones, and the dark ones the line
  // says are lit (a shadowed pixel reads 0 whatever the line says below it).
  std::vector<char> used(pixels.size(), 1);
  Eigen::Vector3d line = Eigen::Vector3d::Zero();
  for (int refit = 0; refit < kMaxRefits; ++refit) {
    Eigen::Matrix3d normal_matrix = Eigen::Matrix3d::Zero();
    Eigen::Vector3d rhs = Eigen::Vector3d::Zero();
    for (std::size_t i = 0; i < pixels.size(); ++i) {
      if (!used[i]) continue;
      normal_matrix += pixels[i].basis * pixels[i].basis.transpose();
      rhs += pixels[i].basis * pixels[i].intensity;
    }
    line = normal_matrix.ldlt().solve(rhs);
    bool changed = false;
    for (std::size_t i = 0; i < pixels.size(); ++i) {
      const char use = pixels[i].intensity > kShadow * albedo || pixels[i].basis.dot(line) > 0.0;
      changed |= use != used[i];
      used[i] = use;
    }
    if (!changed) break;
  }
  double squares = 0.0;
  int count = 0;
  for (std::size_t i = 0; i < pixels.size(); ++i) {
    if (!used[i]) continue;
    squares += std::pow(pixels[i].intensity - pixels[i].basis.dot(line), 2);
    ++count;
  }
  const double a = line.x() / albedo, b = line.tail<2>().norm() / albedo;
  LightEstimate estimate;
  estimate.albedo = albedo;
  estimate.tilt = b > 0.0 ? std::atan2(line.z(), line.y()) : 0.0;
  // cos(sigma - s) = A + B, cos(sigma + s) = A - B.
  const double minus = std::acos(std::clamp(a + b, -1.0, 1.0)), plus = std::acos(std::clamp(a - b, -1.0, 1.0));
  estimate.slant = std::clamp(0.5 * (plus - minus), 0.0, kMaxEstimatedSlant);
  estimate.light = Eigen::Vector3d(std::sin(estimate.slant) * std::cos(estimate.tilt),
                                   std::sin(estimate.slant) * std::sin(estimate.tilt), std::cos(estimate.slant));
  // The ring's misfit, as the turn of the light that would change the ring's brightness by as much:
  // the brightness changes by rho sin(sigma) per radian of S_xy. Not the fit's standard error, which
  // shrinks with the ring's length even where the misfit is the model's (a glossy limb, paint).
  const double misfit = std::sqrt(squares / std::max(1, count)) / albedo;
  const double sin_sigma = std::sin(0.5 * (plus + minus));
  estimate.uncertainty = sin_sigma > 1e-6 ? misfit / sin_sigma : std::numeric_limits<double>::infinity();
  return estimate;
}

}  // namespace shadecut::detail
