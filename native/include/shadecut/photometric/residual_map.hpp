// How far the photographs are from a surface, pixel by pixel: where the result explains them and
// where it does not (cast shadows, highlights, paint read as flat, what no Lambertian surface gives).
#pragma once

#include <shadecut/photometric/photometric_stereo.hpp>
#include <shadecut/support/types.hpp>

#include <Eigen/Core>

#include <vector>

namespace shadecut {

/// The RMS over the photographs of intensity_k - albedo_map max(0, n . S_k) (near lamps: times the
/// lamp's strength at the pixel), in the photographs' intensity units.
///
/// @param[in] images     K >= 1 photographs, H x W linear intensity.
/// @param[in] lights     K unit directions toward the lights, camera frame (near lamps: their
///                       directions from `lamps.centre`).
/// @param[in] lamps      distance 0 for distant lights (a single photograph's case).
/// @param[in] normals    H x W unit normals, camera frame.
/// @param[in] albedo_map H x W albedo per pixel.
/// @param[in] mask       H x W, the pixels measured.
/// @return H x W, >= 0, 0 outside the mask.
ImageF residual_map(const std::vector<ImageF>& images, const std::vector<Eigen::Vector3d>& lights, const NearLamps& lamps,
                    const NormalMap& normals, const ImageF& albedo_map, const Mask& mask);

}  // namespace shadecut
