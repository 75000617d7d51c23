#include <shadecut/support/angular_error.hpp>

#include <shadecut/support/errors.hpp>
#include <shadecut/support/validate.hpp>

#include <Eigen/Geometry>

#include <cmath>
#include <limits>

namespace shadecut {

ImageF angular_error_map(const NormalMap& a, const NormalMap& b, const Mask& mask) {
  check_normals(b, a.rows, a.cols);
  check_mask_fits(mask, a);
  check_mask_fits(mask, b);
  ImageF degrees = ImageF::Constant(mask.rows(), mask.cols(), std::numeric_limits<float>::quiet_NaN());
  for (Eigen::Index i = 0; i < a.size(); ++i) {
    if (!mask.data()[i]) continue;
    const Eigen::Vector3d u = a.xyz.row(i).cast<double>(), v = b.xyz.row(i).cast<double>();
    // atan2 of |u x v| and u . v stays accurate for tiny angles, where acos of the dot product does not.
    degrees.data()[i] = float(std::atan2(u.cross(v).norm(), u.dot(v)) * 180.0 / M_PI);
    if (u.squaredNorm() == 0.0 || v.squaredNorm() == 0.0) degrees.data()[i] = std::numeric_limits<float>::quiet_NaN();
  }
  return degrees;
}

double mean_angular_error(const NormalMap& a, const NormalMap& b, const Mask& mask) {
  const ImageF degrees = angular_error_map(a, b, mask);
  double sum = 0.0;
  Eigen::Index count = 0;
  for (Eigen::Index i = 0; i < degrees.size(); ++i) {
    if (mask.data()[i] && !std::isnan(degrees.data()[i])) {
      sum += degrees.data()[i];
      ++count;
    }
  }
  if (count == 0) throw InvalidArgument("shadecut: the mask for the angular error selects no pixel with two normals");
  return sum / double(count);
}

Mask erode_mask(const Mask& mask, int pixels) {
  Mask current = mask;
  const Eigen::Index rows = mask.rows(), cols = mask.cols();
  for (int step = 0; step < pixels; ++step) {
    Mask next = current;
    for (Eigen::Index r = 0; r < rows; ++r)
      for (Eigen::Index c = 0; c < cols; ++c)
        if (current(r, c))
          next(r, c) = r > 0 && r + 1 < rows && c > 0 && c + 1 < cols && current(r - 1, c) && current(r + 1, c) &&
                       current(r, c - 1) && current(r, c + 1);
    // Past the point where erosion changes nothing more steps cannot either.
    if ((next == current).all()) break;
    current = std::move(next);
  }
  return current;
}

}  // namespace shadecut
