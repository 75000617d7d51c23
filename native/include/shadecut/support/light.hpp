// A distant light and the light-source coordinate frame of Lee & Rosenfeld.
#pragma once

#include <Eigen/Core>

#include <string>
#include <vector>

namespace shadecut {

/// A distant light, and the rotation between the light-source frame and the camera frame.
///
/// The light-source frame has its z axis along the light direction S. A normal with slant s (angle
/// to S) and tilt t in that frame is n' = (sin s cos t, sin s sin t, cos s); in the camera frame it is
/// n = Rz(tilt) Ry(slant) n', where slant = acos(S_z) and tilt = atan2(S_y, S_x) are the light's own.
struct LightFrame {
  Eigen::Vector3d direction;  ///< unit vector toward the light, camera frame
  double slant = 0.0;         ///< sS = acos(S_z), radians, in [0, pi/2)
  double tilt = 0.0;          ///< tS = atan2(S_y, S_x), radians
  Eigen::Matrix3d to_camera;  ///< Rz(tS) Ry(sS)

  /// Normalizes `light` (any length > 0). Throws InvalidArgument for a zero or non-finite vector, or
  /// one at or below the horizon (S_z <= 0): such a light leaves the visible surface unresolvable.
  static LightFrame from_direction(const Eigen::Vector3d& light);

  /// Camera-frame unit normal of light-frame slant `s` and tilt `t` (radians).
  Eigen::Vector3d normal(double s, double t) const;
};

/// The slant (degrees from the viewer) of a light named only by its side, as a multi-angle capture's
/// lamp is when nobody measured it. The photographs cannot tell it: under Lambertian shading another
/// slant of every light gives the same photographs of a deeper or flatter surface (the bas-relief
/// ambiguity), so this fixes the depth's scale, not its forms.
constexpr double kSideLightSlantDegrees = 45.0;

/// The words light_from_side knows: "top", "bottom", "left", "right", "top-left", "top-right",
/// "bottom-left", "bottom-right", and "above", "below" for "top", "bottom".
const std::vector<std::string>& light_side_names();

/// The unit direction toward a light from the image's `side` (a word of light_side_names()) at
/// `slant_degrees` from the viewer, in (0, 90). Throws InvalidArgument naming the words for another
/// word, and for a slant outside (0, 90).
Eigen::Vector3d light_from_side(const std::string& side, double slant_degrees = kSideLightSlantDegrees);

}  // namespace shadecut
