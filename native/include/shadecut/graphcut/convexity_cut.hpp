// The global convex / concave decision: one minimum cut over the two local candidates of every pixel.
#pragma once

#include <shadecut/graphcut/maxflow.hpp>
#include <shadecut/graphcut/tilt_energy.hpp>

#include <vector>

namespace shadecut {

/// Labels every pixel with the candidate (concave t or convex t + pi, as their nearest labels) that
/// minimizes the energy restricted to the two candidates (the paper's eq. 10), solved as ONE binary
/// problem by a single minimum cut.
///
/// Expansion moves change one label value at a time, so they cannot turn a whole curved region from
/// convex to concave (its tilts span many labels); this binary cut can, and it is exact where the
/// pairwise terms are submodular, which holds wherever neighbouring candidate tilts differ by less than
/// 90 degrees. Elsewhere (near singular points of the tilt field) the pairwise term is truncated to its
/// submodular part. Pixels with only one allowed candidate (the other faces away from the viewer) are
/// fixed to it and anchor the rest. Pixels whose tilt is undefined, or with neither candidate allowed,
/// keep their label from `labelling` and do not take part.
///
/// @param[in] energy        the tilt energy (data costs decide which candidates are allowed).
/// @param[in] local         the local estimates the energy was built from.
/// @param[in,out] labelling one allowed label per masked pixel; candidates are written into it.
/// @param[in] solver        the max-flow solver.
void convexity_cut(const TiltEnergy& energy, const LocalShape& local, std::vector<int>& labelling,
                   MaxFlowSolver& solver);

}  // namespace shadecut
