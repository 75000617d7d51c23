// Integration of a normal field into a depth map.
#pragma once

#include <shadecut/types.hpp>

#include <string>

namespace shadecut {

enum class Integrator {
  Poisson,           ///< Least squares on the mask's own pixels (Eigen sparse); respects any mask shape.
  FrankotChellappa,  ///< Projection onto integrable Fourier bases (the paper's choice); whole rectangle.
};

/// Parses "poisson" or "frankot_chellappa"; throws InvalidArgument otherwise.
Integrator parse_integrator(const std::string& name);
std::string to_string(Integrator integrator);

/// Integrates camera-frame normals into depth.
///
/// The surface gradients are p = dz/dx = -n_x / n_z and q = dz/dy = -n_y / n_z (x right, y up, so
/// dz/drow = -q), each clamped to [-max_slope, max_slope] where n_z is tiny.
///
/// @param[in] normals   H x W unit normals, camera frame.
/// @param[in] mask      H x W; only masked pixels are integrated (Poisson) or carry gradients (FC).
/// @param[in] method    which integrator.
/// @param[in] max_slope bound on |p| and |q|, depth units per pixel.
/// @return H x W depth in pixel units, larger = closer to the viewer. Every 4-connected component of
///         the mask is shifted so that its minimum is 0; pixels outside the mask are 0.
ImageF integrate_normals(const NormalMap& normals, const Mask& mask, Integrator method, double max_slope = 10.0);

}  // namespace shadecut
