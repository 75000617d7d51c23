// Internal: the least-squares depth of a masked pixel grid: by the cosine transform on a whole
// rectangle, otherwise by conjugate gradients preconditioned with an aggregation multigrid V-cycle.
#pragma once

#include <shadecut/support/progress.hpp>
#include <shadecut/support/types.hpp>

#include <vector>

namespace shadecut::detail {

/// The rises along the mask's 4-neighbour edges: right[i] = z(r, c + 1) - z(r, c) and
/// down[i] = z(r + 1, c) - z(r, c) wanted, i = r * cols + c; read only where both ends are masked.
struct EdgeRises {
  std::vector<double> right, down;
};

/// A pull of each cell toward a value: weight[i] (z_i - target[i])^2 added to the sum minimised.
/// H * W each, weights >= 0; a component with a positive weight has its constant fixed.
struct Anchors {
  std::vector<double> weight, target;
};

/// Minimises the sum over every pair (a, b) of 4-neighbours both in `mask` of (z_b - z_a - rise_ab)^2
/// and the anchors' pulls, if any: solves (L + diag(weight)) z = div(rise) + weight * target, with L
/// the mask's graph Laplacian. A mask that covers the whole grid, without
/// anchors, is solved exactly by the cosine transform, which diagonalizes L there; any other is
/// iterated until the residual is at most `relative_tolerance` times the right-hand side's (the
/// depth is then exact to about that relative precision). Without anchors each 4-connected
/// component's depth is defined up to a constant, which this leaves arbitrary. Bit-identical for any
/// number of threads (every line is transformed alone; the iteration's sums are taken row by row,
/// then in row order).
///
/// @param[in] mask     H x W.
/// @param[in] rises    H * W each, or both empty for no rises.
/// @param[in] progress told the fraction of the iterations done (estimated from the residual; 1 at the
///                     end of a whole grid's solve), as
///                     stage "integration"; may throw Cancelled.
/// @param[in] anchors  optional (nullptr: none).
/// @return H * W depth, row-major; 0 outside the mask.
std::vector<double> solve_grid_poisson(const Mask& mask, const EdgeRises& rises, double relative_tolerance,
                                       const Progress& progress = {}, const Anchors* anchors = nullptr);

}  // namespace shadecut::detail
