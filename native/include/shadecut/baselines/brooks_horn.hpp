// Brooks & Horn's variational shape from shading, the global method the paper compares with.
#pragma once

#include <shadecut/support/light.hpp>
#include <shadecut/support/progress.hpp>
#include <shadecut/support/types.hpp>

namespace shadecut {

/// The iteration corrects n.S by -(n.S - E/albedo) / (4 lambda) a sweep, which overshoots the
/// brightness for lambda <= 1/4: the normals then oscillate instead of converging (a 64-px sphere
/// still does after 8000 sweeps at 1/4, and settles in ~560 at 0.3). reconstruct() keeps the
/// per-pixel lambda at or above this.
constexpr double kStableSmoothness = 0.3;

struct BrooksHornParams {
  double smoothness = 1.0;        ///< lambda: weight of the smoothness term against the brightness error, > 1/4
  int iterations = 1000;          ///< upper bound on sweeps, >= 1
  double tolerance = 0.0;         ///< stop when a sweep moves the normals by at most this (mean |dn|), >= 0
  bool occluding_contour = true;  ///< hold the mask's edge at the outward silhouette normal (n_z = 0)
};

struct BrooksHornResult {
  NormalMap normals;  ///< H x W camera-frame unit normals, 0 outside the mask
  int iterations = 0; ///< sweeps done
  double change = 0.0;///< mean |dn| of the last sweep
};

/// Minimizes sum (E/albedo - n.S)^2 + lambda sum |grad n|^2 subject to |n| = 1 by the iteration of the
/// paper's eq. (6): n <- normalize(mean of the 4-neighbour normals + (E/albedo - n.S) S / (4 lambda)),
/// one red-black Gauss-Seidel sweep per iteration, neighbours outside the mask left out of the mean.
/// Every normal starts at S, as in the paper's comparison. From there only a boundary condition can
/// move the field (a uniform field along S is a fixed point), so with `occluding_contour` the mask's
/// edge away from the image border holds the outward normal of a silhouette (Ikeuchi & Horn).
///
/// @param[in] image    H x W linear intensity.
/// @param[in] mask     H x W pixels to reconstruct.
/// @param[in] light    the light frame (LightFrame::from_direction).
/// @param[in] albedo   > 0.
/// @param[in] params   see BrooksHornParams; throws InvalidArgument when out of range.
/// @param[in] progress told the fraction of the iterations done, as stage "brooks_horn"; may throw Cancelled.
BrooksHornResult brooks_horn(const ImageF& image, const Mask& mask, const LightFrame& light, double albedo,
                             const BrooksHornParams& params, const Progress& progress = {});

}  // namespace shadecut
