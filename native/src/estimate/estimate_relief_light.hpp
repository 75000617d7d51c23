// Internal: the light of a relief (LightMethod::Relief), called by estimate_light.
#pragma once

#include <shadecut/estimate/estimate_light.hpp>

#include <optional>

namespace shadecut::detail {

/// Light and albedo of a relief: a surface that fills the mask and on average faces the viewer.
///
/// - Tilt (direction and sign): a material's relief has broad tops and narrow grooves (stones and
///   their joints, bark and its fissures, planks and their gaps). Lit from tau, each groove shows
///   its lit wall, then at once its dark wall along tau, while a top brightens or darkens slowly:
///   the image's derivative along tau is negatively skewed, and along -tau positively; paint,
///   symmetric on average, adds no skew. The tilt is the direction whose derivative has the most
///   negative mean cube, a cubic form in the direction (four third moments of the gradient) scanned
///   in half-degree steps. The gradient is taken of the image's periodic component (Moisan 2011, so
///   that the frame's edges add nothing) smoothed by a Gaussian of kGrooveScale pixels. Lambertian
///   shading cannot tell a relief lit from tau from its inverse lit from -tau: a relief of narrow
///   ridges on broad valleys is read as lit from the other side.
/// - Slant: the relief's median intensity is its base facing the viewer, rho S_z; its brightest
///   pixels (99.5th percentile) face the light, rho. So S_z = median / brightest, the slant at most
///   45 degrees: paint brighter than the base would read as a grazing light. A given albedo replaces
///   the brightest and the cap.
/// - Uncertainty: the RMS angle between the light and the light with each image quadrant's own tilt
///   (the same slant): how much the tilt cue scatters over the image. The slant's own error is not
///   in it.
///
/// @param[in] image   H x W linear intensity, validated by the caller.
/// @param[in] mask    H x W pixels of the relief; the others are read as its median.
/// @param[in] albedo  rho if known (then S_z = median / rho), else std::nullopt.
/// @throws InvalidArgument when the relief's pixels are dark.
LightEstimate estimate_relief_light(const ImageF& image, const Mask& mask, std::optional<double> albedo);

}  // namespace shadecut::detail
