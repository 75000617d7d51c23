// Boykov-Kolmogorov maximum flow (Boykov & Kolmogorov, PAMI 2004) specialized to the 4-connected grid.
//
// Two search trees grow from the terminals: S (nodes reached from the source through non-saturated
// arcs) and T (nodes reaching the sink). Growth extends them until an arc joins S to T; augmentation
// pushes the bottleneck along that path, which cuts saturated tree arcs and leaves orphans; adoption
// re-attaches every orphan to its tree or frees it. At the end S is closed under non-saturated arcs
// leaving it and T under non-saturated arcs entering it, so both give minimum cuts; nodes in T are
// reported as the sink side, which puts free (e.g. isolated) nodes on the source side.
//
// Grid specialization: a node's neighbours are implicit in its index (offsets +1, -1, +cols, -cols),
// and a tree parent is stored as the direction towards it, so no adjacency lists exist at all.
//
// Where the data term is strong, nearly all of the flow goes along paths of one or two arcs between
// terminal-connected nodes. initialize() pushes those while it writes the nodes, and then activates
// only the nodes that can still grow, which leaves the tree search a small fraction of the graph to
// visit, mostly while it is still in cache.
//
// With the tuned weak data term it is the other way round: terminal arcs are small next to the arcs
// between pixels, and on the expansion moves of a real reconstruction (Mozart, 256 x 256) four fifths
// of the flow travel paths of about 28 arcs, in some 25,000 augmentations per move, most of which
// drain one small terminal arc and free a part of a tree that must then grow again. augment() is
// therefore written for long paths, and lets each walk carry the terminal flow of the roots next to
// the path's ends too (see augment()).
#include "graphcut/maxflow_impl.hpp"

#include <shadecut/support/errors.hpp>

#include <algorithm>
#include <cfloat>
#include <climits>
#include <cmath>
#include <cstdint>
#include <vector>

namespace shadecut::maxflow_internal {
namespace {

// Directions index a node's outgoing arcs; d ^ 1 is the opposite direction.
constexpr int kRight = 0;
constexpr int kLeft = 1;
constexpr int kDown = 2;
constexpr int kUp = 3;

// Parent codes 0..3 are directions (towards the parent); these mark the other states.
constexpr std::uint8_t kTerminalParent = 4;
constexpr std::uint8_t kOrphan = 5;
constexpr std::uint8_t kNoParent = 6;

constexpr std::uint8_t kFree = 0;
constexpr std::uint8_t kSourceTree = 1;
constexpr std::uint8_t kSinkTree = 2;

// Everything the search touches at one node, packed into half a cache line so that visiting a
// neighbour costs one memory access.
struct Node {
  float cap[4];    // residual capacity of the arc to the right / left / down / up neighbour
  float terminal;  // > 0: residual source -> node; < 0: minus the residual node -> sink
  std::int32_t timestamp;
  std::int32_t dist;  // distance to the terminal along the tree, valid as of `timestamp`
  std::uint8_t parent;
  std::uint8_t tree;
};
static_assert(sizeof(Node) == 32, "Node should fill half a cache line");

// 1 unless x is finite and >= 0. An int rather than a bool, so that GCC vectorizes the check.
int invalid_capacity(float x) { return int(x < 0.0f) | int(!(x <= FLT_MAX)); }

// Active-list links: kInactive marks a node that is not queued, kNone ends the list.
constexpr std::int32_t kNone = -1;
constexpr std::int32_t kInactive = -2;

class GridMaxFlow final : public MaxFlowSolver {
 public:
  double solve(GridGraph& graph, std::vector<std::uint8_t>& sink_side) override {
    check_shape(graph);
    const int n = graph.size();
    sink_side.resize(std::size_t(n));
    if (n == 0) return 0.0;

    // Written as nodes settle and whenever one joins or leaves the sink tree afterwards, which
    // spares a last pass over all nodes.
    sink_side_ = sink_side.data();
    double flow = initialize(graph);
    for (;;) {
      int from = 0;
      int dir = 0;
      if (!grow(from, dir)) break;
      flow += augment(from, dir);
      adopt_orphans();
    }
    write_residuals(graph);
    return flow;
  }

  bool leaves_residuals() const override { return true; }

 private:
  // Copies the capacities into the node array and pushes the flow that needs no search: along
  // source -> i -> sink, and along source -> i -> j -> sink for neighbours i, j. In an expansion move
  // most augmenting paths are of these two kinds, and pushing them during the sweep that writes the
  // nodes, while they are in cache, leaves the tree search only the few longer paths. Then roots the
  // trees at the nodes that keep a terminal arc. Returns the flow pushed.
  double initialize(const GridGraph& graph) {
    const int rows = graph.rows;
    const int cols = graph.cols;
    const int n = rows * cols;
    // A padding row above and below keeps the up / down neighbours of border nodes inside the array;
    // left / right neighbours of border nodes wrap to the adjacent row, which is harmless because the
    // arcs between them are zero both ways.
    nodes_.resize(std::size_t(n) + 2 * std::size_t(cols));
    next_.assign(std::size_t(n), kInactive);
    node_ = nodes_.data() + cols;
    offset_[kRight] = 1;
    offset_[kLeft] = -1;
    offset_[kDown] = cols;
    offset_[kUp] = -cols;
    const Node padding{{0.0f, 0.0f, 0.0f, 0.0f}, 0.0f, 0, 0, kNoParent, kFree};
    std::fill(nodes_.begin(), nodes_.begin() + cols, padding);
    std::fill(nodes_.end() - cols, nodes_.end(), padding);
    first_active_ = kNone;
    last_active_ = kNone;
    orphans_.clear();
    time_ = 0;

    const float* source = graph.source_cap.data();
    const float* sink = graph.sink_cap.data();
    const float* right = graph.right_cap.data();
    const float* right_rev = graph.right_rev_cap.data();
    const float* down = graph.down_cap.data();
    const float* down_rev = graph.down_rev_cap.data();
    zero_row_.assign(std::size_t(cols), 0.0f);
    double flow = 0.0;
    for (int r = 0; r < rows; ++r) {
      const int row = r * cols;
      int invalid = 0;
      for (int i = row; i < row + cols; ++i) {
        invalid |= invalid_capacity(source[i]) | invalid_capacity(sink[i]) | invalid_capacity(right[i]) |
                   invalid_capacity(right_rev[i]) | invalid_capacity(down[i]) | invalid_capacity(down_rev[i]);
      }
      if (invalid) throw InvalidArgument(bad_capacity_message);
      flow += sum_of_min(source + row, sink + row, cols);
      // Arcs leaving the grid through the top or bottom read zeros.
      const float* up = r > 0 ? down_rev + row - cols : zero_row_.data();
      const float* below = r + 1 < rows ? down + row : zero_row_.data();
      float left = 0.0f;
      for (int c = 0; c < cols; ++c) {
        const int i = row + c;
        Node& v = node_[i];
        v.cap[kRight] = c + 1 < cols ? right[i] : 0.0f;
        v.cap[kLeft] = left;
        v.cap[kDown] = below[c];
        v.cap[kUp] = up[c];
        left = right_rev[i];
        v.terminal = source[i] - sink[i];
        v.timestamp = 0;
        v.dist = 1;
        // Each pair of neighbours is handled once, when the later of the two is written; a path
        // needs terminal arcs of opposite signs. Across the left border the arcs are zero, and above
        // the top the padding has no terminal arc. (A product that underflows only skips a push.)
        if (v.terminal * node_[i - 1].terminal < 0.0f) flow += push_two_arc_path(i, kLeft);
        if (v.terminal * node_[i - cols].terminal < 0.0f) flow += push_two_arc_path(i, kUp);
        set_root_or_free(v);
      }
      if (r >= 2) seed_row(r - 2, cols);
    }
    for (int r = std::max(0, rows - 2); r < rows; ++r) seed_row(r, cols);
    return flow;
  }

  // The flow of the paths source -> i -> sink: the smaller terminal capacity of every node. Partial
  // sums keep the double additions from waiting on each other.
  static double sum_of_min(const float* source, const float* sink, int count) {
    double partial[4] = {0.0, 0.0, 0.0, 0.0};
    int k = 0;
    for (; k + 4 <= count; k += 4) {
      for (int j = 0; j < 4; ++j) partial[j] += std::min(source[k + j], sink[k + j]);
    }
    for (; k < count; ++k) partial[0] += std::min(source[k], sink[k]);
    return (partial[0] + partial[1]) + (partial[2] + partial[3]);
  }

  // Pushes as much as possible along source -> i -> j -> sink or source -> j -> i -> sink, where
  // j = i + offset_[dir] and the terminal arcs of i and j have opposite signs. Returns the amount.
  float push_two_arc_path(int i, int dir) {
    Node& v = node_[i];
    Node& u = node_[i + offset_[dir]];
    // A negative amount flows from j to i.
    const float amount = v.terminal > 0.0f ? std::min({v.terminal, v.cap[dir], -u.terminal})
                                           : -std::min({-v.terminal, u.cap[dir ^ 1], u.terminal});
    v.cap[dir] -= amount;
    u.cap[dir ^ 1] += amount;
    v.terminal -= amount;
    u.terminal += amount;
    set_root_or_free(u);
    return std::abs(amount);
  }

  static void set_root_or_free(Node& v) {
    const bool source_root = v.terminal > 0.0f;
    const bool sink_root = v.terminal < 0.0f;
    v.tree = source_root ? kSourceTree : sink_root ? kSinkTree : kFree;
    v.parent = source_root | sink_root ? kTerminalParent : kNoParent;
  }

  // Prepares row r for the tree search once rows r-1..r+1 are final (no later push changes them),
  // while they are still in cache. A free node with a residual arc into the sink tree joins it right
  // away, as growth would have made it do. Only what the search must start from is activated: every
  // source root, and every node that just joined the sink tree next to a free node that has a
  // residual arc into it. Sink roots stay passive, which spares scanning nearly all nodes. This keeps
  // the invariant that makes the trees closed when no node is active any more: every tree node with
  // a residual arc towards a free node (in its tree's direction), and every S node with a residual
  // arc into T, is active. The search keeps it too, as long as a node that becomes free wakes up its
  // neighbours in both trees; see adopt_orphans().
  void seed_row(int r, int cols) {
    for (int i = r * cols; i < (r + 1) * cols; ++i) {
      Node& v = node_[i];
      sink_side_[i] = v.tree == kSinkTree;
      if (v.tree == kSourceTree) {
        activate(i);
        continue;
      }
      if (v.tree != kFree) continue;
      int parent = -1;
      for (int d = 0; d < 4; ++d) {
        const Node& u = node_[i + offset_[d]];
        if (v.cap[d] > 0.0f && u.tree == kSinkTree && (parent < 0 || u.dist < node_[i + offset_[parent]].dist)) {
          parent = d;
        }
      }
      if (parent < 0) continue;
      sink_side_[i] = 1;
      v.tree = kSinkTree;
      v.parent = std::uint8_t(parent);
      v.dist = node_[i + offset_[parent]].dist + 1;
      for (int d = 0; d < 4; ++d) {
        const Node& u = node_[i + offset_[d]];
        if (u.tree == kFree && u.cap[d ^ 1] > 0.0f) {
          activate(i);
          break;
        }
      }
    }
  }

  void activate(int i) {
    if (next_[std::size_t(i)] != kInactive) return;
    next_[std::size_t(i)] = kNone;
    if (last_active_ == kNone) {
      first_active_ = i;
    } else {
      next_[std::size_t(last_active_)] = i;
    }
    last_active_ = i;
  }

  void pop_active() {
    const int i = first_active_;
    first_active_ = next_[std::size_t(i)];
    if (first_active_ == kNone) last_active_ = kNone;
    next_[std::size_t(i)] = kInactive;
  }

  // Grows the trees from the active nodes until a non-saturated arc leads from S to T. On success the
  // arc is from -> from + offset_[dir]. The node being scanned stays at the head of the list, because
  // after the augmentation it may have further free neighbours to claim.
  bool grow(int& from, int& dir) {
    while (first_active_ != kNone) {
      const int p = first_active_;
      Node& v = node_[p];
      if (v.tree == kSourceTree) {
        for (int d = 0; d < 4; ++d) {
          if (!(v.cap[d] > 0.0f)) continue;
          const int q = p + offset_[d];
          Node& u = node_[q];
          if (u.tree == kSinkTree) {
            from = p;
            dir = d;
            return true;
          }
          claim_or_shorten(u, q, v, d ^ 1);
        }
      } else if (v.tree == kSinkTree) {
        for (int d = 0; d < 4; ++d) {
          const int q = p + offset_[d];
          Node& u = node_[q];
          if (!(u.cap[d ^ 1] > 0.0f)) continue;
          if (u.tree == kSourceTree) {
            from = q;
            dir = d ^ 1;
            return true;
          }
          claim_or_shorten(u, q, v, d ^ 1);
        }
      }
      pop_active();
    }
    return false;
  }

  // u (index q) is joined to v's tree through a non-saturated arc; to_parent is the direction from u
  // to v. A free u joins the tree; a u already in it is re-hung below v when that shortens its path to
  // the terminal (BK's distance heuristic). The timestamp condition guarantees v is not u's
  // descendant: along any tree path timestamps never decrease towards the root, and where they are
  // equal distances strictly decrease, so a descendant cannot look closer than u.
  void claim_or_shorten(Node& u, int q, const Node& v, int to_parent) {
    if (u.tree == kFree) {
      sink_side_[q] = v.tree == kSinkTree;
      u.tree = v.tree;
      u.parent = std::uint8_t(to_parent);
      u.timestamp = v.timestamp;
      u.dist = v.dist + 1;
      activate(q);
    } else if (u.dist > v.dist + 1 && u.tree == v.tree && u.timestamp <= v.timestamp) {
      u.parent = std::uint8_t(to_parent);
      u.timestamp = v.timestamp;
      u.dist = v.dist + 1;
    }
  }

  // Pushes the bottleneck capacity along source -> ... -> from -> to -> ... -> sink and queues the
  // nodes whose tree arc it saturates as orphans. Returns the amount pushed.
  //
  // Floats: the bottleneck is the exact minimum of the residuals on the path, so subtracting it leaves
  // every residual >= 0 and the minimal one exactly 0. Each augmentation therefore saturates at least
  // one arc, and a residual is saturated exactly when it is <= 0.
  //
  // Gathering terminal flow into a root from a neighbouring root (source -> u -> r, or the mirror
  // image at the sink) changes no cut's residual capacity, since whatever leaves one terminal arc
  // across a cut comes back on the arc between u and r. So capacity(cut) = flow + residual(cut) still
  // holds for every cut, and the final trees, with no residual arc between them, still give a minimum
  // cut of the returned value, even if a root keeps some of what it gathered (rounding).
  double augment(int from, int dir) {
    // The tree walks chase parent links, one dependent load per arc; remembering the path's nodes
    // lets the update pass run without that chain.
    const int to = from + offset_[dir];
    source_path_.clear();
    sink_path_.clear();
    float bottleneck = node_[from].cap[dir];
    int x = from;
    for (int d = node_[x].parent; d != kTerminalParent; d = node_[x].parent) {
      source_path_.push_back(x);
      x += offset_[d];
      bottleneck = std::min(bottleneck, node_[x].cap[d ^ 1]);
    }
    const int source_root = x;
    x = to;
    for (int d = node_[x].parent; d != kTerminalParent; d = node_[x].parent) {
      sink_path_.push_back(x);
      bottleneck = std::min(bottleneck, node_[x].cap[d]);
      x += offset_[d];
    }
    const int sink_root = x;
    // With a weak data term the terminal arcs are far smaller than the arcs between pixels, so the
    // path would drain one root and the next augmentation would walk nearly the same long path for
    // a neighbouring root. Routing the neighbouring roots' terminal flow through the root first lets
    // one walk carry it all.
    const float source_excess = node_[source_root].terminal;
    const float sink_deficit = -node_[sink_root].terminal;
    if (source_excess < std::min(bottleneck, sink_deficit)) {
      gather_into_source_root(source_root, std::min(bottleneck, sink_deficit) - source_excess);
    }
    if (sink_deficit < std::min(bottleneck, node_[source_root].terminal)) {
      gather_into_sink_root(sink_root, std::min(bottleneck, node_[source_root].terminal) - sink_deficit);
    }
    bottleneck = std::min({bottleneck, node_[source_root].terminal, -node_[sink_root].terminal});

    node_[from].cap[dir] -= bottleneck;
    node_[to].cap[dir ^ 1] += bottleneck;
    for (const int child : source_path_) {
      const int d = node_[child].parent;
      node_[child].cap[d] += bottleneck;
      float& arc = node_[child + offset_[d]].cap[d ^ 1];
      arc -= bottleneck;
      if (arc <= 0.0f) make_orphan(child);
    }
    node_[source_root].terminal -= bottleneck;
    if (node_[source_root].terminal <= 0.0f) make_orphan(source_root);
    for (const int child : sink_path_) {
      const int d = node_[child].parent;
      float& arc = node_[child].cap[d];
      arc -= bottleneck;
      node_[child + offset_[d]].cap[d ^ 1] += bottleneck;
      if (arc <= 0.0f) make_orphan(child);
    }
    node_[sink_root].terminal += bottleneck;
    if (node_[sink_root].terminal >= 0.0f) make_orphan(sink_root);
    return bottleneck;
  }

  // Pushes up to `wanted` from source roots next to root r along source -> neighbour -> r, which
  // adds it to r's residual source arc. A neighbour drained to zero loses its root status.
  void gather_into_source_root(int r, float wanted) {
    Node& v = node_[r];
    for (int d = 0; d < 4 && wanted > 0.0f; ++d) {
      const int q = r + offset_[d];
      Node& u = node_[q];
      if (u.tree != kSourceTree || u.parent != kTerminalParent || !(u.cap[d ^ 1] > 0.0f)) continue;
      const float amount = std::min({wanted, u.terminal, u.cap[d ^ 1]});
      u.cap[d ^ 1] -= amount;
      v.cap[d] += amount;
      u.terminal -= amount;
      v.terminal += amount;
      wanted -= amount;
      if (u.terminal <= 0.0f) make_orphan(q);
    }
  }

  // The mirror image: pushes up to `wanted` along r -> neighbour -> sink for sink roots next to r.
  void gather_into_sink_root(int r, float wanted) {
    Node& v = node_[r];
    for (int d = 0; d < 4 && wanted > 0.0f; ++d) {
      const int q = r + offset_[d];
      Node& u = node_[q];
      if (u.tree != kSinkTree || u.parent != kTerminalParent || !(v.cap[d] > 0.0f)) continue;
      const float amount = std::min({wanted, -u.terminal, v.cap[d]});
      v.cap[d] -= amount;
      u.cap[d ^ 1] += amount;
      u.terminal += amount;
      v.terminal -= amount;
      wanted -= amount;
      if (u.terminal >= 0.0f) make_orphan(q);
    }
  }

  void make_orphan(int i) {
    node_[i].parent = kOrphan;
    orphans_.push_back(i);
  }

  void write_residuals(GridGraph& graph) const {
    const int cols = graph.cols;
    const int n = graph.size();
    for (int i = 0; i < n; ++i) {
      const Node& v = node_[i];
      graph.source_cap[std::size_t(i)] = std::max(0.0f, v.terminal);
      graph.sink_cap[std::size_t(i)] = std::max(0.0f, -v.terminal);
      // The right neighbour of a node in the last column is the first of the next row, whose left
      // arc is zero; below the last row lies the padding.
      graph.right_cap[std::size_t(i)] = v.cap[kRight];
      graph.right_rev_cap[std::size_t(i)] = node_[i + 1].cap[kLeft];
      graph.down_cap[std::size_t(i)] = v.cap[kDown];
      graph.down_rev_cap[std::size_t(i)] = node_[i + cols].cap[kUp];
    }
  }

  // Re-attaches each orphan to a neighbour of its tree whose own path still reaches the terminal,
  // preferring the closest; an orphan with none becomes free and orphans its children.
  void adopt_orphans() {
    ++time_;
    for (std::size_t k = 0; k < orphans_.size(); ++k) {
      const int p = orphans_[k];
      Node& v = node_[p];
      const bool source_tree = v.tree == kSourceTree;
      int best_dir = -1;
      int best_dist = INT_MAX;
      for (int d = 0; d < 4; ++d) {
        const int q = p + offset_[d];
        Node& u = node_[q];
        if (u.tree != v.tree) continue;
        if (!((source_tree ? u.cap[d ^ 1] : v.cap[d]) > 0.0f)) continue;
        const int dist = distance_to_terminal(q);
        if (dist < best_dist) {
          best_dist = dist;
          best_dir = d;
          // A terminal-connected neighbour cannot be beaten.
          if (dist == 1) break;
        }
      }
      if (best_dir >= 0) {
        v.parent = std::uint8_t(best_dir);
        v.timestamp = time_;
        v.dist = best_dist + 1;
        continue;
      }
      // v becomes free: its children are orphaned, and every tree neighbour that could grow into v
      // is activated. The paper activates only v's own tree; the other tree's neighbours are needed
      // too because initialize() leaves most roots passive.
      for (int d = 0; d < 4; ++d) {
        const int q = p + offset_[d];
        Node& u = node_[q];
        if (u.tree == kFree) continue;
        if ((u.tree == kSourceTree ? u.cap[d ^ 1] : v.cap[d]) > 0.0f) activate(q);
        if (u.parent == (d ^ 1)) make_orphan(q);
      }
      sink_side_[p] = 0;
      v.tree = kFree;
      v.parent = kNoParent;
    }
    orphans_.clear();
  }

  // Length of q's tree path to the terminal, or INT_MAX if it runs into an orphan. Nodes checked
  // earlier in this adoption round carry the current timestamp and a known distance, which cuts the
  // walk short; the walk stamps the nodes it verifies so later walks stop at them.
  int distance_to_terminal(int q) {
    int dist = 0;
    int x = q;
    for (;;) {
      Node& w = node_[x];
      if (w.timestamp == time_) {
        dist += w.dist;
        break;
      }
      if (w.parent == kOrphan) return INT_MAX;
      ++dist;
      if (w.parent == kTerminalParent) {
        w.timestamp = time_;
        w.dist = 1;
        break;
      }
      x += offset_[w.parent];
    }
    int remaining = dist;
    for (x = q; node_[x].timestamp != time_; x += offset_[node_[x].parent]) {
      node_[x].timestamp = time_;
      node_[x].dist = remaining--;
    }
    return dist;
  }

  std::uint8_t* sink_side_ = nullptr;  // the caller's output, during solve()
  std::vector<Node> nodes_;           // grid nodes plus a padding row above and below
  Node* node_ = nullptr;              // node 0 of the grid, inside nodes_
  std::vector<std::int32_t> next_;    // intrusive FIFO of active nodes
  std::vector<float> zero_row_;       // capacities of the arcs leaving the grid at the top and bottom
  std::int32_t first_active_ = kNone;
  std::int32_t last_active_ = kNone;
  std::vector<std::int32_t> source_path_, sink_path_;  // the path of the current augmentation
  std::vector<std::int32_t> orphans_;  // processed in FIFO order; adoption appends to it
  std::int32_t time_ = 0;
  int offset_[4] = {0, 0, 0, 0};
};

}  // namespace

std::unique_ptr<MaxFlowSolver> make_grid_solver() { return std::make_unique<GridMaxFlow>(); }

}  // namespace shadecut::maxflow_internal
