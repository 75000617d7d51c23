// Paint separated from shading (an intrinsic decomposition): the per-pixel reflectance of a painted,
// printed or stained object, so that the shape is read from the shading alone (docs/method.md#paint).
#pragma once

#include <shadecut/support/progress.hpp>
#include <shadecut/support/types.hpp>

namespace shadecut {

/// The decomposition's settings; reconstruct() fills them from ReconstructOptions (reflectance_params),
/// which holds the tuned values.
struct ReflectanceParams {
  /// A step of chromaticity (r, g, b) / (r + g + b), read across three pixels of the 3 x 3-smoothed
  /// image, larger than this is paint: under one white light shading never changes the colour.
  double chroma_edge{};
  /// A step of log intensity across three pixels of the smoothed image that departs from the trend of
  /// the steps 3 and 4 pixels away by more than this is paint: shading changes smoothly. <= 0: off.
  double intensity_edge{};
  /// Pixels within this many pixels of the mask's edge read no paint edge: an object's shading falls
  /// off fastest toward its outline (objects only; 0 for reliefs).
  int rim{};
  /// Pixels brighter than this times the image's albedo (top_fit), which no Lambertian surface shows,
  /// are highlights and read no paint, like shadows. <= 0: none.
  double highlight{};
  /// Pixels darker than this share of the image's albedo (top_fit) are shadow and read no paint; a
  /// dark paint in the light is brighter than that (in [0, 1)).
  double shadow{};
};

/// reflectance_colour reads a pixel's colour only where it is brighter than this share of the
/// brightest pixel: darker ones are spread into from their neighbours.
constexpr double kReflectanceDarkShare = 0.05;

struct Reflectance {
  /// H x W reflectance relative to the object's bright paint: 1 at its 90th percentile over the mask,
  /// 1 outside the mask. The image divided by it is the shading image of one albedo.
  ImageF relative;
  int edge_pairs = 0;  ///< neighbour pairs read as paint edges
};

/// Estimates the reflectance of a painted surface (Retinex with colour, Land & McCann 1971, Funt et al.
/// 1992): paint edges are found where the chromaticity jumps (colour) or the log intensity jumps
/// against its local trend (ReflectanceParams); across such an edge the reflectance changes by the
/// image's log step less the shading's step, bridged from the steps on either side of the edge; it is
/// constant everywhere else, in shadows and in highlights. The log reflectance is the least-squares
/// field with those steps on the mask (the integrator's Poisson solver).
///
/// @param[in] intensity H x W linear intensity (>= 2 x 2, finite, >= 0).
/// @param[in] colour    H x W x 3 linear RGB of the same image, or nullptr for a grey image.
/// @param[in] mask      H x W pixels of the object.
/// @param[in] params    see ReflectanceParams.
/// @param[in] progress  stage "albedo"; may throw Cancelled.
/// @param[in] shading   H x W shading of a surface found before (any scale), or nullptr: where it is
///                      above kReflectanceDarkShare of its maximum at both ends of a paint edge, the
///                      edge's shading step is its step, not the image's steps beside the edge.
Reflectance estimate_reflectance(const ImageF& intensity, const ColourImage* colour, const Mask& mask,
                                 const ReflectanceParams& params, const Progress& progress = {},
                                 const ImageF* shading = nullptr);

/// The colour of the reflectance: the image's chromaticity times `grey_albedo` (H x W, the grey albedo
/// per pixel), spread from the pixels where it can be read (brighter than kReflectanceDarkShare of the
/// albedo) into the others. H x W x 3, 0 outside the mask.
ColourImage reflectance_colour(const ImageF& intensity, const ColourImage& colour, const Mask& mask,
                               const ImageF& grey_albedo);

}  // namespace shadecut
