// Tsai & Shah's linear shape from shading, the local method the paper compares with.
#pragma once

#include <shadecut/support/light.hpp>
#include <shadecut/support/progress.hpp>
#include <shadecut/support/types.hpp>

namespace shadecut {

struct TsaiShahResult {
  ImageF depth;        ///< H x W, pixel units, larger = closer, 0 outside the mask (not shifted)
  int iterations = 0;  ///< sweeps done
};

/// Tsai & Shah (1994): with p = dz/dx and q = dz/dy taken as backward differences of the depth
/// (toward the left and the lower neighbour; the forward one where that is outside the mask),
/// the reflectance R(p, q) = (S_z - p S_x - q S_y) / sqrt(1 + p^2 + q^2) is linearized in the depth of
/// each pixel, and f(Z) = E/albedo - R = 0 is solved by one Newton step per pixel per sweep, all pixels
/// from the previous sweep's depth (Jacobi), starting from Z = 0. A pixel whose dR/dZ vanishes keeps
/// its depth for that sweep.
///
/// @param[in] image      H x W linear intensity.
/// @param[in] mask       H x W pixels to reconstruct.
/// @param[in] light      the light frame (LightFrame::from_direction).
/// @param[in] albedo     > 0.
/// @param[in] iterations sweeps, >= 1.
/// @param[in] progress   told the fraction of the sweeps done, as stage "tsai_shah"; may throw Cancelled.
TsaiShahResult tsai_shah(const ImageF& image, const Mask& mask, const LightFrame& light, double albedo, int iterations,
                         const Progress& progress = {});

}  // namespace shadecut
