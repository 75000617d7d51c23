// Normals inside attached shadows, where the image says nothing but "facing away from the light".
#pragma once

#include <shadecut/support/types.hpp>

namespace shadecut {

/// Replaces the normals of the pixels in `fill` (attached shadows, highlights: see
/// unreliable_pixels) by the smoothest field that agrees with the normals around them: a discrete
/// harmonic interpolation of each component, renormalized. Where a filled pixel lies on the mask's
/// edge away from the image border, the edge is taken as an occluding contour (Ikeuchi & Horn 1981):
/// the normal there is the outward direction of the mask in the image plane, n_z = 0. A sphere's x
/// and y normal components are harmonic, so its shadowed part is recovered exactly up to the
/// discretization of the contour.
///
/// @param[in,out] normals  H x W camera-frame normals; the pixels in `fill` are rewritten.
/// @param[in] fill         H x W pixels to fill (outside `mask` ignored).
/// @param[in] mask         H x W.
/// @param[in] occluding_contour whether the mask's edge is an occluding contour.
/// @return number of pixels filled.
int fill_normals(NormalMap& normals, const Mask& fill, const Mask& mask, bool occluding_contour);

/// The pixels whose intensity tells little about their normal at this albedo: attached shadows
/// (intensity <= shadow_threshold * albedo; none when shadow_threshold < 0) and pixels brighter than
/// highlight_threshold * albedo, which no Lambertian surface of that albedo shows (highlights,
/// saturation; none when highlight_threshold <= 0). Only masked pixels are marked.
Mask unreliable_pixels(const ImageF& image, const Mask& mask, double albedo, double shadow_threshold,
                       double highlight_threshold);

}  // namespace shadecut
