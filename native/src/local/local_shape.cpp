#include <shadecut/local/local_shape.hpp>

#include <shadecut/support/errors.hpp>
#include <shadecut/support/validate.hpp>

#include "support/masked_gradient.hpp"
#include "support/parallel.hpp"

#include <algorithm>
#include <cmath>

namespace shadecut {

double object_size(const Mask& mask) { return std::sqrt(double(mask.count())); }

double unary_scale(const Mask& mask) { return kReferenceObjectSize / object_size(mask); }

LocalShape local_shape(const ImageF& image, const Mask& mask, const LightFrame& light, double albedo,
                       double min_curvature) {
  check_image(image);
  check_mask(mask, image);
  check_albedo(albedo);
  if (!(min_curvature >= 0.0) || !std::isfinite(min_curvature))
    throw InvalidArgument("shadecut: min_curvature must be finite and >= 0");
  const int rows = int(image.rows()), cols = int(image.cols());
  LocalShape local{ImageF::Zero(rows, cols), ImageF::Zero(rows, cols), Mask::Constant(rows, cols, false)};
  const double cos_ls = std::cos(light.slant), cos_lt = std::cos(light.tilt), sin_lt = std::sin(light.tilt);
  const double size = object_size(mask);

  detail::parallel_for(rows, 16, 0, [&](int r) {
    for (int c = 0; c < cols; ++c) {
      if (!mask(r, c)) continue;
      const double shading = std::clamp(double(image(r, c)) / albedo, 0.0, 1.0);
      local.slant(r, c) = float(std::acos(shading));
      const detail::MaskedGradient g = detail::masked_gradient(image, mask, r, c);
      const double ix = g.dx, iy = g.dy;
      // A sphere of radius R pixels shades its pixels of slant s with |grad I| ~ albedo sin(s) / R, so
      // |grad I| size / (albedo sin s) is the object's size over the radius of the sphere this pixel
      // would belong to: the curvature the local model reads, in units of the object, the same at any
      // resolution. Below min_curvature the patch is as good as flat and its shading says nothing
      // about the tilt. Zero gradient (a plane, the brightest point) never defines a tilt.
      const double gradient = std::hypot(ix, iy), sin_s = std::sqrt(1.0 - shading * shading);
      if (!g.has_x || !g.has_y || !(gradient > 0.0) || gradient * size < min_curvature * albedo * sin_s) continue;
      local.tilt(r, c) = float(std::atan2(iy * cos_lt - ix * sin_lt, cos_ls * (ix * cos_lt + iy * sin_lt)));
      local.tilt_defined(r, c) = true;
    }
  });
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
