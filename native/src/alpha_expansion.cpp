#include <shadecut/alpha_expansion.hpp>

#include <shadecut/errors.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <memory>

namespace shadecut {

namespace {

// The terms of the expansion move of one label, read straight from the energy and the labelling
// (node on the sink side = pixel switches to alpha). Kolmogorov & Zabih: a pairwise term with values
// A = V(lp, lq), B = V(lp, alpha), C = V(alpha, lq), D = V(alpha, alpha) = 0 becomes
// A + (C - A) x_p + (D - C) x_q + (B + C - A - D) (1 - x_p) x_q, the last an arc p -> q; no arc
// runs q -> p. The full graph and the sparse repair below both read their capacities from here, in
// the same float operations, so that a flow kept from one is exact for the other.
class MoveTerms {
 public:
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

  void set_alpha(int alpha) { alpha_ = alpha; }
  int label(int p) const { return labelling_[std::size_t(p)]; }

  bool variable(int p) const {
    return variables_ ? variables_[p] != 0 : mask_[p] && label(p) != alpha_ && energy_.allowed(p, alpha_);
  }
  /// Answers variable() from `variables` (one flag per pixel, for the current alpha); null: computes it.
  void cache_variables(const std::uint8_t* variables) { variables_ = variables; }

  // Capacity of the arc from p to its right (q = p + 1) or lower (q = p + cols) neighbour, given that
  // edge's weight; zero unless both are variables.
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

  // Cost of switching p (at row r, column c) to alpha minus the cost of keeping its label, with the
  // pairwise terms as the construction distributes them; 0 where p takes no part.
  float switch_cost(int p, int r, int c) const {
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

// The flows kept from the last cut of every label: the net flow through the arc of each pixel to its
// right and to its lower neighbour (the arcs' reverse capacities are zero, so it is >= 0). The
// terminal flows follow from conservation. Together with the current capacities a label's flow
// reparametrizes its next move, which then only has to push what the changes since made possible.
// An arc has capacity only between two pixels where its label is allowed, so each flow is stored at
// its pixel's slot for the label (TiltEnergy::slot): with coarse to fine, a few labels a pixel
// instead of two planes a label.
class KeptFlows {
 public:
  struct State {
    bool started = false;          // the label has a flow (until then its slots hold zeros)
    bool maximal = false;          // a maximum flow whose cut was applied (or empty)
    std::size_t log_position = 0;  // changes logged before this were part of the graph it solved
  };

  explicit KeptFlows(const TiltEnergy& energy)
      : energy_(energy),
        right_(std::size_t(energy.slot_count()), 0.0f),
        down_(std::size_t(energy.slot_count()), 0.0f),
        states_(std::size_t(energy.labels())) {}

  /// The label the accessors below read and write.
  void set_alpha(int alpha) { alpha_ = alpha; }
  State& state() { return states_[std::size_t(alpha_)]; }

  float right(int p) const { return read(right_, p); }
  float down(int p) const { return read(down_, p); }
  void set_right(int p, float flow) { write(right_, p, flow); }
  void set_down(int p, float flow) { write(down_, p, flow); }

  /// Starts the current label's flow as a copy of `label`'s, where that one has started.
  void start_from(int label) {
    state().started = true;
    if (label < 0 || !states_[std::size_t(label)].started) return;
    for (int p = 0; p < energy_.rows() * energy_.cols(); ++p) {
      const std::int64_t from = energy_.slot(p, label), to = energy_.slot(p, alpha_);
      if (from < 0 || to < 0) continue;
      right_[std::size_t(to)] = right_[std::size_t(from)];
      down_[std::size_t(to)] = down_[std::size_t(from)];
    }
  }

 private:
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
};

// Finishes a maximum flow of the current move from a kept flow that was maximal for the same label
// before the pixels in `changed` took new labels. Any augmenting path must now start or pass where
// the graph changed: every other node that could reach the sink then was on the sink side of the
// applied cut, so it has switched to alpha and changed itself. So a sink tree grown from the new
// sink roots among the changed pixels and their neighbours, Boykov-Kolmogorov style but from the
// sink only (the source tree would span nearly every pixel), finds them all; each path starts at a
// node with source excess that the tree reaches. The tree holds exactly the nodes that can reach the
// sink when no path is left: the sink side of the minimum cut the full solver would report.
// A node is read from the energy and the flow when the search first meets it, so the work is
// proportional to the region the tree covers; past `budget` node visits it gives up and leaves a
// valid, not yet maximal flow.
class SparseRepair {
 public:
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

  // Returns false when the budget ran out. On success `sink_side` lists the tree. Either way the
  // flow pushed so far is written back.
  bool run(const MoveTerms& terms, KeptFlows& flow, const std::vector<int>& changed, long budget,
           std::vector<int>& sink_side) {
    ++round_;
    terms_ = &terms;
    flow_ = &flow;
    budget_ = budget;
    queue_.clear();
    head_ = 0;
    orphans_.clear();
    tree_.clear();
    loaded_.clear();
    // Capacities fell on the arcs of changed pixels: a flow above its arc's capacity is cut back to
    // it, which moves the difference into the terminal excess of both ends (a reparametrization).
    for (const int p : changed) {
      const int c = p % cols_;
      if (c + 1 < cols_) flow.set_right(p, std::min(flow.right(p), terms.right_arc(p)));
      if (c > 0) flow.set_right(p - 1, std::min(flow.right(p - 1), terms.right_arc(p - 1)));
      if (p + cols_ < n_) flow.set_down(p, std::min(flow.down(p), terms.down_arc(p)));
      if (p >= cols_) flow.set_down(p - cols_, std::min(flow.down(p - cols_), terms.down_arc(p - cols_)));
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
  // capacities are zero, so a reverse residual is the flow), and its excess from its unary term
  // less what its arcs carry away.
  void load(int p) {
    Node& v = node_[p];
    v.loaded = round_;
    loaded_.push_back(p);
    --budget_;
    const int r = p / cols_, c = p % cols_;
    const float right = c + 1 < cols_ ? flow_->right(p) : 0.0f, left = c > 0 ? flow_->right(p - 1) : 0.0f;
    const float down = r + 1 < rows_ ? flow_->down(p) : 0.0f, up = r > 0 ? flow_->down(p - cols_) : 0.0f;
    v.res[0] = c + 1 < cols_ ? terms_->right_arc(p) - right : 0.0f;
    v.res[1] = left;
    v.res[2] = r + 1 < rows_ ? terms_->down_arc(p) - down : 0.0f;
    v.res[3] = up;
    const float out = right + down - left - up;
    v.excess = terms_->switch_cost(p, r, c) - out;
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
  const MoveTerms* terms_ = nullptr;
  KeptFlows* flow_ = nullptr;
};

// Builds the s-t graph of the current move in `graph`, reparametrized by `flow` when given (cut
// back to the current capacities first), and marks its variables. Returns whether any pixel can
// switch. One sweep, on one core: the flows into a node are cut back by the time it is reached, and
// on a shared machine waiting for a second core at every sweep cost more than it saved.
bool build_move(MoveTerms& terms, int rows, int cols, KeptFlows* flow, GridGraph& graph,
                std::vector<std::uint8_t>& variable) {
  bool any = false;
  for (int p = 0; p < rows * cols; ++p) {
    variable[std::size_t(p)] = terms.variable(p);
    any = any || variable[std::size_t(p)];
  }
  if (!any) return false;
  terms.cache_variables(variable.data());
  struct Uncache {
    MoveTerms& terms;
    ~Uncache() { terms.cache_variables(nullptr); }
  } uncache{terms};
  for (int r = 0; r < rows; ++r) {
    for (int c = 0, p = r * cols; c < cols; ++c, ++p) {
      const bool v = variable[std::size_t(p)];
      const float right = v && c + 1 < cols ? terms.right_arc(p) : 0.0f;
      const float down = v && r + 1 < rows ? terms.down_arc(p) : 0.0f;
      float excess = v ? terms.switch_cost(p, r, c) : 0.0f;
      float flow_right = 0.0f, flow_down = 0.0f;
      if (flow) {
        flow_right = std::min(flow->right(p), right);
        flow_down = std::min(flow->down(p), down);
        flow->set_right(p, flow_right);
        flow->set_down(p, flow_down);
        float out = flow_right + flow_down;
        if (c > 0) out -= flow->right(p - 1);
        if (r > 0) out -= flow->down(p - cols);
        excess -= out;
      }
      graph.right_cap[std::size_t(p)] = right - flow_right;
      graph.right_rev_cap[std::size_t(p)] = flow_right;
      graph.down_cap[std::size_t(p)] = down - flow_down;
      graph.down_rev_cap[std::size_t(p)] = flow_down;
      graph.source_cap[std::size_t(p)] = std::max(0.0f, excess);
      graph.sink_cap[std::size_t(p)] = std::max(0.0f, -excess);
    }
  }
  return true;
}

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// Energy change of switching the pixels in `changed` to alpha, exactly in double precision.
double move_delta(const TiltEnergy& energy, const std::vector<int>& labelling, int alpha,
                  const std::vector<int>& changed, const std::vector<std::uint8_t>& is_changed) {
  const int rows = energy.rows(), cols = energy.cols();
  const Mask& mask = energy.mask();
  auto new_label = [&](int q) { return is_changed[std::size_t(q)] ? alpha : labelling[std::size_t(q)]; };
  double delta = 0.0;
  for (int p : changed) {
    delta += double(energy.data_cost(p, alpha)) - energy.data_cost(p, labelling[std::size_t(p)]);
    const int r = p / cols, c = p % cols;
    auto edge = [&](int q, float weight) {
      // An edge between two switching pixels is counted once, from its lower index.
      if (weight <= 0.0f || !mask.data()[q] || (is_changed[std::size_t(q)] && q < p)) return;
      delta += double(weight) * (energy.label_distance(alpha, new_label(q)) -
                                 energy.label_distance(labelling[std::size_t(p)], labelling[std::size_t(q)]));
    };
    if (c + 1 < cols) edge(p + 1, energy.weight_right(p));
    if (c > 0) edge(p - 1, energy.weight_right(p - 1));
    if (r + 1 < rows) edge(p + cols, energy.weight_down(p));
    if (r > 0) edge(p - cols, energy.weight_down(p - cols));
  }
  return delta;
}

}  // namespace

AlphaExpansionStats alpha_expansion(const TiltEnergy& energy, std::vector<int>& labelling, MaxFlowSolver& solver,
                                    int max_cycles, double tolerance, const MoveCallback& on_move) {
  if (max_cycles < 1) throw InvalidArgument("shadecut: max_cycles must be at least 1");
  if (!(tolerance >= 0.0) || !std::isfinite(tolerance)) throw InvalidArgument("shadecut: tolerance must be finite and >= 0");
  const int n = energy.rows() * energy.cols(), labels = energy.labels();
  if (labelling.size() != std::size_t(n)) throw InvalidArgument("shadecut: the labelling has the wrong size");
  for (int p = 0; p < n; ++p)
    if (energy.mask().data()[p] && (labelling[std::size_t(p)] < 0 || labelling[std::size_t(p)] >= labels ||
                                    !energy.allowed(p, labelling[std::size_t(p)])))
      throw InvalidArgument("shadecut: the initial labelling uses a prohibited label");

  AlphaExpansionStats stats;
  double current = energy.energy(labelling);
  stats.energy_per_cycle.push_back(current);
  GridGraph graph;
  graph.reset(energy.rows(), energy.cols());
  const std::size_t pixels = std::size_t(n);
  std::vector<std::uint8_t> variable(pixels), sink_side, is_changed(pixels, 0);
  std::vector<int> changed, touched;
  MoveTerms terms(energy, labelling);

  // Every pixel that took a new label, in order; a label's kept flow knows how much of it it saw.
  std::vector<int> change_log;
  const bool warm = solver.leaves_residuals();
  std::unique_ptr<KeptFlows> flows = warm ? std::make_unique<KeptFlows>(energy) : nullptr;
  std::unique_ptr<SparseRepair> repair;
  std::vector<int> seen(pixels, -1);
  int seen_round = 0;
  // Past these a repair would cover most of the grid anyway and the full solver does it faster
  // (chosen by instruction counts on the benchmark sphere at 384 x 384: a repair stopped early is
  // work lost, so the budget is generous).
  const std::size_t repair_limit = pixels / 2;
  const long repair_budget = 8 * long(n);

  // An expansion of a label that nothing has changed since its last expansion would find the same
  // cut, and so would one whose own move was the last change (expansion moves are idempotent): both
  // are skipped. `step` counts label visits; -1 = never.
  std::vector<long> solved_at(std::size_t(labels), -1);
  long step = 0, last_change = -1;
  for (int cycle = 0; cycle < max_cycles; ++cycle) {
    bool improved = false;
    for (int alpha = 0; alpha < labels; ++alpha, ++step) {
      const bool nothing_new = solved_at[std::size_t(alpha)] >= 0 && solved_at[std::size_t(alpha)] >= last_change;
      terms.set_alpha(alpha);
      if (flows) flows->set_alpha(alpha);
      KeptFlows::State* flow = flows && flows->state().started ? &flows->state() : nullptr;
      bool solved = false;
      // A label's first move starts from a zero flow, which is maximal for the empty graph before
      // every variable pixel "changed"; where those are few (coarse to fine keeps most labels out of
      // most pixels) the search around them solves it without a full graph.
      const bool first_visit = warm && !flow;
      if (!nothing_new && first_visit) {
        touched.clear();
        for (int p = 0; p < n; ++p)
          if (terms.variable(p)) touched.push_back(p);
        if (touched.size() <= repair_limit) {
          flows->start_from(-1);
          flow = &flows->state();
          flow->maximal = true;
          flow->log_position = change_log.size();
        }
      } else if (!nothing_new && flow && flow->maximal && change_log.size() - flow->log_position <= repair_limit) {
        ++seen_round;
        touched.clear();
        for (std::size_t k = flow->log_position; k < change_log.size(); ++k) {
          const int p = change_log[k];
          if (seen[std::size_t(p)] != seen_round) seen[std::size_t(p)] = seen_round, touched.push_back(p);
        }
      }
      if (!nothing_new && flow && flow->maximal && (first_visit || change_log.size() - flow->log_position <= repair_limit)) {
        if (!repair) repair = std::make_unique<SparseRepair>(energy.rows(), energy.cols());
        const auto start = std::chrono::steady_clock::now();
        solved = repair->run(terms, *flows, touched, repair_budget, changed);
        stats.maxflow_seconds += seconds_since(start);
        stats.repaired_moves += solved;
      }
      if (!nothing_new && !solved) {
        if (warm && !flow) {
          // The previous label's move has nearly the same shape; its flow, cut back to this move's
          // capacities, leaves less to push than none (7% fewer instructions at 384 x 384).
          flows->start_from(alpha - 1);
          flow = &flows->state();
        }
        if (build_move(terms, energy.rows(), energy.cols(), flow ? flows.get() : nullptr, graph, variable)) {
          const auto start = std::chrono::steady_clock::now();
          solver.solve(graph, sink_side);
          stats.maxflow_seconds += seconds_since(start);
          changed.clear();
          for (int p = 0; p < n; ++p)
            if (variable[std::size_t(p)] && sink_side[std::size_t(p)]) changed.push_back(p);
          if (flow) {
            // The reverse capacities were the kept flow and started at zero: now they hold the flow.
            for (int p = 0; p < n; ++p) {
              flows->set_right(p, graph.right_rev_cap[std::size_t(p)]);
              flows->set_down(p, graph.down_rev_cap[std::size_t(p)]);
            }
          }
          solved = true;
        } else if (flow) {
          // No pixel can switch, and the kept flow was not cut back to that: the next move of this
          // label starts over from the full graph.
          flow->maximal = false;
        }
      }
      if (solved) {
        solved_at[std::size_t(alpha)] = step;
        ++stats.moves;
        for (int p : changed) is_changed[std::size_t(p)] = 1;
        const double delta = move_delta(energy, labelling, alpha, changed, is_changed);
        for (int p : changed) is_changed[std::size_t(p)] = 0;
        // Float capacities can make a cut that is optimal up to rounding raise the energy by a hair;
        // such a move is refused, which keeps the energy monotone.
        const bool accept = !changed.empty() && delta < -1e-9 * std::max(1.0, std::abs(current));
        if (flow) {
          flow->log_position = change_log.size();
          // A refused cut leaves sink-side pixels unchanged that the repair would not look at.
          flow->maximal = accept || changed.empty();
        }
        if (accept) {
          for (int p : changed) labelling[std::size_t(p)] = alpha;
          change_log.insert(change_log.end(), changed.begin(), changed.end());
          current += delta;
          improved = true;
          ++stats.accepted_moves;
          last_change = step;
        }
      }
      if (on_move && !on_move((cycle + double(alpha + 1) / labels) / max_cycles)) throw Cancelled();
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
