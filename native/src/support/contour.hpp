// Internal: the mask's edge read as an occluding contour, shared by the shadow filling and Brooks &
// Horn's boundary condition so that both take the same normals there.
#pragma once

#include <shadecut/support/types.hpp>

#include <Eigen/Core>

namespace shadecut::detail {

/// Outward unit direction of the mask's edge at masked pixel (r, c) in the image plane (x right,
/// y up): the sum of the directions toward its unmasked 4-neighbours. Zero inside the mask, where
/// those directions cancel, and on the image border, where the edge is only the frame.
inline Eigen::Vector2d contour_outward(const Mask& mask, int r, int c) {
  const int rows = int(mask.rows()), cols = int(mask.cols());
  if (r == 0 || c == 0 || r == rows - 1 || c == cols - 1) return Eigen::Vector2d::Zero();
  const Eigen::Vector2d d(double(!mask(r, c + 1)) - double(!mask(r, c - 1)),
                          double(!mask(r - 1, c)) - double(!mask(r + 1, c)));
  return d.norm() > 0.5 ? Eigen::Vector2d(d.normalized()) : Eigen::Vector2d::Zero();
}

}  // namespace shadecut::detail
