#include <shadecut/local_shape.hpp>

#include <shadecut/errors.hpp>
#include <shadecut/validate.hpp>

#include "masked_gradient.hpp"

#include <algorithm>
#include <cmath>

namespace shadecut {

LocalShape local_shape(const ImageF& image, const Mask& mask, const LightFrame& light, double albedo,
                       double min_gradient) {
  check_image(image);
  check_mask(mask, image);
  if (!(albedo > 0.0) || !std::isfinite(albedo)) throw InvalidArgument("shadecut: the albedo must be finite and > 0");
  const int rows = int(image.rows()), cols = int(image.cols());
  LocalShape local{ImageF::Zero(rows, cols), ImageF::Zero(rows, cols), Mask::Constant(rows, cols, false)};
  const double cos_ls = std::cos(light.slant), cos_lt = std::cos(light.tilt), sin_lt = std::sin(light.tilt);

#pragma omp parallel for schedule(static)
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) {
      if (!mask(r, c)) continue;
      local.slant(r, c) = float(std::acos(std::clamp(double(image(r, c)) / albedo, 0.0, 1.0)));
      const detail::MaskedGradient g = detail::masked_gradient(image, mask, r, c);
      const double ix = g.dx, iy = g.dy;
      if (!g.has_x || !g.has_y || std::hypot(ix, iy) < min_gradient * albedo) continue;
      local.tilt(r, c) = float(std::atan2(iy * cos_lt - ix * sin_lt, cos_ls * (ix * cos_lt + iy * sin_lt)));
      local.tilt_defined(r, c) = true;
    }
  }
  return local;
}

NormalMap convex_normals(const LocalShape& local, const LightFrame& light, const Mask& mask) {
  const int rows = int(mask.rows()), cols = int(mask.cols());
  NormalMap normals(rows, cols);
  for (Eigen::Index i = 0; i < normals.size(); ++i) {
    if (!mask.data()[i]) continue;
    const double tilt = local.tilt_defined.data()[i] ? double(local.tilt.data()[i]) + M_PI : M_PI;
    normals.xyz.row(i) = light.normal(local.slant.data()[i], tilt).cast<float>();
  }
  return normals;
}

}  // namespace shadecut
