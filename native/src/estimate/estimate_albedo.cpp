#include <shadecut/estimate/estimate_albedo.hpp>

#include <shadecut/support/errors.hpp>
#include <shadecut/support/validate.hpp>

#include "support/enum_names.hpp"
#include "support/parallel.hpp"

#include <algorithm>
#include <cmath>
#include <functional>

namespace shadecut {

namespace {

void order(float& low, float& high) {
  const float smaller = std::min(low, high);
  high = std::max(low, high);
  low = smaller;
}

// The median of nine by Paeth's exchange network (Graphics Gems, 1990): 19 branch-free min/max
// pairs, which the compiler vectorizes over a row, as it cannot an nth_element per pixel.
float median_of_nine(float p0, float p1, float p2, float p3, float p4, float p5, float p6, float p7, float p8) {
  order(p1, p2), order(p4, p5), order(p7, p8), order(p0, p1), order(p3, p4), order(p6, p7);
  order(p1, p2), order(p4, p5), order(p7, p8), order(p0, p3), order(p5, p8), order(p4, p7);
  order(p3, p6), order(p1, p4), order(p2, p5), order(p4, p7), order(p4, p2), order(p6, p4);
  order(p4, p2);
  return p4;
}

// The median of each pixel's 3 x 3 neighbourhood, the border repeated outward.
ImageF median_3x3(const ImageF& image) {
  const Eigen::Index rows = image.rows(), cols = image.cols();
  Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> padded(rows + 2, cols + 2);
  for (Eigen::Index r = -1; r <= rows; ++r)
    for (Eigen::Index c = -1; c <= cols; ++c)
      padded(r + 1, c + 1) = image(std::clamp(r, Eigen::Index(0), rows - 1), std::clamp(c, Eigen::Index(0), cols - 1));
  ImageF filtered(rows, cols);
  detail::parallel_for(int(rows), 16, 0, [&](int r) {
    const float* up = &padded(r, 0);
    const float* middle = &padded(r + 1, 0);
    const float* down = &padded(r + 2, 0);
    float* out = &filtered(r, 0);
    for (Eigen::Index c = 0; c < cols; ++c)
      out[c] = median_of_nine(up[c], up[c + 1], up[c + 2], middle[c], middle[c + 1], middle[c + 2], down[c],
                              down[c + 1], down[c + 2]);
  });
  return filtered;
}

double brightest(const ImageF& image, const Mask& mask) {
  const ImageF filtered = median_3x3(image);
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
  static const std::vector<std::string> names{"brightest", "top_fit", "retinex"};
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
  if (method == AlbedoMethod::Retinex)
    throw InvalidArgument("shadecut: the albedo method retinex gives one albedo per pixel; reconstruct() reads it "
                          "(estimate_reflectance), estimate_albedo only top_fit or brightest");
  const double largest = brightest(image, mask);
  double albedo = method == AlbedoMethod::TopFit ? top_fit(image, mask, window) : std::nan("");
  if (!std::isfinite(albedo) || largest <= albedo * (1.0 + window.agreement)) albedo = largest;
  if (!(albedo > 0.0)) throw InvalidArgument("shadecut: the image is dark everywhere in the mask; nothing to reconstruct");
  return albedo;
}

}  // namespace shadecut
