// Pentland's linear shape from shading, for reliefs: the depth from the slope along the light.
#pragma once

#include <shadecut/support/light.hpp>
#include <shadecut/support/progress.hpp>
#include <shadecut/support/types.hpp>

namespace shadecut {

struct PentlandResult {
  ImageF depth;        ///< H x W, pixel units, larger = closer, mean 0 over the image
  int iterations = 0;  ///< solves done
};

/// Pentland (1990), made a least-squares fit. A relief is nearly flat, so its shading is nearly linear
/// in the depth's gradient: with p = dz/dx, q = dz/dy (x to the right, y up) and the unit light S,
/// I / albedo = (S_z - p S_x - q S_y) / sqrt(1 + p^2 + q^2), so at every masked pixel the slope along
/// the light's image direction is known,
///
///   p S_x + q S_y = S_z - (I / albedo) sqrt(1 + p^2 + q^2),
///
/// and the slope across it is what one image leaves open. Each solve finds the depth of least
/// sum |S_xy . grad z - that slope|^2 + smoothness |grad z|^2 over the image, with central differences,
/// by one 2-D FFT of the image padded on every side by an eighth of its larger side; outside the mask
/// and in the padding the slope is 0 (flat ground), and the slope's mean over the image (a tilt of the
/// whole) is left out. The first solve takes the square root as 1; each further one takes it from the
/// last solution's central differences.
///
/// @param[in] image       H x W linear intensity.
/// @param[in] mask        H x W pixels whose intensity is read.
/// @param[in] light       the light frame (LightFrame::from_direction); its direction has S_z > 0.
/// @param[in] albedo      > 0.
/// @param[in] smoothness  > 0: the weight of |grad z|^2 against the slope along the light (a ratio of
///                        two squared slopes, the same at every resolution).
/// @param[in] iterations  solves, >= 1.
/// @param[in] progress    told the fraction of the solves done, as stage "pentland"; may throw Cancelled.
PentlandResult pentland(const ImageF& image, const Mask& mask, const LightFrame& light, double albedo,
                        double smoothness, int iterations, const Progress& progress = {});

}  // namespace shadecut
