// Internal to the max-flow layer: warm starts for a family of grid graphs on the same nodes, one per
// label, whose capacities change a few nodes at a time (the expansion moves of alpha-expansion).
// Not part of the public API.
#pragma once

#include <shadecut/graphcut/grid_graph.hpp>
#include <shadecut/graphcut/tilt_energy.hpp>

#include <cstddef>
#include <cstdint>
#include <vector>

namespace shadecut::maxflow_internal {

/// The flows kept from the last cut of every label's graph, and the log of the nodes whose
/// capacities changed since. A flow is the net flow through the arc of each node to its right and to
/// its lower neighbour (the arcs' reverse capacities are zero, so it is >= 0); the terminal flows
/// follow from conservation. Together with the current capacities a label's flow reparametrizes its
/// next cut, which then only has to push what the changes since made possible.
/// An arc has capacity only between two pixels where its label is allowed, so each flow is stored at
/// its pixel's slot for the label (TiltEnergy::slot): with coarse to fine, a few labels a pixel
/// instead of two planes a label.
class KeptFlows {
 public:
  /// @param[in] energy  gives the grid, the labels and the slot layout; must outlive this object.
  explicit KeptFlows(const TiltEnergy& energy);

  /// The label the members below read and write.
  void set_alpha(int alpha) { alpha_ = alpha; }

  /// Whether the current label has a flow (until then its slots hold zeros).
  bool started() const { return state().started; }
  /// Whether that flow is maximal for the graph as it was when it was last cut, or the move was empty.
  bool maximal() const { return state().maximal; }

  float right(int p) const { return read(right_, p); }
  float down(int p) const { return read(down_, p); }
  void set_right(int p, float flow) { write(right_, p, flow); }
  void set_down(int p, float flow) { write(down_, p, flow); }

  /// Starts the current label's flow as a copy of `label`'s, where that one has started (-1: none,
  /// i.e. a zero flow).
  void start_from(int label);

  /// Takes as the current label's flow what a solver that leaves_residuals() left in `graph`, a graph
  /// reparametrized by that flow: the reverse capacities held the kept flow over arcs of zero reverse
  /// capacity, so now they hold the new flow.
  void keep(const GridGraph& graph);

  /// Records that the current label's flow was just cut: `maximal` as maximal() will report; the
  /// changes logged from now on are new to it.
  void mark_cut(bool maximal) {
    state().log_position = log_.size();
    state().maximal = maximal;
  }
  /// Records that the current label's flow is not maximal for its graph, so that its next cut starts
  /// over from the full graph.
  void mark_not_maximal() { state().maximal = false; }

  /// Logs that the nodes in `nodes` changed their capacities, in every label's graph.
  void log_changes(const std::vector<int>& nodes) { log_.insert(log_.end(), nodes.begin(), nodes.end()); }
  /// Number of node changes logged since the current label's flow was last cut (a node may repeat).
  std::size_t changes_since_cut() const { return log_.size() - state().log_position; }
  /// Lists in `nodes` every node changed since the current label's flow was last cut, once each.
  void changed_since_cut(std::vector<int>& nodes);

 private:
  struct State {
    bool started = false;
    bool maximal = false;
    std::size_t log_position = 0;  // changes logged before this were part of the graph it solved
  };

  State& state() { return states_[std::size_t(alpha_)]; }
  const State& state() const { return states_[std::size_t(alpha_)]; }

  float read(const std::vector<float>& flows, int p) const {
    const std::int64_t s = energy_.slot(p, alpha_);
    return s < 0 ? 0.0f : flows[std::size_t(s)];
  }
  // An arc without a slot has no capacity, so the flow written there is 0.
  void write(std::vector<float>& flows, int p, float flow) {
    const std::int64_t s = energy_.slot(p, alpha_);
    if (s >= 0) flows[std::size_t(s)] = flow;
  }

  const TiltEnergy& energy_;
  std::vector<float> right_, down_;
  std::vector<State> states_;
  int alpha_ = 0;
  std::vector<int> log_;  // every node that changed, in order
  std::vector<int> seen_;  // round in which changed_since_cut() listed each node
  int seen_round_ = 0;
};

}  // namespace shadecut::maxflow_internal
