// The 4-connected parts of a mask: each is an independent surface, its depth known up to a constant.
#pragma once

#include <shadecut/support/types.hpp>

#include <Eigen/Core>

#include <cstdint>

namespace shadecut {

/// H x W component labels, row-major.
using Labels = Eigen::Array<std::int32_t, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

struct MaskComponents {
  Labels labels;  ///< H x W: -1 outside the mask, 0 .. count - 1 inside
  int count = 0;  ///< number of components
};

/// Labels the 4-connected components of `mask`, numbered in the raster order (row by row, left to
/// right) of each component's first pixel. An empty mask has no component.
MaskComponents mask_components(const Mask& mask);

}  // namespace shadecut
