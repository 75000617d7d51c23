// Internal: reconstruct() of several photographs of one view, each under its own light.
#pragma once

#include <shadecut/pipeline/observation.hpp>
#include <shadecut/pipeline/reconstruct_options.hpp>
#include <shadecut/pipeline/reconstruction.hpp>

#include <optional>
#include <vector>

namespace shadecut::detail {

/// Photometric stereo where three or more photographs are usable, the graph cut between the two
/// normals two photographs leave, the pixels with fewer filled from their neighbours, then the depth
/// (docs/method.md, "Several photographs"). Every photograph's light must be given.
Reconstruction reconstruct_photographs(const std::vector<Observation>& photographs, const Mask* mask,
                                       std::optional<double> albedo, const ReconstructOptions& options);

}  // namespace shadecut::detail
