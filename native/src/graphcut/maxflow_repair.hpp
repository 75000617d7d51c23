// Internal to the max-flow layer: the sparse repair, which finishes a kept flow (KeptFlows) after a
// few nodes of its graph changed, by a search around those nodes instead of a cut of the full graph.
// Not part of the public API.
#pragma once

#include "graphcut/maxflow_warm_start.hpp"

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace shadecut::maxflow_internal {

/// Finishes a maximum flow of a grid graph from a kept flow that was maximal for the graph before the
/// nodes in `changed` changed, where every node that could reach the sink then is among them (in
/// alpha-expansion: the applied cut switched those pixels to alpha, which changed them). Any
/// augmenting path must then start or pass where the graph changed. So a sink tree grown from the
/// new sink roots among the changed nodes and their neighbours, Boykov-Kolmogorov style but from the
/// sink only (the source tree would span nearly every node), finds them all; each path starts at a
/// node with source excess that the tree reaches. The tree holds exactly the nodes that can reach the
/// sink when no path is left: the sink side of the minimum cut the full solver would report.
/// A node is read from the capacities and the flow when the search first meets it, so the work is
/// proportional to the region the tree covers; past `budget` node visits it gives up and leaves a
/// valid, not yet maximal flow.
///
/// `Capacities` gives the graph on demand, in the same float operations as the full graph it
/// stands for, so that the flows stay exact for both: `float right_arc(int p) const` and
/// `float down_arc(int p) const`, the capacity of the arc from node p to its right / lower neighbour
/// (the reverse arcs have none), and `float terminal(int p, int r, int c) const`, p's source capacity
/// where > 0, minus its sink capacity where < 0 (r, c: p's row and column). A template, not an
/// interface: these are read once or more for every node the search meets.
template <class Capacities>
class SparseRepair {
 public:
  /// Sizes the search for a rows x cols grid; one object serves every move.
  SparseRepair(int rows, int cols)
      : rows_(rows), cols_(cols), n_(rows * cols), nodes_(std::size_t(n_) + 2 * std::size_t(cols)) {
    node_ = nodes_.data() + cols;
    offset_[0] = 1;
    offset_[1] = -1;
    offset_[2] = cols;
    offset_[3] = -cols;
    // The padding rows above and below stand for the arcs out of the grid: none.
    for (int p = -cols; p < 0; ++p) node_[p].loaded = kPadding;
    for (int p = n_; p < n_ + cols; ++p) node_[p].loaded = kPadding;
  }

  /// @param[in] capacities  the current graph, read on demand.
  /// @param[in,out] flow     the kept flows, set to the graph's label: the flow to finish; the flow
  ///                         pushed so far is written back whether or not the search finishes.
  /// @param[in] changed      the nodes whose capacities changed since the flow was maximal.
  /// @param[in] budget       node visits allowed.
  /// @param[out] sink_side   on success, the sink side of the minimum cut, in no particular order.
  /// @return false when the budget ran out: the flow is valid but may not be maximal.
  bool run(const Capacities& capacities, KeptFlows& flow, const std::vector<int>& changed, long budget,
           std::vector<int>& sink_side) {
    ++round_;
    capacities_ = &capacities;
    flow_ = &flow;
    budget_ = budget;
    queue_.clear();
    head_ = 0;
    orphans_.clear();
    tree_.clear();
    loaded_.clear();
    // Capacities fell on the arcs of changed nodes: a flow above its arc's capacity is cut back to
    // it, which moves the difference into the terminal excess of both ends (a reparametrization).
    for (const int p : changed) {
      const int c = p % cols_;
      if (c + 1 < cols_) flow.set_right(p, std::min(flow.right(p), capacities.right_arc(p)));
      if (c > 0) flow.set_right(p - 1, std::min(flow.right(p - 1), capacities.right_arc(p - 1)));
      if (p + cols_ < n_) flow.set_down(p, std::min(flow.down(p), capacities.down_arc(p)));
      if (p >= cols_) flow.set_down(p - cols_, std::min(flow.down(p - cols_), capacities.down_arc(p - cols_)));
    }
    for (const int p : changed) {
      for (int d = -1; d < 4; ++d) {
        const int q = d < 0 ? p : p + offset_[d];
        Node& u = node_[q];
        if (u.loaded == kPadding || u.loaded == round_) continue;
        load(q);
        if (u.excess < 0.0f) join(q, kRoot);
      }
    }
    const bool done = search();
    write_back();
    if (!done) return false;
    // A node that left the tree and joined it again is listed twice.
    sink_side.clear();
    for (const int p : tree_) {
      if (node_[p].in_tree != round_) continue;
      node_[p].in_tree = -1;
      sink_side.push_back(p);
    }
    return true;
  }

 private:
  static constexpr std::uint8_t kRoot = 4;
  static constexpr std::uint8_t kOrphan = 5;
  static constexpr std::int32_t kPadding = -2;

  struct Node {
    float res[4] = {0.0f, 0.0f, 0.0f, 0.0f};  // residual of the arc to the right / left / lower / upper neighbour
    float excess = 0.0f;                       // > 0: residual from the source; < 0: minus that to the sink
    std::int32_t loaded = -1;                  // round in which res and excess were read
    std::int32_t in_tree = -1;                 // round in which the node is in the tree
    std::uint8_t parent = 0;                   // direction towards the parent, kRoot or kOrphan
  };

  // Reads p's residuals from the current capacities and the kept flow (the arcs' reverse
  // capacities are zero, so a reverse residual is the flow), and its excess from its terminal
  // capacities less what its arcs carry away.
  void load(int p) {
    Node& v = node_[p];
    v.loaded = round_;
    loaded_.push_back(p);
    --budget_;
    const int r = p / cols_, c = p % cols_;
    const float right = c + 1 < cols_ ? flow_->right(p) : 0.0f, left = c > 0 ? flow_->right(p - 1) : 0.0f;
    const float down = r + 1 < rows_ ? flow_->down(p) : 0.0f, up = r > 0 ? flow_->down(p - cols_) : 0.0f;
    v.res[0] = c + 1 < cols_ ? capacities_->right_arc(p) - right : 0.0f;
    v.res[1] = left;
    v.res[2] = r + 1 < rows_ ? capacities_->down_arc(p) - down : 0.0f;
    v.res[3] = up;
    const float out = right + down - left - up;
    v.excess = capacities_->terminal(p, r, c) - out;
  }

  Node& loaded(int p) {
    Node& v = node_[p];
    if (v.loaded != round_ && v.loaded != kPadding) load(p);
    return v;
  }

  void join(int p, std::uint8_t parent) {
    node_[p].in_tree = round_;
    node_[p].parent = parent;
    tree_.push_back(p);
    queue_.push_back(p);
  }

  // Grows the tree and augments until no path is left. False when the budget ran out.
  bool search() {
    while (head_ < queue_.size()) {
      if (budget_ < 0) return false;
      const int v = queue_[head_];
      if (node_[v].in_tree != round_) {
        ++head_;
        continue;
      }
      int source_node = -1, dir = 0;
      for (int d = 0; d < 4 && source_node < 0; ++d) {
        const int q = v + offset_[d];
        Node& u = loaded(q);
        if (u.in_tree == round_ || !(u.res[d ^ 1] > 0.0f)) continue;
        if (u.excess > 0.0f) {
          source_node = q;
          dir = d ^ 1;
        } else {
          join(q, u.excess < 0.0f ? kRoot : std::uint8_t(d ^ 1));
        }
      }
      // The node stays at the head: after the augmentation it may have more neighbours to claim.
      if (source_node < 0) {
        ++head_;
        continue;
      }
      augment(source_node, dir);
      if (!adopt()) return false;
    }
    return true;
  }

  // Pushes the bottleneck along source -> s -> (tree path) -> sink, s outside the tree with excess.
  // The bottleneck is the exact minimum of the residuals, so the arcs it saturates end at exactly 0.
  void augment(int s, int dir) {
    float bottleneck = std::min(node_[s].excess, node_[s].res[dir]);
    int x = s + offset_[dir];
    for (std::uint8_t d = node_[x].parent; d != kRoot; d = node_[x].parent) {
      bottleneck = std::min(bottleneck, node_[x].res[d]);
      x += offset_[d];
    }
    bottleneck = std::min(bottleneck, -node_[x].excess);

    node_[s].excess -= bottleneck;
    push(s, dir, bottleneck);
    x = s + offset_[dir];
    for (std::uint8_t d = node_[x].parent; d != kRoot; d = node_[x].parent) {
      const int next = x + offset_[d];
      if (push(x, d, bottleneck)) make_orphan(x);
      x = next;
    }
    node_[x].excess += bottleneck;
    if (node_[x].excess >= 0.0f) make_orphan(x);
  }

  // Returns whether the arc is saturated.
  bool push(int x, int d, float amount) {
    node_[x].res[d] -= amount;
    node_[x + offset_[d]].res[d ^ 1] += amount;
    return node_[x].res[d] <= 0.0f;
  }

  void make_orphan(int p) {
    node_[p].parent = kOrphan;
    orphans_.push_back(p);
  }

  // True if p's parent chain still ends at a root.
  bool rooted(int p) {
    for (;;) {
      --budget_;
      const std::uint8_t d = node_[p].parent;
      if (d == kRoot) return true;
      if (d == kOrphan) return false;
      p += offset_[d];
    }
  }

  // Re-hangs each orphan below a tree neighbour it still has a residual arc into and whose path is
  // intact, else frees it, orphans its children and queues the tree neighbours that could grow into
  // it again. Returns false when the budget ran out.
  bool adopt() {
    for (std::size_t k = 0; k < orphans_.size(); ++k) {
      if (budget_ < 0) return false;
      const int p = orphans_[k];
      Node& v = node_[p];
      if (v.in_tree != round_ || v.parent != kOrphan) continue;
      int chosen = -1;
      for (int d = 0; d < 4 && chosen < 0; ++d) {
        const int q = p + offset_[d];
        if (node_[q].in_tree == round_ && v.res[d] > 0.0f && rooted(q)) chosen = d;
      }
      if (chosen >= 0) {
        v.parent = std::uint8_t(chosen);
        continue;
      }
      v.in_tree = -1;
      for (int d = 0; d < 4; ++d) {
        const int q = p + offset_[d];
        if (node_[q].in_tree != round_) continue;
        if (node_[q].parent == (d ^ 1)) make_orphan(q);
        if (v.res[d] > 0.0f) queue_.push_back(q);
      }
    }
    orphans_.clear();
    return true;
  }

  // The flow on an arc both of whose ends were read is the reverse residual at its far end; an arc
  // with an end left unread carried nothing new.
  void write_back() {
    for (const int p : loaded_) {
      const int c = p % cols_;
      if (c + 1 < cols_ && node_[p + 1].loaded == round_) flow_->set_right(p, node_[p + 1].res[1]);
      if (p + cols_ < n_ && node_[p + cols_].loaded == round_) flow_->set_down(p, node_[p + cols_].res[3]);
    }
  }

  int rows_, cols_, n_;
  std::vector<Node> nodes_;  // the grid's nodes with a padding row above and below
  Node* node_ = nullptr;
  int offset_[4] = {0, 0, 0, 0};
  std::vector<int> queue_, orphans_, tree_, loaded_;
  std::size_t head_ = 0;
  int round_ = 0;
  long budget_ = 0;
  const Capacities* capacities_ = nullptr;
  KeptFlows* flow_ = nullptr;
};

}  // namespace shadecut::maxflow_internal
