#include <shadecut/render.hpp>

#include <shadecut/errors.hpp>
#include <shadecut/light.hpp>
#include <shadecut/validate.hpp>

#include <algorithm>

namespace shadecut {

namespace {

// Derivative along one axis at (r, c) from the masked neighbours only; `before`/`after` are the
// neighbours at -1 / +1 steps along the axis (nullptr when outside the image or the mask).
float masked_derivative(float centre, const float* before, const float* after) {
  if (before && after) return 0.5f * (*after - *before);
  if (after) return *after - centre;
  if (before) return centre - *before;
  return 0.0f;
}

}  // namespace

NormalMap normals_from_depth(const ImageF& depth, const Mask& mask) {
  check_image(depth, "depth map");
  check_mask(mask, depth);
  const int rows = int(depth.rows()), cols = int(depth.cols());
  NormalMap normals(rows, cols);
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) {
      if (!mask(r, c)) continue;
      auto at = [&](int rr, int cc) -> const float* {
        if (rr < 0 || rr >= rows || cc < 0 || cc >= cols || !mask(rr, cc)) return nullptr;
        return &depth(rr, cc);
      };
      const float dz_dx = masked_derivative(depth(r, c), at(r, c - 1), at(r, c + 1));
      // y is up, so the row below is one step in -y.
      const float dz_dy = masked_derivative(depth(r, c), at(r + 1, c), at(r - 1, c));
      Eigen::Vector3f n(-dz_dx, -dz_dy, 1.0f);
      normals.xyz.row(Eigen::Index(r) * cols + c) = n.normalized();
    }
  }
  return normals;
}

ImageF render_lambertian(const NormalMap& normals, const Eigen::Vector3d& light, double albedo, const Mask& mask) {
  if (!(albedo >= 0.0) || !std::isfinite(albedo)) throw InvalidArgument("shadecut: the albedo must be finite and >= 0");
  check_normals(normals, int(mask.rows()), int(mask.cols()));
  const Eigen::Vector3f s = LightFrame::from_direction(light).direction.cast<float>();
  ImageF image = ImageF::Zero(normals.rows, normals.cols);
  for (Eigen::Index i = 0; i < normals.size(); ++i) {
    if (!mask.data()[i]) continue;
    image.data()[i] = float(albedo) * std::max(0.0f, normals.xyz.row(i).dot(s));
  }
  return image;
}

}  // namespace shadecut
