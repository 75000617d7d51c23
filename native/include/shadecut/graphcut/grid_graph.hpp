// A capacitated 4-connected grid graph: the s-t graph of one alpha-expansion move.
#pragma once

#include <cstdint>
#include <vector>

namespace shadecut {

/// Capacities of an s-t graph whose non-terminal nodes are the pixels of a rows x cols grid.
///
/// Node (r, c) has index r * cols + c. Every array has rows * cols entries, all >= 0:
///   source_cap[i]  capacity of source -> i (paid when i ends on the sink side),
///   sink_cap[i]    capacity of i -> sink   (paid when i ends on the source side),
///   right_cap[i]   capacity of i -> (r, c+1), right_rev_cap[i] of (r, c+1) -> i  (unused when c = cols-1),
///   down_cap[i]    capacity of i -> (r+1, c), down_rev_cap[i]  of (r+1, c) -> i  (unused when r = rows-1).
/// A node whose capacities are all zero is isolated: solvers skip it cheaply.
struct GridGraph {
  int rows = 0;
  int cols = 0;
  std::vector<float> source_cap, sink_cap;
  std::vector<float> right_cap, right_rev_cap;
  std::vector<float> down_cap, down_rev_cap;

  /// Resizes to rows x cols and sets every capacity to zero.
  void reset(int rows_, int cols_) {
    rows = rows_;
    cols = cols_;
    const std::size_t n = std::size_t(rows_) * std::size_t(cols_);
    for (auto* v : {&source_cap, &sink_cap, &right_cap, &right_rev_cap, &down_cap, &down_rev_cap}) v->assign(n, 0.0f);
  }
  int size() const { return rows * cols; }
};

}  // namespace shadecut
