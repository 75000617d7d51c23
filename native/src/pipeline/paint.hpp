// Internal: reconstruct() of an image whose paint is read first (albedo_method retinex), or of one
// albedo; the albedo map and the de-lit colour filled either way.
#pragma once

#include <shadecut/pipeline/reconstruct_options.hpp>
#include <shadecut/pipeline/reconstruction.hpp>

#include <Eigen/Core>

#include <optional>

namespace shadecut::detail {

/// reconstruct() of `image` (H x W intensity) over `mask` (nullptr: every pixel); `colour` is the
/// photograph's colour or nullptr for a grey one.
Reconstruction reconstruct_painted(const ImageF& image, const ColourImage* colour, const std::optional<Eigen::Vector3d>& light,
                                   const Mask* mask, std::optional<double> albedo, const ReconstructOptions& options);

}  // namespace shadecut::detail
