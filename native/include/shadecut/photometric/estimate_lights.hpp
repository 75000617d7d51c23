// Uncalibrated photometric stereo: the lights of several photographs from the photographs alone.
#pragma once

#include <shadecut/photometric/photometric_stereo.hpp>
#include <shadecut/support/light.hpp>
#include <shadecut/support/types.hpp>

#include <vector>

namespace shadecut {

/// The hint's slant range, degrees: within a degree of the viewer four lights stand too near one
/// another to be told apart, within a degree of the horizon they only graze the surface.
constexpr double kLeastHintSlant = 1.0;
constexpr double kGreatestHintSlant = 89.0;

/// What the user knows about the lights, short of their directions.
struct LightHint {
  /// The lights are about equally strong and at about the same slant (moved around the subject at
  /// one height, the usual multi-angle capture). Required: without it the generalized bas-relief
  /// ambiguity stays open.
  bool same_slant = true;
  /// Their slant, degrees from the viewing direction, in [kLeastHintSlant, kGreatestHintSlant]; by
  /// default a side's light's. The
  /// photographs leave the surface's depth scale open (the bas-relief's flattening turns every
  /// light's slant alike); this settles it, as well as the user knows it.
  double slant = kSideLightSlantDegrees;
  /// The image-plane direction the first photograph's light comes from, about (degrees, from +x
  /// toward +y: 90 = the top, 0 = the right); within 90 degrees of it settles the convex / concave flip.
  double first_tilt = 90.0;
};

/// The fewest photographs whose lights can be estimated: three leave the factorization no equation
/// beyond its own rank.
constexpr int kFewestPhotographsToEstimateLights = 4;

struct PhotometricLights {
  LightDirections lights;            ///< K x 3 unit directions toward the lights, camera frame
  std::vector<double> uncertainty;   ///< per light, degrees: the largest angle to the lights of the
                                     ///< ambiguity's members that fit the hint nearly as well
  double hint_misfit = 0.0;          ///< how far the lights found are from the hint (0 = exactly)
  int pixels = 0;                    ///< pixels lit in every photograph that the factorization used
};

/// The lights of K >= 4 photographs of one Lambertian surface (I_k = albedo n . S_k where lit):
/// the pixels lit in every photograph give M (pixels x K) = B S of rank 3 (Hayakawa's SVD),
/// known up to an invertible 3 x 3 matrix; the surface's integrability narrows that to the
/// generalized bas-relief family (Yuille & Snow's linear constraint), and the hint picks its
/// member: the lights most nearly equal in strength, at the hint's slant, spread around the subject
/// (their image-plane directions cancelling about), the first from
/// the hint's side. The lights' tilts come from the photographs; their common slant is the hint's.
///
/// @param[in] images K >= 4 photographs, H x W linear intensity on one common scale, finite.
/// @param[in] mask   H x W, the surface.
/// @param[in] hint   what is known of the lights.
/// @throws InvalidArgument for fewer than four photographs, images of different sizes, too few
///         pixels lit in every photograph (fewer than 100 with their four neighbours), or a hint
///         without same_slant or with a slant outside (0, 90).
PhotometricLights estimate_photometric_lights(const std::vector<ImageF>& images, const Mask& mask, const LightHint& hint = {});

}  // namespace shadecut
