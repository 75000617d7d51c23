// Internal: the light and albedo a call uses.
#pragma once

#include <shadecut/pipeline/reconstruct_options.hpp>
#include <shadecut/pipeline/reconstruction.hpp>
#include <shadecut/support/light.hpp>

#include <optional>

namespace shadecut::detail {

/// The light frame and albedo used (written to result.light, result.albedo and, when estimated, the
/// stats): given, or estimated from the image (an object's albedo with its estimated light;
/// otherwise estimate_albedo's, or a relief's median). `brightest` is the largest masked intensity.
LightFrame choose_lighting(const ImageF& image, const Mask& mask, float brightest, const std::optional<Eigen::Vector3d>& light,
                           std::optional<double> albedo, const ReconstructOptions& options, const Progress& progress,
                           Reconstruction& result);

}  // namespace shadecut::detail
