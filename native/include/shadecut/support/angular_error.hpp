// Angular error between two normal fields: the measure of every ShadeCut evaluation.
#pragma once

#include <shadecut/support/types.hpp>

namespace shadecut {

/// Per-pixel angle between two normal fields.
///
/// @param[in] a, b  H x W normals (need not be unit length; zero vectors give NaN).
/// @param[in] mask  H x W; pixels outside it are NaN.
/// @return H x W angles in degrees.
ImageF angular_error_map(const NormalMap& a, const NormalMap& b, const Mask& mask);

/// Mean of angular_error_map over the masked pixels where both fields have a normal (a zero vector
/// has none), degrees. Throws InvalidArgument when no pixel is left.
double mean_angular_error(const NormalMap& a, const NormalMap& b, const Mask& mask);

/// The mask shrunk by `pixels` steps of 4-neighbour erosion (pixels on the image border erode too).
Mask erode_mask(const Mask& mask, int pixels);

}  // namespace shadecut
