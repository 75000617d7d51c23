// Internal: the rules that make a surface of a labelling's normals the same way for the call's result
// and for the inversion the orientation is judged against.
#pragma once

#include <shadecut/pipeline/reconstruct_options.hpp>
#include <shadecut/support/types.hpp>

namespace shadecut::detail {

/// The relative intensity at or below which a pixel counts as shadow; < 0 (none) when shadows are not filled.
double shadow_threshold_used(const ReconstructOptions& options);

/// Whether the mask's edge is the object's outline (an occluding contour): never for a relief.
bool edge_is_outline(const ReconstructOptions& options);

/// The detail size of a relief's call (ReconstructStats::detail_size): NaN for objects, seamless
/// output and detail_size < 0, for a uniform image, which has no scale, and for pentland unless given.
double detail_size_used(const ImageF& image, const Mask& mask, const ReconstructOptions& options);

/// A relief made what a relief is: on a flat carrier facing the viewer, without the forms larger than
/// its detail (the integration's drift). Seamless output tiles as it is and is left alone.
void finish_relief(ImageF& depth, const Mask& mask, const ReconstructOptions& options, double detail_size);

}  // namespace shadecut::detail
