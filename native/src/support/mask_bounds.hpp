// Internal: the rectangle a mask's pixels lie in.
#pragma once

#include <shadecut/support/types.hpp>

#include <optional>

namespace shadecut::detail {

/// Rows [top, top + rows) and columns [left, left + cols) of a frame.
struct Box {
  int top = 0, left = 0, rows = 0, cols = 0;
};

/// The smallest box that holds every pixel of `mask`; std::nullopt for a mask with none.
inline std::optional<Box> mask_bounds(const Mask& mask) {
  const Eigen::Array<bool, Eigen::Dynamic, 1> any_in_row = mask.rowwise().any(), any_in_col = mask.colwise().any().transpose();
  int top = 0, bottom = int(mask.rows()), left = 0, right = int(mask.cols());
  while (top < bottom && !any_in_row(top)) ++top;
  if (top == bottom) return std::nullopt;
  while (!any_in_row(bottom - 1)) --bottom;
  while (!any_in_col(left)) ++left;
  while (!any_in_col(right - 1)) --right;
  return Box{top, left, bottom - top, right - left};
}

}  // namespace shadecut::detail
