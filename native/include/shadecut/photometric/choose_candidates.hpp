// The graph cut wherever the photographs leave a choice: one normal per pixel out of a few candidates,
// so that neighbours agree.
#pragma once

#include <shadecut/photometric/photometric_stereo.hpp>
#include <shadecut/support/progress.hpp>
#include <shadecut/support/types.hpp>

#include <cstdint>
#include <vector>

namespace shadecut {

/// Up to N candidate normals per pixel.
struct NormalCandidates {
  /// N maps, each H x W: candidate k of every pixel (unit, camera frame); read where k < count.
  std::vector<NormalMap> normals;
  /// H x W, 0..N: how many candidates a pixel has. 0 = the pixel takes no part (outside the surface,
  /// or left to another method); 1 = fixed, it anchors its neighbours.
  CountImage count;
  /// Empty, or N maps H x W: the cost (>= 0, finite) of choosing candidate k, on the scale of the
  /// smoothness term (a chord: 0..2 per neighbour pair).
  std::vector<ImageF> data_cost;
};

/// The candidates photometric_stereo leaves: one (its normal) where three or more photographs are
/// usable, four (four_fits, costing each its cost less the cheapest's) where one of four is
/// left out, two (first_candidate, second_candidate) where two are, none elsewhere. A candidate that
/// faces away from the viewer (n_z < 0) costs -n_z, about its distance to the nearest visible normal:
/// near the outline noise puts the true normal there too, so it stays a candidate (a pixel left with
/// one would hold its neighbours to it). Each also costs its shadow conflict: the light it would
/// catch where the other photographs are dark. Takes `result` by value: pass it with std::move when it
/// is not needed after, and its normal maps are moved into the candidates instead of copied.
NormalCandidates photometric_candidates(PhotometricStereoResult result);

struct CandidateCutParams {
  /// Weight of the pairwise term: smoothness |n_p - n_q| between 4-neighbours (the paper's V_pq,
  /// a chord), against the data costs. > 0.
  double smoothness = 1.0;
  int max_cycles = 10;  ///< cycles of moves over the candidate indices, >= 1
  /// After the cut, every segment of pixels with two candidates (4-connected, bounded where the two
  /// come within kCoincidentDegrees of each other) is switched to its other candidates when that makes
  /// the normals clearly more integrable (the squared curl of their gradients, summed over the 2 x 2
  /// cells that touch it, falls by half or more). The smoothness term cannot tell such a segment from
  /// its mirror image: two
  /// lights leave the mirror of a smooth field across their plane as smooth, but not integrable.
  bool integrable_segments = true;
};

/// Two candidates closer than this (degrees) are one: the pixel bounds segments (integrable_segments).
constexpr double kCoincidentDegrees = 3.0;

struct CandidateCutResult {
  NormalMap normals;   ///< H x W, the chosen candidate as given; (0, 0, 0) where count is 0
  CountImage choice;   ///< H x W, the chosen candidate's index; -1 where count is 0
  /// Energy of the start: every pixel at its cheapest candidate. Where no pixel has two or more
  /// candidates there is nothing to choose and nothing is summed: initial_energy and energy are 0.
  double initial_energy = 0.0;
  double energy = 0.0;          ///< energy of the cut's result (never above initial_energy), before
                                ///< integrable_segments
  int cycles = 0;               ///< cycles run (the most of any region)
  int accepted_moves = 0;       ///< moves that lowered the energy
  int segments = 0;             ///< segments of two candidates (integrable_segments)
  int switched_segments = 0;    ///< of them, switched to their other candidates
};

/// Minimizes E = sum_p D_p(k_p) + smoothness sum over 4-neighbours (p, q) with candidates of
/// |n_p(k_p) - n_q(k_q)| over the choices k_p, by fusion moves (Lempitsky et al. 2010): move k lets
/// every pixel that has a candidate k switch to it at once, a minimum cut on the pixel grid with the
/// core's max-flow solver. The pairs of a move whose term is not submodular are approximated
/// (Rother et al. 2005) and a move is kept only if the exact energy falls, so the energy never rises.
/// Each 4-connected region of pixels with a choice is cut on its own bounding box: regions meet only
/// through fixed pixels, so the energy splits exactly between them, and a move's graph spans the
/// pixels with a choice, not the frame. A region's cycles stop when a cycle keeps no move or after
/// max_cycles. With two candidates per pixel named
/// consistently (photometric_candidates: `first` on the viewer's side of the lights' plane), a region
/// whose whole choice is wrong switches in one move. Then CandidateCutParams::integrable_segments.
///
/// @param[in] candidates the candidates (shapes checked); by value: pass them with std::move when they
///                       are not needed after, and where no pixel has a choice their maps become the
///                       result without a copy.
/// @param[in] params     weights.
/// @param[in] progress   told the fraction of the cycle budget done, as stage "candidate cut"; may
///                       throw Cancelled.
/// @throws InvalidArgument for mismatched shapes, a count outside 0..N, non-finite or negative costs,
///         non-finite candidates, or params out of range.
CandidateCutResult choose_candidates(NormalCandidates candidates, const CandidateCutParams& params = {},
                                     const Progress& progress = {});

}  // namespace shadecut
