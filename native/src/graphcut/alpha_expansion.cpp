#include <shadecut/graphcut/alpha_expansion.hpp>

#include <shadecut/support/errors.hpp>

#include "graphcut/expansion_move.hpp"
#include "graphcut/maxflow_repair.hpp"
#include "graphcut/maxflow_warm_start.hpp"
#include "support/stopwatch.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>

namespace shadecut {

namespace {

using detail::MoveTerms;
using maxflow_internal::KeptFlows;
using Repair = maxflow_internal::SparseRepair<MoveTerms>;

void check_arguments(const TiltEnergy& energy, const std::vector<int>& labelling, int max_cycles,
                     double tolerance) {
  if (max_cycles < 1) throw InvalidArgument("shadecut: max_cycles must be at least 1");
  if (!(tolerance >= 0.0) || !std::isfinite(tolerance)) throw InvalidArgument("shadecut: tolerance must be finite and >= 0");
  const int n = energy.rows() * energy.cols(), labels = energy.labels();
  if (labelling.size() != std::size_t(n)) throw InvalidArgument("shadecut: the labelling has the wrong size");
  for (int p = 0; p < n; ++p)
    if (energy.mask().data()[p] && (labelling[std::size_t(p)] < 0 || labelling[std::size_t(p)] >= labels ||
                                    !energy.allowed(p, labelling[std::size_t(p)])))
      throw InvalidArgument("shadecut: the initial labelling uses a prohibited label");
}

// Solves the expansion moves. With a solver that leaves_residuals(), every label keeps the maximum
// flow of its last move, and its next move is finished from that flow by the sparse repair when few
// pixels changed since, else cut from the full graph reparametrized by it.
class MoveSolver {
 public:
  // `labelling` is read where it stands at every move.
  MoveSolver(const TiltEnergy& energy, const std::vector<int>& labelling, MaxFlowSolver& solver)
      : terms_(energy, labelling),
        solver_(solver),
        variable_(std::size_t(energy.rows()) * std::size_t(energy.cols())),
        flows_(solver.leaves_residuals() ? std::make_unique<KeptFlows>(energy) : nullptr),
        // Past these a repair would cover most of the grid anyway and the full solver does it faster
        // (chosen by instruction counts on the benchmark sphere at 384 x 384: a repair stopped early
        // is work lost, so the budget is generous).
        repair_limit_(variable_.size() / 2),
        repair_budget_(8 * long(variable_.size())) {
    // A pixel with a single label never switches; coarse to fine leaves most pixels so.
    for (int p = 0; p < int(variable_.size()); ++p)
      if (energy.mask().data()[p] && energy.window_width(p) > 1) open_pixels_.push_back(p);
  }

  // Solves the move of label `alpha`: `changed` gets the pixels that switch in its minimum cut
  // (maybe none), `stats` the time in max-flow and the repairs. False when no pixel can switch.
  bool solve(int alpha, std::vector<int>& changed, AlphaExpansionStats& stats) {
    terms_.set_alpha(alpha);
    if (flows_) {
      flows_->set_alpha(alpha);
      if (repairable()) {
        if (!repair_) repair_ = std::make_unique<Repair>(terms_.rows(), terms_.cols());
        const Stopwatch stopwatch;
        const bool repaired = repair_->run(terms_, *flows_, touched_, repair_budget_, changed);
        stats.maxflow_seconds += stopwatch.seconds();
        stats.repaired_moves += repaired;
        if (repaired) return true;
      }
      // The previous label's move has nearly the same shape; its flow, cut back to this move's
      // capacities, leaves less to push than none (docs/benchmarks.md, "Kept flows").
      if (!flows_->started()) flows_->start_from(alpha - 1);
    }
    // Sized at the first full cut: where the repairs solve every move, the graph is never needed.
    if (graph_.size() == 0) graph_.reset(terms_.rows(), terms_.cols());
    if (!detail::build_move(terms_, flows_.get(), graph_, variable_)) {
      // The kept flow was not cut back to an empty move: the label's next move starts over from the
      // full graph.
      if (flows_) flows_->mark_not_maximal();
      return false;
    }
    const Stopwatch stopwatch;
    solver_.solve(graph_, sink_side_);
    stats.maxflow_seconds += stopwatch.seconds();
    changed.clear();
    for (int p = 0; p < graph_.size(); ++p)
      if (variable_[std::size_t(p)] && sink_side_[std::size_t(p)]) changed.push_back(p);
    if (flows_) flows_->keep(graph_);
    return true;
  }

  // Records whether the move just solved was `applied`, i.e. its pixels in `changed` took alpha.
  void record(bool applied, const std::vector<int>& changed) {
    if (!flows_) return;
    // A refused cut leaves sink-side pixels unchanged that the repair would not look at.
    flows_->mark_cut(applied || changed.empty());
    if (applied) flows_->log_changes(changed);
  }

 private:
  // Whether the current label's move can be finished by the sparse repair; if so, touched_ lists the
  // pixels where its graph changed since its kept flow was maximal.
  bool repairable() {
    if (!flows_->started()) {
      // A label's first move starts from a zero flow, which is maximal for the empty graph before
      // every variable pixel "changed"; where those are few (coarse to fine keeps most labels out of
      // most pixels) the search around them solves it without a full graph.
      touched_.clear();
      for (int p : open_pixels_)
        if (terms_.variable(p)) touched_.push_back(p);
      if (touched_.size() > repair_limit_) return false;
      flows_->start_from(-1);
      flows_->mark_cut(true);
      return true;
    }
    if (!flows_->maximal() || flows_->changes_since_cut() > repair_limit_) return false;
    flows_->changed_since_cut(touched_);
    return true;
  }

  MoveTerms terms_;
  MaxFlowSolver& solver_;
  GridGraph graph_;
  std::vector<std::uint8_t> variable_, sink_side_;
  std::unique_ptr<KeptFlows> flows_;  // null: every move is cut from scratch
  std::unique_ptr<Repair> repair_;    // made at the first repair
  std::vector<int> touched_;
  std::vector<int> open_pixels_;  // masked pixels with more than one label in their window
  const std::size_t repair_limit_;
  const long repair_budget_;
};

}  // namespace

AlphaExpansionStats alpha_expansion(const TiltEnergy& energy, std::vector<int>& labelling, MaxFlowSolver& solver,
                                    int max_cycles, double tolerance, const Progress& progress) {
  check_arguments(energy, labelling, max_cycles, tolerance);
  const int labels = energy.labels();
  AlphaExpansionStats stats;
  double current = energy.energy(labelling);
  stats.energy_per_cycle.push_back(current);
  MoveSolver moves(energy, labelling, solver);
  std::vector<int> changed;
  std::vector<std::uint8_t> is_changed(labelling.size(), 0);

  // An expansion of a label that nothing has changed since its last expansion would find the same
  // cut, and so would one whose own move was the last change (expansion moves are idempotent): both
  // are skipped. `step` counts label visits; -1 = never.
  std::vector<long> solved_at(std::size_t(labels), -1);
  long step = 0, last_change = -1;
  for (int cycle = 0; cycle < max_cycles; ++cycle) {
    bool improved = false;
    for (int alpha = 0; alpha < labels; ++alpha, ++step) {
      const bool nothing_new = solved_at[std::size_t(alpha)] >= 0 && solved_at[std::size_t(alpha)] >= last_change;
      if (!nothing_new && moves.solve(alpha, changed, stats)) {
        solved_at[std::size_t(alpha)] = step;
        ++stats.moves;
        for (int p : changed) is_changed[std::size_t(p)] = 1;
        const double delta = detail::move_delta(energy, labelling, alpha, changed, is_changed);
        for (int p : changed) is_changed[std::size_t(p)] = 0;
        // Float capacities can make a cut that is optimal up to rounding raise the energy by a hair;
        // such a move is refused, which keeps the energy monotone.
        const bool accept = !changed.empty() && delta < -1e-9 * std::max(1.0, std::abs(current));
        moves.record(accept, changed);
        if (accept) {
          for (int p : changed) labelling[std::size_t(p)] = alpha;
          current += delta;
          improved = true;
          ++stats.accepted_moves;
          last_change = step;
        }
      }
      progress.report((cycle + double(alpha + 1) / labels) / max_cycles, "graphcut");
    }
    ++stats.cycles;
    const double before = stats.energy_per_cycle.back();
    current = energy.energy(labelling);
    stats.energy_per_cycle.push_back(current);
    if (!improved || before - current <= tolerance * std::abs(before)) break;
  }
  return stats;
}

}  // namespace shadecut
