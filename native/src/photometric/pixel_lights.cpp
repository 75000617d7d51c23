#include "photometric/pixel_lights.hpp"

#include <shadecut/support/errors.hpp>
#include <shadecut/support/validate.hpp>

#include <cmath>

namespace shadecut::detail {

PixelLights::PixelLights(const std::vector<Eigen::Vector3d>& distant, const NearLamps& lamps)
    : distant_(distant), lamps_(lamps), directions_(distant), strengths_(distant.size(), 1.0) {}

void PixelLights::at(int r, int c) {
  if (!near()) return;
  const double depth = lamps_.depth.size() > 0 ? double(lamps_.depth(r, c)) : 0.0;
  const Eigen::Vector3d point(double(c), -double(r), depth);
  for (std::size_t k = 0; k < distant_.size(); ++k) {
    const Eigen::Vector3d toward = lamps_.centre + lamps_.distance * distant_[k] - point;
    const double length = toward.norm();
    directions_[k] = toward / length;
    strengths_[k] = std::pow(lamps_.distance / length, 2);
  }
}

void check_lamps(const NearLamps& lamps, int rows, int cols) {
  if (!(lamps.distance >= 0.0) || !std::isfinite(lamps.distance))
    throw InvalidArgument("shadecut: the lamps' distance must be finite and >= 0 (0 = distant lights), got " +
                          number_text(lamps.distance));
  if (!lamps.centre.allFinite()) throw InvalidArgument("shadecut: the lamps' centre holds a NaN or infinite value");
  if (lamps.depth.size() > 0 && (lamps.depth.rows() != rows || lamps.depth.cols() != cols))
    throw InvalidArgument("shadecut: the lamps' depth does not have the photographs' size");
  if (lamps.depth.size() > 0 && !lamps.depth.isFinite().all())
    throw InvalidArgument("shadecut: the lamps' depth holds a NaN or infinite value");
}

}  // namespace shadecut::detail
