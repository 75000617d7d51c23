#include <shadecut/pipeline/relief.hpp>

#include <shadecut/support/errors.hpp>
#include <shadecut/support/rebase_depth.hpp>

#include <Eigen/Dense>

#include <algorithm>
#include <limits>
#include <vector>

namespace shadecut {

double median_intensity(const ImageF& image, const Mask& mask) {
  std::vector<float> values;
  values.reserve(std::size_t(mask.count()));
  for (Eigen::Index i = 0; i < image.size(); ++i)
    if (mask.data()[i]) values.push_back(image.data()[i]);
  if (values.empty()) throw InvalidArgument("shadecut: the mask selects no pixel");
  const auto middle = values.begin() + std::ptrdiff_t(values.size() / 2);
  std::nth_element(values.begin(), middle, values.end());
  if (!(*middle > 0.0f)) throw InvalidArgument("shadecut: the image is dark in most of the relief; nothing to reconstruct");
  return double(*middle);
}

double relief_albedo(const ImageF& image, const Mask& mask, const Eigen::Vector3d& light) {
  return median_intensity(image, mask) / light.z();
}

void flatten_relief(ImageF& depth, NormalMap& normals, const Mask& mask) {
  Eigen::Matrix3d normal_matrix = Eigen::Matrix3d::Zero();
  Eigen::Vector3d rhs = Eigen::Vector3d::Zero();
  for (Eigen::Index r = 0; r < depth.rows(); ++r) {
    for (Eigen::Index c = 0; c < depth.cols(); ++c) {
      if (!mask(r, c)) continue;
      const Eigen::Vector3d basis(double(c), -double(r), 1.0);
      normal_matrix += basis * basis.transpose();
      rhs += basis * double(depth(r, c));
    }
  }
  if (mask.count() < 3) return;
  // z = a x + b y + c; removing it changes the gradients (p, q) by (-a, -b) everywhere.
  const Eigen::Vector3d plane = normal_matrix.ldlt().solve(rhs);
  for (Eigen::Index r = 0; r < depth.rows(); ++r) {
    for (Eigen::Index c = 0; c < depth.cols(); ++c) {
      if (!mask(r, c)) continue;
      depth(r, c) -= float(plane.x() * double(c) - plane.y() * double(r) + plane.z());
      auto n = normals.xyz.row(r * depth.cols() + c);
      if (!(n.z() > 0.0f)) continue;
      const double p = -n.x() / n.z() - plane.x(), q = -n.y() / n.z() - plane.y();
      n = Eigen::Vector3f(float(-p), float(-q), 1.0f).normalized().transpose();
    }
  }
  rebase_depth(depth, mask);
}

}  // namespace shadecut
