#include <shadecut/estimate_albedo.hpp>

#include <shadecut/errors.hpp>
#include <shadecut/validate.hpp>

#include "enum_names.hpp"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <functional>

namespace shadecut {

namespace {

double brightest(const ImageF& image, const Mask& mask) {
  ImageF filtered(image.rows(), image.cols());
  const cv::Mat source(int(image.rows()), int(image.cols()), CV_32F, const_cast<float*>(image.data()));
  cv::Mat target(int(image.rows()), int(image.cols()), CV_32F, filtered.data());
  cv::medianBlur(source, target, 3);
  float largest = 0.0f;
  for (Eigen::Index i = 0; i < image.size(); ++i)
    if (mask.data()[i]) largest = std::max(largest, filtered.data()[i]);
  return largest;
}

// The albedo at which the least-squares line through (share, intensity^2) of the sorted intensities
// in the window reaches share 0; NaN when the window is too small to fit.
double top_fit(const ImageF& image, const Mask& mask, const TopFitWindow& window) {
  std::vector<float> values;
  values.reserve(std::size_t(mask.count()));
  for (Eigen::Index i = 0; i < image.size(); ++i)
    if (mask.data()[i]) values.push_back(image.data()[i]);
  const double count = double(values.size());
  const std::size_t first = std::size_t(std::floor(window.from * count));
  const std::size_t last = std::min(values.size(), std::size_t(std::ceil(window.to * count)));
  if (last < first + 3) return std::nan("");
  std::partial_sort(values.begin(), values.begin() + std::ptrdiff_t(last), values.end(), std::greater<float>());
  double sum_a = 0.0, sum_t = 0.0, sum_aa = 0.0, sum_at = 0.0;
  for (std::size_t i = first; i < last; ++i) {
    const double share = (double(i) + 0.5) / count, t = double(values[i]) * values[i];
    sum_a += share, sum_t += t, sum_aa += share * share, sum_at += share * t;
  }
  const double n = double(last - first);
  const double slope = (n * sum_at - sum_a * sum_t) / (n * sum_aa - sum_a * sum_a);
  // A brightness that grows with the share is no falling edge: the window's brightest value is the
  // best that can be said.
  if (!(slope < 0.0)) return values[first];
  return std::sqrt(std::max(0.0, (sum_t - slope * sum_a) / n));
}

}  // namespace

const std::vector<std::string>& albedo_method_names() {
  static const std::vector<std::string> names{"brightest", "top_fit"};
  return names;
}

AlbedoMethod parse_albedo_method(const std::string& name) {
  return parse_enum<AlbedoMethod>(albedo_method_names(), name, "albedo method");
}

std::string to_string(AlbedoMethod method) { return albedo_method_names().at(std::size_t(method)); }

double estimate_albedo(const ImageF& image, const Mask& mask, AlbedoMethod method, const TopFitWindow& window) {
  check_image(image);
  check_mask(mask, image);
  if (!(window.from >= 0.0 && window.from < window.to && window.to <= 1.0 && window.agreement >= 0.0))
    throw InvalidArgument("shadecut: the top_fit window must satisfy 0 <= from < to <= 1 and agreement >= 0");
  const double largest = brightest(image, mask);
  double albedo = method == AlbedoMethod::TopFit ? top_fit(image, mask, window) : std::nan("");
  if (!std::isfinite(albedo) || largest <= albedo * (1.0 + window.agreement)) albedo = largest;
  if (!(albedo > 0.0)) throw InvalidArgument("shadecut: the image is dark everywhere in the mask; nothing to reconstruct");
  return albedo;
}

}  // namespace shadecut
