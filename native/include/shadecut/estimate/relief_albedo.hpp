// The albedo of a relief (a surface filling the frame that on average faces the viewer), read from
// its median intensity.
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

}  // namespace shadecut
