// Block averaging: the one rule by which an image and its mask are made smaller, for the add-on's
// working size and for the coarse levels of the graph cut alike.
#pragma once

#include <shadecut/support/types.hpp>

namespace shadecut {

struct Downsampled {
  ImageF image;  ///< h x w, h = H / factor and w = W / factor (rounded down)
  Mask mask;     ///< h x w
};

/// Shrinks an image by an integer factor. Output pixel (i, j) stands for the factor x factor block at
/// (factor i, factor j): it lies in the mask when at least `min_coverage` (0..1] of the block's pixels
/// do, and then holds the mean of the block's masked pixels; it is 0 elsewhere. Trailing rows and
/// columns that do not fill a block are dropped.
///
/// @param[in] image        H x W.
/// @param[in] mask         H x W.
/// @param[in] factor       >= 1.
/// @param[in] min_coverage share of a block that must be masked, in (0, 1].
/// @throws InvalidArgument for a mask of another shape, factor < 1 or min_coverage outside (0, 1].
Downsampled downsample(const ImageF& image, const Mask& mask, int factor, double min_coverage);

}  // namespace shadecut
