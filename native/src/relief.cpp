#include <shadecut/relief.hpp>

#include <shadecut/errors.hpp>
#include <shadecut/mask_components.hpp>

#include <Eigen/Dense>

#include <limits>
#include <vector>

namespace shadecut {

double relief_albedo(const ImageF& image, const Mask& mask, const Eigen::Vector3d& light) {
  const double mean = (image * mask.cast<float>()).cast<double>().sum() / double(std::max<Eigen::Index>(1, mask.count()));
  if (!(mean > 0.0)) throw InvalidArgument("shadecut: the image is dark everywhere in the mask; nothing to reconstruct");
  return mean / light.z();
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
  const MaskComponents components = mask_components(mask);
  std::vector<float> minimum(std::size_t(components.count), std::numeric_limits<float>::infinity());
  for (Eigen::Index r = 0; r < depth.rows(); ++r) {
    for (Eigen::Index c = 0; c < depth.cols(); ++c) {
      if (!mask(r, c)) continue;
      depth(r, c) -= float(plane.x() * double(c) - plane.y() * double(r) + plane.z());
      float& lowest = minimum[std::size_t(components.labels(r, c))];
      lowest = std::min(lowest, depth(r, c));
      auto n = normals.xyz.row(r * depth.cols() + c);
      if (!(n.z() > 0.0f)) continue;
      const double p = -n.x() / n.z() - plane.x(), q = -n.y() / n.z() - plane.y();
      n = Eigen::Vector3f(float(-p), float(-q), 1.0f).normalized().transpose();
    }
  }
  for (Eigen::Index i = 0; i < depth.size(); ++i)
    if (mask.data()[i]) depth.data()[i] -= minimum[std::size_t(components.labels.data()[i])];
}

}  // namespace shadecut
