// Internal: the orientation statistics of a result (ReconstructStats::orientation_residual,
// inverted_residual, orientation_ambiguous).
#pragma once

#include <shadecut/pipeline/reconstruct_options.hpp>
#include <shadecut/pipeline/reconstruction.hpp>
#include <shadecut/support/light.hpp>

namespace shadecut::detail {

/// The surface `depth`, `normals` (the result's; before fit_shading when it ran, finished alike)
/// rendered, and the surface of its normals turned by pi about the light (n -> 2 (n . S) S - n, each
/// normal's other one of the same brightness), made a surface as the result was (filled, integrated,
/// flattened for a relief) and rendered, over the reliable pixels (`image`'s, outside `unreliable`);
/// both on block means when the object is large. Judged before the fit: the fit refines one of the
/// two surfaces, and the other would read worse for that alone.
void judge_orientation(const ImageF& image, const Mask& unreliable, const LightFrame& frame, const ReconstructOptions& options,
                       const ImageF& depth, const NormalMap& normals, Reconstruction& result);

}  // namespace shadecut::detail
