// Reliefs: surfaces that fill the frame (a wall, a coin, bark) and on average face the viewer. That
// one fact fixes what an image of them cannot: the albedo and the lowest frequencies of the depth.
#pragma once

#include <shadecut/support/types.hpp>

#include <Eigen/Core>

namespace shadecut {

/// The median intensity of the masked pixels (the upper middle one of an even count): the intensity
/// of a relief's base, which faces the viewer.
/// @throws InvalidArgument for an empty mask or a relief dark in most of its pixels.
double median_intensity(const ImageF& image, const Mask& mask);

/// The albedo of a relief: its typical normal is the viewing direction, so its median intensity is
/// albedo * S_z. The median, not the mean: steep flanks (a brick's bevel, a groove) would pull the
/// mean down. Returns median_intensity / S_z.
///
/// @param[in] light unit direction toward the light, S_z > 0.
/// @throws InvalidArgument for an image dark everywhere in the mask.
double relief_albedo(const ImageF& image, const Mask& mask, const Eigen::Vector3d& light);

/// Removes the least-squares plane of the masked depth, so that the relief sits on a flat carrier
/// facing the viewer (no ramp), and tilts the normals to match; then every 4-connected component's
/// minimum is 0 again.
///
/// @param[in,out] depth   H x W, pixel units (x = column, y = -row).
/// @param[in,out] normals H x W camera-frame unit normals.
/// @param[in] mask        H x W.
void flatten_relief(ImageF& depth, NormalMap& normals, const Mask& mask);

}  // namespace shadecut
