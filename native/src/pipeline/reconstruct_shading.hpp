// Internal: reconstruct() of an image of one albedo, which the public reconstruct() calls on the image
// itself or, with albedo_method retinex, on its shading image (paint.cpp).
#pragma once

#include <shadecut/pipeline/reconstruct.hpp>

#include <cstdint>

namespace shadecut::detail {

/// Throws InvalidArgument for options that are out of range or do not fit the mask (every option but
/// the retinex_* ones, which paint.cpp checks).
void check_options(const ReconstructOptions& options, const Mask& mask);

/// The peak bytes a reconstruct() call with these options needs for an image of `pixels` pixels, from
/// the measured model in docs/benchmarks.md ("Memory"); check_options refuses a call above
/// available_memory().
std::uint64_t estimated_peak_memory(const ReconstructOptions& options, std::int64_t pixels);

/// reconstruct()'s arguments and result (albedo_map and albedo_colour left empty); the albedo, given or
/// estimated, is one value.
Reconstruction reconstruct_shading(const ImageF& image, const std::optional<Eigen::Vector3d>& light, const Mask* mask,
                                   std::optional<double> albedo, const ReconstructOptions& options);

}  // namespace shadecut::detail
