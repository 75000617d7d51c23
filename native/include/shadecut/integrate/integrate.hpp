// Integration of a normal field into a depth map.
#pragma once

#include <shadecut/support/progress.hpp>
#include <shadecut/support/types.hpp>

#include <string>
#include <vector>

namespace shadecut {

enum class Integrator {
  Poisson,           ///< Least squares on the mask's own pixels; respects any mask shape.
  FrankotChellappa,  ///< Projection onto integrable Fourier bases (the paper's choice); whole rectangle,
                     ///< periodic, gradients 0 outside the mask. The mean masked gradient, which no
                     ///< periodic basis holds, is integrated separately as a plane, so planes come out
                     ///< exact.
};

/// Every integrator's name, in the order of the enum.
const std::vector<std::string>& integrator_names();

/// Parses one of integrator_names(); throws InvalidArgument otherwise.
Integrator parse_integrator(const std::string& name);
std::string to_string(Integrator integrator);

/// Turns every masked normal that faces away from the viewer (n_z < 0), which no depth map has, into
/// the grazing normal of the same tilt: (n_x, n_y, 0) normalized; (0, 0, -1), which has no tilt,
/// becomes (0, 0, 1). The shape-from-shading methods can produce such normals where the image's
/// brightness allows a slant beyond 90 degrees; reconstruct() folds them before integrating.
///
/// @param[in,out] normals H x W unit normals.
/// @param[in] mask        H x W; normals outside it are left alone.
/// @return the number of normals folded.
int fold_back_facing(NormalMap& normals, const Mask& mask);

/// The least max_slope an integration takes: a clamp below it keeps every normal within a degree of
/// the viewer (atan(0.01 sqrt 2) = 0.8 degrees), a flat surface whatever the normals say.
constexpr double kMinMaxSlope = 0.01;

/// Integrates camera-frame normals into depth.
///
/// The surface gradients are p = dz/dx = -n_x / n_z and q = dz/dy = -n_y / n_z (x right, y up, so
/// dz/drow = -q), each clamped to [-max_slope, max_slope]. A normal with 0 <= n_z <= 1e-6 (grazing)
/// gets the clamped slope in the direction it tilts; one facing away (n_z < 0) is an error
/// (fold_back_facing turns it into a grazing one).
///
/// Poisson minimises, over every pair (a, b) of 4-neighbours both in the mask, (z_b - z_a - g_ab)^2
/// with g_ab the mean of the two pixels' gradients along that edge, one independent surface per
/// 4-connected component. It is solved by conjugate gradients preconditioned with an aggregation
/// multigrid V-cycle, to a relative residual of 1e-8: the exact least-squares depth to about 1e-7
/// of its range, in time linear in the pixel count; the same bits for any number of threads.
///
/// @param[in] normals   H x W unit normals, camera frame. Normals outside the mask are never read.
/// @param[in] mask      H x W; only masked pixels are integrated (Poisson) or carry gradients (FC).
/// @param[in] method    which integrator.
/// @param[in] max_slope bound on |p| and |q|, depth units per pixel; finite and >= kMinMaxSlope.
/// @param[in] progress  told the fraction done, as stage "integration" (Poisson); may throw Cancelled.
/// @return H x W depth in pixel units, larger = closer to the viewer. Every 4-connected component of
///         the mask is shifted so that its minimum is 0 (both methods; a one-pixel component is 0);
///         pixels outside the mask are 0. An empty mask gives all zeros.
/// @throws InvalidArgument for an empty normal map, a mask or vector count that does not match it,
///         a bad max_slope, or a non-finite, zero or back-facing normal inside the mask.
ImageF integrate_normals(const NormalMap& normals, const Mask& mask, Integrator method, double max_slope = 10.0,
                         const Progress& progress = {});

/// The depth that tiles: its left column continues into its right one, its top row into its bottom
/// (seamless textures). Frankot-Chellappa over the whole frame, which is least squares on the torus,
/// without the plane integrate_normals keeps: the mean gradient, which no tiling surface has, is
/// dropped.
///
/// @param[in] normals   H x W unit normals, camera frame; every pixel is used.
/// @param[in] max_slope bound on |p| and |q| as for integrate_normals.
/// @return H x W depth in pixel units, larger = closer, minimum 0, periodic in both directions.
/// @throws InvalidArgument as integrate_normals does.
ImageF integrate_periodic(const NormalMap& normals, double max_slope = 10.0);

}  // namespace shadecut
