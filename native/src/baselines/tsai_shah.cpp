#include <shadecut/baselines/tsai_shah.hpp>

#include <shadecut/support/errors.hpp>
#include <shadecut/support/validate.hpp>

#include "support/parallel.hpp"

#include <algorithm>
#include <cmath>
#include <string>

namespace shadecut {

TsaiShahResult tsai_shah(const ImageF& image, const Mask& mask, const LightFrame& light, double albedo, int iterations,
                         const Progress& progress) {
  check_iterative_input(image, mask, albedo, iterations);

  const int rows = int(image.rows()), cols = int(image.cols());
  const double sx = light.direction.x(), sy = light.direction.y(), sz = light.direction.z();
  TsaiShahResult result;
  result.depth = ImageF::Zero(rows, cols);
  ImageF previous = result.depth;
  ReportClock clock;
  auto inside = [&](int r, int c) { return r >= 0 && r < rows && c >= 0 && c < cols && mask(r, c); };

  for (int iteration = 0; iteration < iterations; ++iteration) {
    previous.swap(result.depth);
    detail::parallel_for(rows, 16, 0, [&](int r) {
      for (int c = 0; c < cols; ++c) {
        if (!mask(r, c)) continue;
        const double z = previous(r, c);
        // Each slope is sign * (z - neighbour): sign +1 for the backward neighbour, -1 for the forward one.
        auto slope = [&](int br, int bc, int fr, int fc, double* sign) {
          *sign = inside(br, bc) ? 1.0 : inside(fr, fc) ? -1.0 : 0.0;
          if (*sign > 0.0) return z - previous(br, bc);
          if (*sign < 0.0) return double(previous(fr, fc)) - z;
          return 0.0;
        };
        double dp = 0.0, dq = 0.0;
        const double p = slope(r, c - 1, r, c + 1, &dp);
        const double q = slope(r + 1, c, r - 1, c, &dq);
        const double norm = std::sqrt(1.0 + p * p + q * q);
        const double reflectance = (sz - p * sx - q * sy) / norm;
        const double derivative = (-sx * dp - sy * dq) / norm - reflectance * (p * dp + q * dq) / (norm * norm);
        const double residual = image(r, c) / albedo - reflectance;
        result.depth(r, c) = float(std::abs(derivative) > 1e-9 ? z + residual / derivative : z);
      }
    });
    result.iterations = iteration + 1;
    if (clock.due() || result.iterations == iterations) progress.report(double(result.iterations) / iterations, "tsai_shah");
  }
  return result;
}

}  // namespace shadecut
