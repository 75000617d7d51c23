#include <shadecut/support/render.hpp>

#include <shadecut/support/errors.hpp>
#include <shadecut/support/light.hpp>
#include <shadecut/support/validate.hpp>

#include "support/masked_gradient.hpp"

#include <algorithm>

namespace shadecut {

NormalMap normals_from_depth(const ImageF& depth, const Mask& mask) {
  check_image(depth, "depth map");
  check_mask(mask, depth);
  const int rows = int(depth.rows()), cols = int(depth.cols());
  NormalMap normals(rows, cols);
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) {
      if (!mask(r, c)) continue;
      const detail::MaskedGradient g = detail::masked_gradient(depth, mask, r, c);
      normals.xyz.row(Eigen::Index(r) * cols + c) = Eigen::Vector3d(-g.dx, -g.dy, 1.0).normalized().cast<float>();
    }
  }
  return normals;
}

NormalMap normals_from_periodic_depth(const ImageF& depth) {
  check_image(depth, "depth map");
  const int rows = int(depth.rows()), cols = int(depth.cols());
  NormalMap normals(rows, cols);
  for (int r = 0; r < rows; ++r) {
    const int up = (r + rows - 1) % rows, down = (r + 1) % rows;
    for (int c = 0; c < cols; ++c) {
      const int left = (c + cols - 1) % cols, right = (c + 1) % cols;
      const double dx = 0.5 * (double(depth(r, right)) - depth(r, left));
      const double dy = 0.5 * (double(depth(up, c)) - depth(down, c));  // y grows upward
      normals.xyz.row(Eigen::Index(r) * cols + c) = Eigen::Vector3d(-dx, -dy, 1.0).normalized().cast<float>();
    }
  }
  return normals;
}

ImageF render_lambertian(const NormalMap& normals, const Eigen::Vector3d& light, double albedo, const Mask& mask) {
  if (!(albedo >= 0.0) || !std::isfinite(albedo)) throw InvalidArgument("shadecut: the albedo must be finite and >= 0");
  check_mask_fits(mask, normals);
  const Eigen::Vector3f s = LightFrame::from_direction(light).direction.cast<float>();
  ImageF image = ImageF::Zero(normals.rows, normals.cols);
  for (Eigen::Index i = 0; i < normals.size(); ++i) {
    if (!mask.data()[i]) continue;
    image.data()[i] = float(albedo) * std::max(0.0f, normals.xyz.row(i).dot(s));
  }
  return image;
}

double brightness_residual(const ImageF& depth, const ImageF& image, const Mask& mask, const Mask& counted,
                           const Eigen::Vector3d& light, double albedo) {
  const ImageF rendered = render_lambertian(normals_from_depth(depth, mask), light, albedo, mask);
  return counted.select((rendered - image).cast<double>().square(), 0.0).sum();
}

double mean_brightness_residual(const ImageF& depth, const ImageF& image, const Mask& mask, const Mask& counted,
                                const Eigen::Vector3d& light, double albedo) {
  const Eigen::Index pixels = counted.count();
  return pixels ? brightness_residual(depth, image, mask, counted, light, albedo) / double(pixels) : 0.0;
}

}  // namespace shadecut
