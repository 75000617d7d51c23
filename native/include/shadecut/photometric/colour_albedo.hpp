// The de-lit base colour of a surface photographed under several known lights.
#pragma once

#include <shadecut/photometric/photometric_stereo.hpp>
#include <shadecut/support/types.hpp>

#include <vector>

namespace shadecut {

/// Per pixel and channel, the albedo rho_c that best explains the photographs given the normal:
/// rho_c = sum_k I_ck s_k / sum_k s_k^2, s_k = n . S_k, over the photographs k usable there by the
/// rules of photometric_stereo: not clipped, not in shadow (s_k >= params.shadow_fraction), and not
/// an outlier (its luminance within params.outlier_tolerance times the albedo of what the median of
/// the photographs' luminance / s_k predicts: a highlight or a cast shadow is left out).
///
/// @param[in] photographs K colour photographs, each H x W x 3 linear RGB on one common scale (the
///                        luminance of each, support/intensity.hpp's rule, being what
///                        photometric_stereo was given), finite.
/// @param[in] lights      K x 3, toward the lights (normalized here); checked as photometric_stereo does.
/// @param[in] normals     H x W unit normals (photometric_stereo's, or the candidates chosen by
///                        choose_candidates); pixels with the zero vector get albedo 0.
/// @param[in] mask        H x W, the surface.
/// @param[in] clipped     empty, or K masks H x W: true where a photograph is clipped.
/// @param[in] params      shadow_fraction and outlier_tolerance.
/// @return H x W x 3 linear RGB albedo, 0 outside the mask and where no photograph is usable.
/// @throws InvalidArgument for the shapes and inputs photometric_stereo refuses, or normals of
///         another size.
ColourImage photometric_colour_albedo(const std::vector<ColourImage>& photographs, const LightDirections& lights,
                                      const NormalMap& normals, const Mask& mask, const std::vector<Mask>& clipped = {},
                                      const PhotometricStereoParams& params = {});

/// photometric_colour_albedo of grey photographs (H x W linear intensity each): the same rules, one
/// channel, without three copies of each photograph.
ImageF photometric_albedo(const std::vector<ImageF>& photographs, const LightDirections& lights, const NormalMap& normals,
                          const Mask& mask, const std::vector<Mask>& clipped = {},
                          const PhotometricStereoParams& params = {});

}  // namespace shadecut
