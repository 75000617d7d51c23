#include <shadecut/baselines/pentland.hpp>

#include <shadecut/support/errors.hpp>
#include <shadecut/support/validate.hpp>

#include "integrate/fourier.hpp"
#include "support/masked_gradient.hpp"
#include "support/parallel.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <string>
#include <vector>

namespace shadecut {

namespace {

using Field = std::vector<std::complex<double>>;

// The slope along the light's image direction that the shading asks of each pixel, placed in the
// padded field (0 outside the mask and in the padding), its mean over the image removed. `depth`
// empty: the first-order slope S_z - I / albedo.
Field slope_along_light(const ImageF& image, const Mask& mask, const ImageF& depth, double sz, double albedo, int pad,
                        int padded_cols) {
  const int rows = int(image.rows()), cols = int(image.cols());
  Field field(std::size_t(rows + 2 * pad) * std::size_t(padded_cols), 0.0);
  const Mask whole = Mask::Constant(rows, cols, true);  // the depth covers the image: one-sided only at its edges
  double sum = 0.0;
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) {
      if (!mask(r, c)) continue;
      double root = 1.0;
      if (depth.size() > 0) {
        const detail::MaskedGradient g = detail::masked_gradient(depth, whole, r, c);
        root = std::sqrt(1.0 + g.dx * g.dx + g.dy * g.dy);
      }
      const double slope = sz - double(image(r, c)) / albedo * root;
      field[std::size_t(r + pad) * std::size_t(padded_cols) + std::size_t(c + pad)] = slope;
      sum += slope;
    }
  const double mean = sum / double(rows * cols);
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) field[std::size_t(r + pad) * std::size_t(padded_cols) + std::size_t(c + pad)] -= mean;
  return field;
}

// The depth of least |S_xy . grad z - slope|^2 + smoothness |grad z|^2 (central differences, the
// padded field periodic), cut back to the image and shifted to mean 0.
ImageF solve_depth(Field field, int rows, int cols, int pad, double sx, double sy, double smoothness) {
  const int padded_rows = rows + 2 * pad, padded_cols = cols + 2 * pad;
  detail::fourier_2d(field, padded_rows, padded_cols, detail::FourierDirection::Forward);
  detail::parallel_for(padded_rows, 16, 0, [&](int r) {
    const double across_rows = -std::sin(detail::angular_frequency(r, padded_rows));  // d/dy, y up, over i
    for (int c = 0; c < padded_cols; ++c) {
      const double across_cols = std::sin(detail::angular_frequency(c, padded_cols));  // d/dx over i
      const std::complex<double> along(0.0, sx * across_cols + sy * across_rows);
      const double gradient_power = across_cols * across_cols + across_rows * across_rows;
      const double denominator = std::norm(along) + smoothness * gradient_power;
      std::complex<double>& value = field[std::size_t(r) * std::size_t(padded_cols) + std::size_t(c)];
      value = denominator > 0.0 ? value * std::conj(along) / denominator : 0.0;
    }
  });
  detail::fourier_2d(field, padded_rows, padded_cols, detail::FourierDirection::Inverse);
  ImageF depth(rows, cols);
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c)
      depth(r, c) = float(field[std::size_t(r + pad) * std::size_t(padded_cols) + std::size_t(c + pad)].real());
  depth.array() -= depth.mean();
  return depth;
}

}  // namespace

PentlandResult pentland(const ImageF& image, const Mask& mask, const LightFrame& light, double albedo,
                        double smoothness, int iterations, const Progress& progress) {
  check_iterative_input(image, mask, albedo, iterations);
  if (!(smoothness > 0.0) || !std::isfinite(smoothness))
    throw InvalidArgument("shadecut: pentland's smoothness must be finite and > 0; got " + number_text(smoothness));
  const int rows = int(image.rows()), cols = int(image.cols());
  const int pad = std::max(rows, cols) / 8;
  const Eigen::Vector3d& s = light.direction;
  PentlandResult result;
  for (int solve = 0; solve < iterations; ++solve) {
    result.depth = solve_depth(slope_along_light(image, mask, result.depth, s.z(), albedo, pad, cols + 2 * pad), rows,
                               cols, pad, s.x(), s.y(), smoothness);
    result.iterations = solve + 1;
    progress.report(double(result.iterations) / iterations, "pentland");
  }
  return result;
}

}  // namespace shadecut
