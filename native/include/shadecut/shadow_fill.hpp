// Normals inside attached shadows, where the image says nothing but "facing away from the light".
#pragma once

#include <shadecut/types.hpp>

namespace shadecut {

/// Replaces the normals of shadowed pixels (intensity <= threshold * albedo) by the smoothest field
/// that agrees with the normals around them: a discrete harmonic interpolation of each component,
/// renormalized. Where a shadowed pixel lies on the mask's edge away from the image border, the edge
/// is taken as an occluding contour (Ikeuchi & Horn 1981): the normal there is the outward direction
/// of the mask in the image plane, n_z = 0. A sphere's x and y normal components are harmonic, so its
/// shadowed part is recovered exactly up to the discretization of the contour.
///
/// @param[in,out] normals  H x W camera-frame normals; shadowed pixels are rewritten.
/// @param[in] image        H x W linear intensity.
/// @param[in] mask         H x W.
/// @param[in] albedo       > 0.
/// @param[in] threshold    relative intensity at or below which a pixel counts as shadowed.
/// @param[in] occluding_contour whether the mask's edge is an occluding contour.
/// @return number of pixels filled.
int fill_attached_shadows(NormalMap& normals, const ImageF& image, const Mask& mask, double albedo, double threshold,
                          bool occluding_contour);

}  // namespace shadecut
