// Internal: reconstruct() of an image of one albedo, which the public reconstruct() calls on the image
// itself or, with albedo_method retinex, on its shading image (paint.cpp).
#pragma once

#include <shadecut/pipeline/reconstruct_options.hpp>
#include <shadecut/pipeline/reconstruction.hpp>

#include <Eigen/Core>

#include <optional>

namespace shadecut::detail {

/// reconstruct()'s arguments and result (albedo_map and albedo_colour left empty); the albedo, given or
/// estimated, is one value.
Reconstruction reconstruct_shading(const ImageF& image, const std::optional<Eigen::Vector3d>& light, const Mask* mask,
                                   std::optional<double> albedo, const ReconstructOptions& options);

}  // namespace shadecut::detail
