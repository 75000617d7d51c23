// Alpha-expansion (Boykov, Veksler & Zabih 2001) of a TiltEnergy.
#pragma once

#include <shadecut/graphcut/maxflow.hpp>
#include <shadecut/support/progress.hpp>
#include <shadecut/graphcut/tilt_energy.hpp>

#include <vector>

namespace shadecut {

struct AlphaExpansionStats {
  std::vector<double> energy_per_cycle;  ///< energy of the initial labelling, then after every cycle
  int cycles = 0;                        ///< full cycles over the labels
  int moves = 0;                         ///< expansion moves solved (labels with no candidate pixel are skipped)
  int accepted_moves = 0;                ///< moves that lowered the energy
  int repaired_moves = 0;                ///< moves solved by finishing the label's kept flow, without a full cut
  double maxflow_seconds = 0.0;          ///< time inside MaxFlowSolver::solve and the sparse repairs of kept flows
};

/// Minimizes `energy` by expansion moves, cycling over the labels until a full cycle lowers the energy
/// no more (or `max_cycles` cycles, or a cycle lowers it by no more than `tolerance` times itself). Each move is a minimum cut over the pixels where the label is
/// allowed and not already taken (Kolmogorov & Zabih's construction; the pairwise term is a metric, so
/// every move is graph-representable). A move is kept only if it lowers the energy, so the energy never
/// rises. A solver that leaves_residuals() lets every label keep its last maximum flow: the label's
/// next move starts from it, and when few pixels changed since, it is finished by a search around
/// them instead of a full cut (the same minimum cut, found in a fraction of the time).
///
/// @param[in] energy        the energy.
/// @param[in,out] labelling one allowed label per masked pixel (e.g. energy.convex_labelling()).
/// @param[in] solver        the max-flow solver; its buffers are reused across moves.
/// @param[in] max_cycles    >= 1.
/// @param[in] tolerance     >= 0; 0 = run until a cycle gains nothing (the paper's criterion).
/// @param[in] progress      told after every move the fraction of the cycle budget done, as stage
///                          "graphcut"; may throw Cancelled.
AlphaExpansionStats alpha_expansion(const TiltEnergy& energy, std::vector<int>& labelling, MaxFlowSolver& solver,
                                    int max_cycles, double tolerance = 0.0, const Progress& progress = {});

}  // namespace shadecut
