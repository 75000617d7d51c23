#include <shadecut/estimate/estimate_light.hpp>

#include <shadecut/support/errors.hpp>
#include <shadecut/estimate/estimate_albedo.hpp>
#include <shadecut/support/validate.hpp>

#include "support/enum_names.hpp"
#include "estimate/estimate_contour_light.hpp"
#include "estimate/estimate_relief_light.hpp"
#include "support/masked_gradient.hpp"

#include <algorithm>
#include <cmath>

namespace shadecut {

namespace {

// Moments of the image of a unit-albedo Lambertian sphere seen whole, light at slant s, attached
// shadow included: E1 = mean of max(0, n.S), E2 = mean of max(0, n.S)^2 over the disc.
double shadowed_mean(double s) { return 2.0 * ((M_PI - s) * std::cos(s) + std::sin(s)) / (3.0 * M_PI); }
double shadowed_mean_square(double s) { return std::pow(1.0 + std::cos(s), 2) / 8.0; }

}  // namespace

const std::vector<std::string>& light_method_names() {
  static const std::vector<std::string> names{"lee_rosenfeld", "zheng_chellappa", "relief", "contour"};
  return names;
}

LightMethod parse_light_method(const std::string& name) {
  return parse_enum<LightMethod>(light_method_names(), name, "light estimator");
}

std::string to_string(LightMethod method) { return light_method_names().at(std::size_t(method)); }

LightEstimate estimate_light(const ImageF& image_in, const Mask& mask, LightMethod method, std::optional<double> ceiling) {
  check_image(image_in);
  check_mask(mask, image_in);
  if (image_in.minCoeff() < 0.0f) throw InvalidArgument("shadecut: the image has negative intensities; linear intensity is >= 0");
  if (ceiling) check_albedo(*ceiling);
  if (mask.count() < kMinLightPixels)
    throw InvalidArgument("shadecut: the light cannot be estimated from " + std::to_string(mask.count()) +
                          " pixel" + (mask.count() == 1 ? "" : "s") + ": the estimators read the statistics of the "
                          "shading over at least " + std::to_string(kMinLightPixels) + " pixels; give the light");
  if (method == LightMethod::Relief) return detail::estimate_relief_light(image_in, mask, ceiling);
  if (method == LightMethod::Contour)
    return detail::estimate_contour_light(image_in, mask, ceiling ? *ceiling : estimate_albedo(image_in, mask));
  // Highlights and saturated spots would pull the light toward them: above the albedo no Lambertian
  // surface of it shows, so the image is read clipped there.
  const ImageF image = image_in.min(float(ceiling ? *ceiling : estimate_albedo(image_in, mask)));
  const int rows = int(image.rows()), cols = int(image.cols());
  double sum = 0.0, sum_square = 0.0, count = 0.0;
  Eigen::Vector2d direction_sum = Eigen::Vector2d::Zero(), gradient_sum = Eigen::Vector2d::Zero();
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) {
      if (!mask(r, c)) continue;
      const double intensity = image(r, c);
      sum += intensity;
      sum_square += intensity * intensity;
      count += 1.0;
      const detail::MaskedGradient g = detail::masked_gradient(image, mask, r, c);
      if (!g.has_x || !g.has_y) continue;
      const Eigen::Vector2d gradient(g.dx, g.dy);
      gradient_sum += gradient;
      if (gradient.norm() > 0.0) direction_sum += gradient.normalized();
    }
  }
  const double mean = sum / count, mean_square = sum_square / count;
  if (!(mean > 0.0)) throw InvalidArgument("shadecut: the image is dark everywhere in the mask; nothing to reconstruct");
  const double ratio = mean * mean / mean_square;  // in (0, 1] by Cauchy-Schwarz

  LightEstimate estimate;
  const Eigen::Vector2d tilt_vector = method == LightMethod::LeeRosenfeld ? direction_sum : gradient_sum;
  estimate.tilt = tilt_vector.norm() > 0.0 ? std::atan2(tilt_vector.y(), tilt_vector.x()) : 0.0;
  if (method == LightMethod::LeeRosenfeld) {
    // ratio = (16/9) c^2 / (1 + c^2) with c = cos(slant); every ratio >= 8/9 means a frontal light.
    const double c2 = ratio >= 8.0 / 9.0 ? 1.0 : ratio / (16.0 / 9.0 - ratio);
    estimate.slant = std::min(kMaxEstimatedSlant, std::acos(std::sqrt(c2)));
    estimate.albedo = mean / (2.0 / 3.0 * std::cos(estimate.slant));
  } else {
    // mean^2 / mean_square falls monotonically from 8/9 (frontal) to 32 / (9 pi^2) (grazing).
    double low = 0.0, high = kMaxEstimatedSlant;
    auto ratio_at = [](double s) { return std::pow(shadowed_mean(s), 2) / shadowed_mean_square(s); };
    if (ratio >= ratio_at(low)) {
      high = low;
    } else if (ratio > ratio_at(high)) {
      for (int i = 0; i < 60; ++i) {
        const double middle = 0.5 * (low + high);
        (ratio_at(middle) > ratio ? low : high) = middle;
      }
    }
    estimate.slant = high;
    estimate.albedo = mean / shadowed_mean(estimate.slant);
  }
  estimate.light = Eigen::Vector3d(std::sin(estimate.slant) * std::cos(estimate.tilt),
                                   std::sin(estimate.slant) * std::sin(estimate.tilt), std::cos(estimate.slant));
  return estimate;
}

}  // namespace shadecut
