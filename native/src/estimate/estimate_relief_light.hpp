// Internal: the light of a relief (LightMethod::Relief), called by estimate_light.
#pragma once

#include <shadecut/estimate/estimate_light.hpp>

#include <optional>

namespace shadecut::detail {

/// Light and albedo of a relief: a surface that fills the mask and on average faces the viewer.
///
/// With small slopes a Lambertian relief's image is I ~ rho (S_z - |S_xy| dz/dtau) (tau the light's
/// tilt direction), in Fourier terms I(w) ~ -i rho |S_xy| (w . tau) z(w): shading shows the relief's
/// slope along tau only.
/// - Tilt axis: the tau for which the relief implied by the image, z(w) = I(w) / (w . tau), has the
///   least energy: a relief whose height spectrum is the same in every direction (a wall of
///   stones, bark, a carving) is then lit along tau. The image's periodic component (Moisan 2011) is
///   used, so that the frame's own edges add no spectrum.
/// - Tilt sign: the light from above (S_y >= 0), from the right on the horizontal. Lambertian shading
///   cannot tell it: a relief lit from tau and the same relief inverted, lit from -tau, give the same
///   image.
/// - Slant: the relief's median intensity is its base facing the viewer, rho S_z; its brightest
///   pixels (99.5th percentile) face the light, rho. So S_z = median / brightest.
///
/// @param[in] image   H x W linear intensity, validated by the caller.
/// @param[in] mask    H x W pixels of the relief; the others are read as its median.
/// @param[in] albedo  rho if known (then S_z = median / rho), else std::nullopt.
/// @throws InvalidArgument when the relief's pixels are dark.
LightEstimate estimate_relief_light(const ImageF& image, const Mask& mask, std::optional<double> albedo);

}  // namespace shadecut::detail
