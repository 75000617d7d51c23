// Internal: the normals of two photographs of one view, each under its own light (docs/method.md,
// "Two photographs").
#pragma once

#include <shadecut/photometric/photometric_stereo.hpp>
#include <shadecut/pipeline/observation.hpp>
#include <shadecut/pipeline/reconstruct_options.hpp>

#include <vector>

namespace shadecut::detail {

/// The normals each photograph gives alone (the paper's graph cut under its own light, with
/// `options`), within `mask`: one H x W unit normal map per photograph.
std::vector<NormalMap> photographs_read_alone(const std::vector<Observation>& photographs, const Mask& mask,
                                              const ReconstructOptions& options, const Progress& progress);

/// Of `anchors`, the one nearest the circles of normals of the pixels both photographs light
/// (`both_lit`): the least mean angle from the circles (nearest_on_circles).
const NormalMap& nearest_to_circles(const std::vector<NormalMap>& anchors, const std::vector<ImageF>& images,
                                    const std::vector<Eigen::Vector3d>& lights, const NearLamps& lamps,
                                    const Mask& both_lit);

/// The normalized mean of two normal maps within `mask`.
NormalMap mean_normals(const NormalMap& first, const NormalMap& second, const Mask& mask);

/// Where both photographs are usable (usable == 2), whatever the albedo, the normal lies on the circle
/// n . (I_2 S_1 - I_1 S_2) = 0 (S_k the light at the pixel, I_k the intensity at its strength): there
/// the point of that circle nearest `anchor` (facing the first light); elsewhere `anchor` itself.
/// @param[in] images  the two photographs, H x W.
/// @param[in] lights  their unit lights; `lamps` as PhotometricStereoParams::lamps.
/// @param[in] usable  H x W, photometric_stereo's count of usable photographs.
/// @param[in] anchor  H x W unit normals.
NormalMap nearest_on_circles(const std::vector<ImageF>& images, const std::vector<Eigen::Vector3d>& lights,
                             const NearLamps& lamps, const CountImage& usable, const NormalMap& anchor, const Mask& mask);

}  // namespace shadecut::detail
