// Internal to alpha-expansion: how the expansion move of one label becomes an s-t graph on the pixel
// grid, and what the move changes in the energy. Not part of the public API.
#pragma once

#include "graphcut/maxflow_warm_start.hpp"

#include <shadecut/graphcut/grid_graph.hpp>
#include <shadecut/graphcut/tilt_energy.hpp>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace shadecut::detail {

/// The terms of the expansion move of one label, read straight from the energy and the labelling
/// (node on the sink side = pixel switches to alpha). Kolmogorov & Zabih: a pairwise term with values
/// A = V(lp, lq), B = V(lp, alpha), C = V(alpha, lq), D = V(alpha, alpha) = 0 becomes
/// A + (C - A) x_p + (D - C) x_q + (B + C - A - D) (1 - x_p) x_q, the last an arc p -> q; no arc
/// runs q -> p. The full graph (build_move) and the sparse repair (maxflow_internal::SparseRepair)
/// both read their capacities from here, in the same float operations, so that a flow kept from one
/// is exact for the other. Everything is inline: both call it once or more per pixel.
class MoveTerms {
 public:
  /// @param[in] energy     the energy; must outlive this object.
  /// @param[in] labelling  the current labelling, read where it stands at every call.
  MoveTerms(const TiltEnergy& energy, const std::vector<int>& labelling)
      : energy_(energy),
        labelling_(labelling),
        rows_(energy.rows()),
        cols_(energy.cols()),
        labels_(energy.labels()),
        mask_(energy.mask().data()),
        distance_(2 * std::size_t(labels_)) {
    // label_distance without its modulo: entry a - b + labels.
    for (int d = 0; d < 2 * labels_; ++d) distance_[std::size_t(d)] = energy.label_distance(d, 0);
  }

  int rows() const { return rows_; }
  int cols() const { return cols_; }
  void set_alpha(int alpha) { alpha_ = alpha; }
  int label(int p) const { return labelling_[std::size_t(p)]; }

  /// Whether pixel p can switch to alpha.
  bool variable(int p) const {
    return variables_ ? variables_[p] != 0 : mask_[p] && label(p) != alpha_ && energy_.allowed(p, alpha_);
  }
  /// Answers variable() from `variables` (one flag per pixel, for the current alpha); null: computes it.
  void cache_variables(const std::uint8_t* variables) { variables_ = variables; }

  /// Capacity of the arc from p to its right (q = p + 1) or lower (q = p + cols) neighbour, given that
  /// edge's weight; zero unless both are variables.
  float arc(int p, int q, float weight) const {
    if (!(weight > 0.0f) || !variable(p) || !variable(q)) return 0.0f;
    const int lp = label(p), lq = label(q);
    const float a = weight * distance(lp, lq);
    const float b = weight * distance(lp, alpha_);
    const float c = weight * distance(alpha_, lq);
    return std::max(0.0f, b + c - a);
  }
  float right_arc(int p) const { return arc(p, p + 1, energy_.weight_right(p)); }
  float down_arc(int p) const { return arc(p, p + cols_, energy_.weight_down(p)); }

  /// Cost of switching p (at row r, column c) to alpha minus the cost of keeping its label, with the
  /// pairwise terms as the construction distributes them; 0 where p takes no part. In the graph: p's
  /// source capacity where > 0, minus its sink capacity where < 0.
  float terminal(int p, int r, int c) const {
    if (!variable(p)) return 0.0f;
    const int lp = label(p);
    float sum = 0.0f;
    // The edges in the order their owners come in a row-major sweep.
    if (r > 0) sum += from_other_end(p - cols_, energy_.weight_down(p - cols_), lp);
    if (c > 0) sum += from_other_end(p - 1, energy_.weight_right(p - 1), lp);
    if (c + 1 < cols_) sum += from_own_end(p + 1, energy_.weight_right(p), lp);
    if (r + 1 < rows_) sum += from_own_end(p + cols_, energy_.weight_down(p), lp);
    return sum + energy_.data_cost(p, alpha_) - energy_.data_cost(p, lp);
  }

 private:
  float distance(int a, int b) const { return distance_[std::size_t(a - b + labels_)]; }

  // Edge p -> q seen from p (a variable): C - A, whether q is a variable or fixed at its label.
  float from_own_end(int q, float weight, int lp) const {
    if (!(weight > 0.0f)) return 0.0f;
    const int lq = label(q);
    return weight * distance(alpha_, lq) - weight * distance(lp, lq);
  }
  // Edge o -> p seen from p (a variable): -C if o is a variable, else B - A with o at its label.
  float from_other_end(int o, float weight, int lp) const {
    if (!(weight > 0.0f)) return 0.0f;
    if (variable(o)) return -(weight * distance(alpha_, lp));
    const int lo = label(o);
    return weight * distance(lo, alpha_) - weight * distance(lo, lp);
  }

  const TiltEnergy& energy_;
  const std::vector<int>& labelling_;
  int rows_, cols_, labels_;
  const bool* mask_;
  std::vector<float> distance_;
  int alpha_ = 0;
  const std::uint8_t* variables_ = nullptr;
};

/// Builds the s-t graph of the move of the label `terms` is set to, reparametrized by the current
/// label's kept flow when `flows` is given (the flow is cut back to the current capacities first, and
/// stored so).
///
/// @param[in] terms        the move; its variables are cached while the graph is built.
/// @param[in,out] flows    null, or the kept flows set to the same label.
/// @param[out] graph       sized terms.rows() x terms.cols() already; every capacity is written.
/// @param[out] variable    one entry per pixel, sized already: 1 where the pixel can switch.
/// @return whether any pixel can switch (if not, `graph` is left as it was).
bool build_move(MoveTerms& terms, maxflow_internal::KeptFlows* flows, GridGraph& graph,
                std::vector<std::uint8_t>& variable);

/// Energy change of switching the pixels in `changed` to `alpha`, exactly in double precision (the
/// graph's float capacities are not).
///
/// @param[in] energy      the energy.
/// @param[in] labelling   the labelling before the move.
/// @param[in] alpha       the move's label.
/// @param[in] changed     the pixels that switch.
/// @param[in] is_changed  one flag per pixel: 1 exactly at the pixels in `changed`.
double move_delta(const TiltEnergy& energy, const std::vector<int>& labelling, int alpha,
                  const std::vector<int>& changed, const std::vector<std::uint8_t>& is_changed);

}  // namespace shadecut::detail
