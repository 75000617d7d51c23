// Internal: the light of an object seen whole, read at its occluding contour (LightMethod::Contour),
// called by estimate_light.
#pragma once

#include <shadecut/estimate/estimate_light.hpp>

namespace shadecut::detail {

/// The share of the object's size (object_size: the square root of the mask's area) by which the
/// ring estimate_contour_light reads lies inside the outline. Chosen by scripts/tune_parameters.py
/// --light-method on the training surfaces (docs/parameters.md, "The light").
constexpr double kContourRing = 0.04;

/// Light of an object seen whole against a background, whose outline is an occluding contour.
///
/// Near the outline a surface turns away from the viewer: along a ring a little inside it, every
/// normal has about the same slant sigma from the viewer and points outward, n = (sin sigma o,
/// cos sigma) with o the outline's outward direction (contour_outward of the ring's own edge). Its
/// brightness is then rho max(0, cos sigma S_z + sin sigma o . S_xy): a line in o, whose slope gives
/// the light's image-plane direction and whose two coefficients A = cos sigma cos s, B = sin sigma
/// sin s give the slant s = (acos(A - B) - acos(A + B)) / 2 (and sigma), with the albedo rho known.
/// The line is fitted by least squares to the ring's pixels that are lit or that the fit says are
/// (attached shadows are read as 0), the image clipped at rho.
///
/// @param[in] image  H x W linear intensity, validated by the caller.
/// @param[in] mask   H x W, the object.
/// @param[in] albedo rho > 0 (estimate_albedo's when not given); it is also the estimate's albedo.
/// @param[in] ring   the ring's depth inside the outline as a share of object_size (kContourRing),
///                   in pixels rounded, at least 0 (the outline's own pixels).
/// @return the estimate with its uncertainty: the ring's misfit (root mean square, over the albedo)
///         as the turn of the light that changes the ring's brightness by as much, radians; large
///         where the ring does not follow the model (a glossy or painted limb, an edge that is no
///         occluding contour). Where the ring has fewer than 16 pixels (a relief filling the frame has
///         no outline): zheng_chellappa's estimate with an unknown (NaN) uncertainty.
LightEstimate estimate_contour_light(const ImageF& image, const Mask& mask, double albedo, double ring = kContourRing);

}  // namespace shadecut::detail
