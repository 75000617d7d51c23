// The Lambertian image formation model ShadeCut inverts, and normals of height fields.
#pragma once

#include <shadecut/support/types.hpp>

#include <Eigen/Core>

namespace shadecut {

/// Camera-frame unit normals of a height field, normalize(-dz/dx, -dz/dy, 1) with x right, y up.
///
/// @param[in] depth  H x W depth, pixel units, larger = closer.
/// @param[in] mask   H x W; derivatives use only masked pixels (central differences, one-sided at the
///                   mask's edge, 0 where a pixel has no masked neighbour along that axis).
/// @return normals, (0, 0, 0) outside the mask.
NormalMap normals_from_depth(const ImageF& depth, const Mask& mask);

/// normals_from_depth of a depth that tiles (integrate_periodic): central differences everywhere,
/// the image's opposite edges taken as neighbours, so that the normals tile as the depth does.
///
/// @param[in] depth H x W depth, pixel units, larger = closer.
/// @return H x W unit normals.
NormalMap normals_from_periodic_depth(const ImageF& depth);

/// Lambertian image I = albedo * max(0, S . N) of a normal field under a distant light.
///
/// @param[in] normals H x W unit normals, camera frame.
/// @param[in] light   direction toward the light, camera frame, any length > 0 (normalized here).
/// @param[in] albedo  >= 0.
/// @param[in] mask    H x W; pixels outside it are 0.
/// @return H x W linear intensity.
ImageF render_lambertian(const NormalMap& normals, const Eigen::Vector3d& light, double albedo, const Mask& mask);

/// How far a depth's rendering is from the image: sum over the `counted` pixels of
/// (render_lambertian(normals_from_depth(depth, mask)) - image)^2.
///
/// @param[in] depth   H x W depth, pixel units.
/// @param[in] image   H x W linear intensity.
/// @param[in] mask    H x W pixels of the surface (its normals' support).
/// @param[in] counted H x W pixels summed (e.g. the mask without shadows and highlights).
/// @param[in] light   direction toward the light (normalized here).
/// @param[in] albedo  >= 0.
double brightness_residual(const ImageF& depth, const ImageF& image, const Mask& mask, const Mask& counted,
                           const Eigen::Vector3d& light, double albedo);

/// brightness_residual per counted pixel (0 when none is counted): comparable between image sizes.
double mean_brightness_residual(const ImageF& depth, const ImageF& image, const Mask& mask, const Mask& counted,
                                const Eigen::Vector3d& light, double albedo);

}  // namespace shadecut
