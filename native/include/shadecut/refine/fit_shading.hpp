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
  /// same minimum at every resolution (a depth's Laplacian in pixels shrinks as 1 / resolution).
  /// No default here: ReconstructOptions::fit_smoothness holds the tuned one.
  double smoothness{};
  /// ADMM steps (each about one Poisson solve) at most at any one level of coarse to fine; 0: no fit.
  int max_steps = 200;
  /// Degrees, in (0, 90]: a pixel whose start normal (the start depth's) is more than this from the
  /// viewer is not fitted; the smoothness and its neighbours carry it. 90: every pixel of `fitted`.
  /// No default here: ReconstructOptions::fit_max_slant holds the tuned one.
  double max_slant{};
};

struct FitShadingStats {
  double residual_before = 0.0;    ///< sum over the fitted pixels of (rho max(0, n . S) - I)^2, start depth
  double residual_after = 0.0;     ///< the same for the returned depth; never above residual_before
  int steps = 0;                   ///< ADMM steps, over every level, that led to the returned depth (0: none kept)
};

/// Refines `depth` (z0) over the whole image, at its own resolution, to minimize
///
///   sum over fitted pixels (rho max(0, n(z) . S) - I)^2  +  mu^2 sum |L (z - z0)|^2
///
/// with L the mask's graph Laplacian (4-neighbours both masked). The second term asks the correction,
/// not the surface, to be smooth: a surface's own curvature (a sphere's rim) costs nothing, and where
/// the start is right the fit leaves it (docs/method.md, section 8).
///
/// By ADMM on a per-pixel gradient g = grad z: a gradient step (per pixel, a 2-D Gauss-Newton
/// problem in closed form, on every core), a depth step (one Poisson solve of the gradient's changes,
/// detail::solve_grid_poisson, and one Jacobi step for the smoothness), a dual step; coarse to fine
/// (block averages by 2 down to an object of at most 32 pixels, each level started from the coarser
/// one), so that the many steps the large-scale shape needs run where they are cheap. n(z) =
/// (-p, -q, 1) / |.| with p, q the masked central differences of the depth (one-sided at the mask's
/// edge), exactly as normals_from_depth takes them, so the normals of the result render as fitted.
/// The result is returned only if its brightness residual is at or below the start's: it never
/// explains the image worse than `depth`. Steep pixels (params.max_slant) are left out of the fit:
/// there a pixel's central differences depart most from the surface's normal and the integrated
/// start is least sure; fitted, their errors ran inward along the image's characteristic curves
/// (docs/method.md, section 8).
///
/// @param[in,out] depth  H x W, pixel units (larger = closer); values outside the mask are kept.
/// @param[in] image      H x W linear intensity.
/// @param[in] mask       H x W pixels of the surface.
/// @param[in] fitted     H x W pixels whose intensity is Lambertian (inside the mask; e.g. the mask
///                       without unreliable_pixels: shadows and highlights do not follow the model);
///                       of them, those at most params.max_slant steep are fitted.
/// @param[in] light      unit direction toward the light, S_z > 0.
/// @param[in] albedo     rho > 0.
/// @param[in] progress   told the fraction of the work done, stage "fit_shading"; false cancels.
FitShadingStats fit_shading(ImageF& depth, const ImageF& image, const Mask& mask, const Mask& fitted,
                            const Eigen::Vector3d& light, double albedo, const FitShadingParams& params,
                            const Progress& progress = {});

}  // namespace shadecut
