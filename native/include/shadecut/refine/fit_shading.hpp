// A depth that explains the image: the integrated depth of a reconstruction, refined so that its
// Lambertian rendering matches the image (beyond the paper, which stops at integration).
#pragma once

#include <shadecut/support/progress.hpp>
#include <shadecut/support/types.hpp>

#include <Eigen/Core>

namespace shadecut {

struct FitShadingParams {
  /// mu of the cost below, for an object of kReferenceObjectSize pixels (local_shape.hpp); the
  /// per-pixel weight is mu * object_size / kReferenceObjectSize, which gives the same surface the
  /// same minimum at every resolution (depth second differences shrink as 1 / resolution).
  /// No default here: ReconstructOptions::fit_smoothness holds the tuned one.
  double smoothness{};
  int max_steps = 15;              ///< Levenberg-Marquardt steps at most
  /// A larger object (object_size, pixels) is fitted on blocks of ceil(its size / this) pixels: the
  /// correction, bilinearly interpolated back, then the largest of 1, 1/2, 1/4, 1/8 of it that does
  /// not raise the residual at full resolution (or none). Bounds the time, since the sparse
  /// factorizations grow faster than the pixel count (docs/benchmarks.md, "Fitting the depth to the
  /// image").
  double max_object_size = 256.0;
  double tolerance = 1e-4;         ///< stop when a step lowers the cost by less than this share of it
};

struct FitShadingStats {
  double residual_before = 0.0;    ///< sum over the fitted pixels of (rho max(0, n . S) - I)^2, start depth
  double residual_after = 0.0;     ///< the same for the returned depth; never above residual_before
  int steps = 0;                   ///< accepted steps (on blocks: theirs, 0 if none of their correction applies)
};

/// Refines `depth` (z0) to minimize
///
///   sum over fitted pixels (rho max(0, n(z) . S) - I)^2  +  mu^2 sum |second differences of (z - z0)|^2
///
/// The second term asks the correction, not the surface, to be smooth: a surface's own curvature (a
/// sphere's rim) costs nothing, and where the start is right the fit leaves it (smoothing z itself
/// flattened the sphere's rim on the training surfaces: docs/method.md, section 8).
///
/// by Levenberg-Marquardt (Gauss-Newton steps, each a sparse Cholesky solve, SimplicialLDLT), started
/// from `depth`. n(z) = (-p, -q, 1) / |.| with p, q the masked central differences of the depth
/// (one-sided at the mask's edge), exactly as normals_from_depth takes them, so the normals of the
/// result render as fitted. A step is kept only if it lowers the cost and leaves the brightness
/// residual at or below the start's: the result never explains the image worse than `depth`.
///
/// @param[in,out] depth  H x W, pixel units (larger = closer); values outside the mask are kept.
/// @param[in] image      H x W linear intensity.
/// @param[in] mask       H x W pixels of the surface.
/// @param[in] fitted     H x W pixels whose intensity is Lambertian (inside the mask; e.g. the mask
///                       without unreliable_pixels: shadows and highlights do not follow the model).
/// @param[in] light      unit direction toward the light, S_z > 0.
/// @param[in] albedo     rho > 0.
/// @param[in] progress   told the fraction of steps done, stage "fit_shading"; false cancels.
FitShadingStats fit_shading(ImageF& depth, const ImageF& image, const Mask& mask, const Mask& fitted,
                            const Eigen::Vector3d& light, double albedo, const FitShadingParams& params,
                            const Progress& progress = {});

}  // namespace shadecut
