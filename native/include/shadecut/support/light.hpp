// A distant light and the light-source coordinate frame of Lee & Rosenfeld.
#pragma once

#include <Eigen/Core>

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

}  // namespace shadecut
