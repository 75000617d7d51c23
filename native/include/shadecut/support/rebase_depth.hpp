// The gauge of a reconstructed depth: each connected part of the mask is its own surface, known up to
// a constant, and that constant is fixed by its lowest point.
#pragma once

#include <shadecut/support/types.hpp>

namespace shadecut {

/// Shifts the depth of every 4-connected component of `mask` so that its minimum is 0.
///
/// @param[in,out] depth H x W, pixel units; pixels outside the mask are left as they are.
/// @param[in]     mask  H x W.
void rebase_depth(ImageF& depth, const Mask& mask);

}  // namespace shadecut
