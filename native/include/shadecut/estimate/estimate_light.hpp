// The light direction and albedo of one image, estimated from its statistics (no shape known).
#pragma once

#include <shadecut/support/types.hpp>

#include <Eigen/Core>

#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <vector>

namespace shadecut {

enum class LightMethod {
  /// "lee_rosenfeld" (Lee & Rosenfeld 1985): tilt = direction of the mean of the unit intensity-gradient
  /// vectors; slant and albedo from the mean intensity E1 and mean squared intensity E2 of a
  /// Lambertian sphere seen whole and lit without attached shadow: E1 = 2/3 rho cos(s),
  /// E2 = rho^2 (1 + cos^2 s) / 4. It ignores the attached shadow, so it underestimates oblique slants.
  LeeRosenfeld,
  /// "zheng_chellappa" (after Zheng & Chellappa 1991): tilt = direction of the mean intensity
  /// gradient (magnitudes kept); slant and albedo from the exact moments of the sphere image with its
  /// attached shadow: E1 = 2 rho ((pi - s) cos s + sin s) / (3 pi), E2 = rho^2 (1 + cos s)^2 / 8.
  ZhengChellappa,
  /// "relief": for a surface that fills the frame and on average faces the viewer, whose normals are
  /// nothing like a sphere's. Tilt axis from the image's spectrum (the one along which the image
  /// integrates to the least relief), the light from above (S_y >= 0: shading cannot tell a relief lit
  /// from one side from its inverse lit from the other), slant from S_z = median / brightest
  /// (99.5th percentile) intensity; albedo = median / S_z. Details in src/estimate_relief_light.hpp.
  Relief,
  /// "contour": for an object seen whole against a background, whose outline is an occluding
  /// contour (its normals there point outward in the image plane): the brightness along a ring just
  /// inside the outline, a line in the outline's outward direction, gives the light's image-plane
  /// direction (its slope) and, with the albedo, its slant. Its uncertainty comes with it
  /// (LightEstimate::uncertainty). Without an outline (a relief filling the frame) it falls back to
  /// zheng_chellappa. Details in src/estimate/estimate_contour_light.hpp.
  Contour,
};

/// Every estimator's name, in the order of the enum.
const std::vector<std::string>& light_method_names();

/// Parses one of light_method_names(); throws InvalidArgument otherwise.
LightMethod parse_light_method(const std::string& name);
std::string to_string(LightMethod estimator);

/// The largest slant an estimate gives (radians, 89 degrees): a light at the horizon has S_z = 0,
/// which reconstruct() rejects, so every estimator stops just above it.
constexpr double kMaxEstimatedSlant = 89.0 * M_PI / 180.0;

/// The fewest masked pixels a light is estimated from: every estimator reads statistics of the
/// shading (its moments, its gradients, an outline), which a handful of pixels do not have; fewer
/// gave (0, 0, 1) without a word.
constexpr int kMinLightPixels = 16;

struct LightEstimate {
  Eigen::Vector3d light;  ///< unit vector toward the light, camera frame; slant <= kMaxEstimatedSlant
  double albedo = 0.0;    ///< > 0
  double slant = 0.0;     ///< radians, the angle between the light and the viewing direction
  double tilt = 0.0;      ///< radians, atan2(S_y, S_x); 0 when the image has no gradient at all
  /// radians: how far the light may be off, where the estimator can say (contour: its fit's misfit
  /// as an angle of the light); NaN where it cannot.
  double uncertainty = std::numeric_limits<double>::quiet_NaN();
};

/// Estimates light and albedo from the masked pixels of a Lambertian image.
///
/// lee_rosenfeld and zheng_chellappa assume that the surface normals in the mask are spread like
/// those of a sphere seen whole (uniformly over the visible hemisphere in image area), and that the
/// mask covers the object only: background pixels bias the moments. relief assumes a relief.
/// Derivatives are central differences between masked pixels (y up), taken where both axes have a
/// masked neighbour.
///
/// The image is read clipped at `ceiling`, the albedo: above it no Lambertian surface of that albedo
/// shows, and a highlight or saturated spot would pull the light toward it. On a clean image the
/// default ceiling is its brightest value and changes nothing.
///
/// @param[in] image   H x W linear intensity (>= 2 x 2, finite, >= 0).
/// @param[in] mask    H x W pixels to use.
/// @param[in] method  which estimator.
/// @param[in] ceiling the albedo, or std::nullopt for estimate_albedo's (top_fit); relief: the albedo,
///                    or std::nullopt for its brightest pixels', and the image is not clipped;
///                    contour: the albedo it uses and returns (top_fit's when std::nullopt).
/// @throws InvalidArgument for bad input, a mask of fewer than kMinLightPixels pixels or an image
///         dark everywhere in the mask.
LightEstimate estimate_light(const ImageF& image, const Mask& mask, LightMethod method,
                             std::optional<double> ceiling = std::nullopt);

}  // namespace shadecut
