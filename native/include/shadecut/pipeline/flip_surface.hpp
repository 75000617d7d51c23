// A reconstructed surface turned inside out: the other answer an image lit from near the viewer
// allows (a dome and its hollow render alike under a frontal light).
#pragma once

#include <shadecut/support/types.hpp>

namespace shadecut {

/// Inverts a surface in place: depth z -> -z, then every 4-connected component of the mask shifted
/// so that its minimum is 0 again (rebase_depth: the gauge of every reconstructed depth), and
/// normals (nx, ny, nz) -> (-nx, -ny, nz), the normals of the inverted depth. Flipping twice gives
/// back the surface.
///
/// @param[in,out] depth   H x W, pixel units, larger = closer.
/// @param[in,out] normals H x W camera-frame unit normals (0 outside the mask stays 0).
/// @param[in]     mask    H x W, the surface's pixels; depth outside it is left as it is.
/// @throws InvalidArgument when the shapes differ.
void flip_surface(ImageF& depth, NormalMap& normals, const Mask& mask);

}  // namespace shadecut
