// A viscosity-solution shape from shading for an oblique light: the modern baseline the graph cut is
// measured against.
#pragma once

#include <shadecut/support/light.hpp>
#include <shadecut/support/progress.hpp>
#include <shadecut/support/types.hpp>

namespace shadecut {

struct UpwindResult {
  ImageF depth;        ///< H x W, pixel units, larger = closer, 0 outside the mask
  int iterations = 0;  ///< rounds of four sweeps done
  bool converged = false;  ///< the last round changed no depth by more than 1e-4 pixel
};

/// The brightest shade I / albedo the sweeps solve for. At I = 1 the equation holds at one slope
/// only (the normal along the light), which rounding misses, so no update settles there and the
/// depth around it sinks a little more every round; just below 1 it holds on a small ring of slopes
/// and every update has a solution (docs/comparison_methods.md, "upwind").
constexpr double kUpwindBrightestShade = 1.0 - 1e-4;

/// Solves the orthographic Lambertian equation for the depth z (p = dz/dx, q = dz/dy, y up)
///   H(p, q) = I sqrt(1 + p^2 + q^2) + S_x p + S_y q - S_z = 0,   I = image / albedo,
/// I clamped to `brightest_shade`, with z = 0 on the mask's edge (an object seen whole: its outline is the silhouette), for its
/// maximal viscosity solution, the one that bulges toward the viewer. H is convex in (p, q), so the
/// upwind (Godunov-type) update of a pixel is the smallest value, over the stencils of one horizontal
/// and/or one vertical neighbour, that solves H = 0 with one-sided differences toward those
/// neighbours and is causal (the characteristic dH/d(p, q) comes from them); a stencil with no
/// neighbour in x (or y) takes the p (or q) that minimizes H. Gauss-Seidel sweeps in the four
/// diagonal orders (fast sweeping, Tsai, Cheng, Osher & Zhao, SIAM J. Numer. Anal. 41, 2003) start
/// from +infinity inside the mask and only lower the depth.
///
/// @param[in] image      H x W linear intensity.
/// @param[in] mask       H x W pixels to reconstruct; out-of-image pixels count as outside.
/// @param[in] light      the light frame (LightFrame::from_direction).
/// @param[in] albedo     > 0.
/// @param[in] iterations most rounds of four sweeps, >= 1; fewer when a round changes nothing.
/// @param[in] progress   told the fraction of the rounds done, as stage "upwind"; may throw Cancelled.
/// @param[in] brightest_shade  in (1e-3, 1]: the largest I solved for (kUpwindBrightestShade).
UpwindResult upwind(const ImageF& image, const Mask& mask, const LightFrame& light, double albedo, int iterations,
                    const Progress& progress = {}, double brightest_shade = kUpwindBrightestShade);

}  // namespace shadecut
