#include "integrate/grid_poisson.hpp"

#include "integrate/fourier.hpp"
#include "support/mask_bounds.hpp"
#include "support/parallel.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <optional>
#include <stdexcept>
#include <utility>

namespace shadecut::detail {

namespace {

// Levels smaller than this run on one thread: their work is shorter than what waking the other
// threads costs, and on a busy machine a thread waiting at a barrier for one that lost its core
// costs far more (with every level parallel, 2 threads took 65 times as long as 1 at 512 x 512 with
// one other busy process). Rows are handed out in small chunks for the same reason: a thread that
// lost its core holds up the others by one chunk, not by half the grid.
constexpr std::size_t kParallelCells = std::size_t(1) << 18;
constexpr int kRowsPerChunk = 16;

// body(row) for every row of a level of `cells` cells: in parallel on large levels only.
template <class Body>
void for_each_row(int rows, std::size_t cells, Body&& body) {
  parallel_for(rows, kRowsPerChunk, cells >= kParallelCells ? 0 : 1, body);
}

// A per-cell array with a row and a cell of zeros before and after it, so that the four neighbours
// of any cell can be read without bounds checks: the weights toward cells off the grid are 0.
template <class T>
class Field {
 public:
  Field() = default;
  Field(std::size_t size, int cols) : pad_(std::size_t(cols) + 1), values_(size + 2 * pad_, T(0)) {}
  T* data() { return values_.data() + pad_; }
  const T* data() const { return values_.data() + pad_; }
  void fill(T value) { std::fill(values_.begin(), values_.end(), value); }

 private:
  std::size_t pad_ = 0;
  std::vector<T> values_;
};

// One level of the hierarchy: a graph Laplacian with weighted 4-neighbour edges on a rows x cols grid.
// The V-cycle only preconditions, so its levels are held in float: its sweeps move half the bytes,
// and the conjugate gradients, in double, still reach the tolerance in as many iterations
// (docs/benchmarks.md, "Integration").
struct Level {
  int rows = 0, cols = 0;
  Field<float> right, down;        // weight of the edge to (r, c + 1), to (r + 1, c); 0 where there is none
  Field<float> anchor;             // weight of a cell's pull toward a value (Anchors); 0 without
  Field<float> diagonal, inverse;  // sum of a cell's weights, its inverse (0 for a cell with none)
  Field<float> solution, rhs;
  // Per row, the columns [first, end) that hold every cell with a weight: the others stay 0 in every
  // field, so the sweeps skip them (an object's frame is mostly background).
  std::vector<int> first, end;

  Level(int rows_, int cols_) : rows(rows_), cols(cols_) {
    for (Field<float>* field : {&right, &down, &anchor, &diagonal, &inverse, &solution, &rhs}) *field = Field<float>(size(), cols);
  }
  std::size_t size() const { return std::size_t(rows) * std::size_t(cols); }

  void set_diagonal() {
    const float* r = right.data();
    const float* d = down.data();
    const float* a = anchor.data();
    float* diag = diagonal.data();
    float* inv = inverse.data();
    first.assign(std::size_t(rows), cols);
    end.assign(std::size_t(rows), 0);
    for (int row = 0; row < rows; ++row) {
      for (int c = 0; c < cols; ++c) {
        const std::size_t i = std::size_t(row) * std::size_t(cols) + std::size_t(c);
        diag[i] = r[i] + r[i - 1] + d[i] + d[i - std::size_t(cols)] + a[i];
        inv[i] = diag[i] > 0.0f ? 1.0f / diag[i] : 0.0f;
        if (diag[i] > 0.0f) {
          first[std::size_t(row)] = std::min(first[std::size_t(row)], c);
          end[std::size_t(row)] = c + 1;
        }
      }
    }
  }
  // The flat indices [begin, stop) of row r's cells with a weight (empty when it has none).
  std::pair<std::ptrdiff_t, std::ptrdiff_t> span(int r) const {
    const std::ptrdiff_t start = std::ptrdiff_t(r) * cols;
    return {start + first[std::size_t(r)], start + std::max(end[std::size_t(r)], first[std::size_t(r)])};
  }
};

Level finest_level(const Mask& mask, const Anchors* anchors) {
  Level level(int(mask.rows()), int(mask.cols()));
  const bool* inside = mask.data();
  float* right = level.right.data();
  float* down = level.down.data();
  float* anchor = level.anchor.data();
  const int rows = level.rows, cols = level.cols;
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) {
      const std::size_t i = std::size_t(r) * cols + c;
      if (!inside[i]) continue;
      right[i] = c + 1 < cols && inside[i + 1] ? 1.0f : 0.0f;
      down[i] = r + 1 < rows && inside[i + cols] ? 1.0f : 0.0f;
      if (anchors) anchor[i] = float(anchors->weight[i]);
    }
  }
  level.set_diagonal();
  return level;
}

// Aggregation of 2 x 2 blocks: the Galerkin product P^T L P with piecewise-constant P is again a
// graph Laplacian, whose edge between two blocks carries the summed weights of the fine edges
// between them, and whose anchors are the blocks' summed anchors.
Level coarsen(const Level& fine) {
  Level coarse((fine.rows + 1) / 2, (fine.cols + 1) / 2);
  const float* fine_right = fine.right.data();
  const float* fine_down = fine.down.data();
  const float* fine_anchor = fine.anchor.data();
  float* right = coarse.right.data();
  float* down = coarse.down.data();
  float* anchor = coarse.anchor.data();
  for (int r = 0; r < coarse.rows; ++r) {
    for (int c = 0; c < coarse.cols; ++c) {
      const std::size_t i = std::size_t(r) * coarse.cols + c;
      const int fr = 2 * r, fc = 2 * c;
      for (int k = 0; k < 2; ++k) {
        if (fr + k < fine.rows && fc + 1 < fine.cols) right[i] += fine_right[std::size_t(fr + k) * fine.cols + fc + 1];
        if (fc + k < fine.cols && fr + 1 < fine.rows) down[i] += fine_down[std::size_t(fr + 1) * fine.cols + fc + k];
        for (int j = 0; j < 2; ++j)
          if (fr + k < fine.rows && fc + j < fine.cols) anchor[i] += fine_anchor[std::size_t(fr + k) * fine.cols + fc + j];
      }
    }
  }
  coarse.set_diagonal();
  return coarse;
}

// A level's weights as seen from one cell: its neighbours are read through the padding.
struct Stencil {
  const float* right;
  const float* down;
  const float* diagonal;
  std::ptrdiff_t cols;

  explicit Stencil(const Level& level)
      : right(level.right.data()), down(level.down.data()), diagonal(level.diagonal.data()), cols(level.cols) {}
  template <class T>
  T neighbours(const T* x, std::ptrdiff_t i) const {
    return T(right[i]) * x[i + 1] + T(right[i - 1]) * x[i - 1] + T(down[i]) * x[i + cols] + T(down[i - cols]) * x[i - cols];
  }
  template <class T>
  T laplacian(const T* x, std::ptrdiff_t i) const { return T(diagonal[i]) * x[i] - neighbours(x, i); }
};

// Sums of one value per row, added in row order: the same bits for any thread count.
double in_row_order(const std::vector<double>& row_sums) {
  double total = 0.0;
  for (double sum : row_sums) total += sum;
  return total;
}

// out = L x on the cells with edges (the others stay 0); returns x . out.
double apply(const Level& level, const double* x, double* out, std::vector<double>& row_sums) {
  const Stencil stencil(level);
  for_each_row(level.rows, level.size(), [&](int r) {
    double sum = 0.0;
    for (auto [i, end] = level.span(r); i < end; ++i) {
      out[i] = stencil.laplacian(x, i);
      sum += x[i] * out[i];
    }
    row_sums[std::size_t(r)] = sum;
  });
  return in_row_order(row_sums);
}

// One Gauss-Seidel half sweep over row r's cells with (r + c) % 2 == colour. The two colours are
// independent: a cell of one reads only cells of the other.
void relax_row(Level& level, int r, int colour) {
  const Stencil stencil(level);
  const float* inverse = level.inverse.data();
  const float* rhs = level.rhs.data();
  float* x = level.solution.data();
  auto [i, end] = level.span(r);
  for (i += (i - r * stencil.cols + r + colour) % 2; i < end; i += 2) x[i] = inverse[i] * (rhs[i] + stencil.neighbours(x, i));
}

// A Gauss-Seidel sweep: the cells of colour `first`, then the others. The rows are taken in bands of
// kRowsPerChunk, each in one pass that relaxes row r's first colour and then row r - 1's second (its
// neighbours of the first colour are all new by then), so that the rows are read from memory once, not
// twice; a band's first and last rows, whose neighbours of the first colour lie in other bands, get
// their second colour after every band is done. The result is that of the two half sweeps one after
// the other, whatever the number of threads.
void sweep(Level& level, int first) {
  const int second = 1 - first;
  const int bands = (level.rows + kRowsPerChunk - 1) / kRowsPerChunk;
  const int threads = level.size() >= kParallelCells ? 0 : 1;
  parallel_for(bands, 1, threads, [&](int band) {
    const int top = band * kRowsPerChunk, bottom = std::min(level.rows, top + kRowsPerChunk);
    for (int r = top; r < bottom; ++r) {
      relax_row(level, r, first);
      if (r - 1 > top) relax_row(level, r - 1, second);
    }
  });
  parallel_for(bands, 1, threads, [&](int band) {
    const int top = band * kRowsPerChunk, bottom = std::min(level.rows, top + kRowsPerChunk);
    relax_row(level, top, second);
    if (bottom - 1 > top) relax_row(level, bottom - 1, second);
  });
}

// Unsmoothed aggregation makes coarse corrections too small (about half for the Laplacian);
// over-correcting recovers most of the two-grid rate (Braess 1995) and, being below 2, keeps the
// preconditioner positive definite. 1.9 rather than Braess's 1.8: one to three iterations fewer of
// 10-27 on every mask tried (DiLiGenT's three, Mozart, random blobs and combs, the benchmark's disk
// with holes: 17 to 14 at 1024 px); 1.95 saves at most one more, closer to the bound.
constexpr double kCoarseCorrectionScale = 1.9;
constexpr int kCoarsestSweeps = 8;

// Approximately solves level l's system for its rhs into its solution. Symmetric (the smoothing
// after the coarse correction mirrors the one before), so that it can precondition conjugate gradients.
void v_cycle(std::vector<Level>& levels, std::size_t l) {
  Level& level = levels[l];
  level.solution.fill(0.0);
  if (l + 1 == levels.size()) {
    for (int k = 0; k < kCoarsestSweeps; ++k) sweep(level, 0);
    for (int r = 0; r < level.rows; ++r) relax_row(level, r, 0);
    return;
  }
  sweep(level, 0);
  // The residual b - L x, summed over each 2 x 2 block: the coarse level's right-hand side.
  Level& coarse = levels[l + 1];
  const float* b = level.rhs.data();
  const float* x = level.solution.data();
  const Stencil stencil(level);
  float* coarse_rhs = coarse.rhs.data();
  const std::ptrdiff_t cols = level.cols;
  for_each_row(coarse.rows, level.size(), [&](int coarse_row) {
    float* out = coarse_rhs + std::size_t(coarse_row) * coarse.cols;
    std::fill(out, out + coarse.cols, 0.0f);
    for (int r = 2 * coarse_row; r < std::min(2 * coarse_row + 2, level.rows); ++r) {
      const std::ptrdiff_t start = r * cols;
      for (auto [i, end] = level.span(r); i < end; ++i) out[(i - start) / 2] += b[i] - stencil.laplacian(x, i);
    }
  });
  v_cycle(levels, l + 1);
  const float* correction = coarse.solution.data();
  float* solution = level.solution.data();
  for_each_row(level.rows, level.size(), [&](int r) {
    const float* from = correction + std::size_t(r / 2) * coarse.cols;
    const std::ptrdiff_t start = r * cols;
    for (auto [i, end] = level.span(r); i < end; ++i) solution[i] += float(kCoarseCorrectionScale) * from[(i - start) / 2];
  });
  sweep(level, 1);
}

// Row sums over the cells with edges in parallel, then their total in row order: the same bits for any
// thread count.
template <class T>
double dot(const Level& level, const double* a, const T* b, std::vector<double>& row_sums) {
  for_each_row(level.rows, level.size(), [&](int r) {
    double sum = 0.0;
    for (auto [i, end] = level.span(r); i < end; ++i) sum += a[i] * double(b[i]);
    row_sums[std::size_t(r)] = sum;
  });
  return in_row_order(row_sums);
}

std::vector<Level> hierarchy(const Mask& mask, const Anchors* anchors) {
  std::vector<Level> levels;
  levels.push_back(finest_level(mask, anchors));
  while (levels.back().rows > 2 || levels.back().cols > 2) levels.push_back(coarsen(levels.back()));
  return levels;
}

// b = div(rise) + anchor weight * target into b (H * W, row-major): each edge of two masked
// 4-neighbours pulls its ends apart by its rise (none where `rises` is empty), each anchor pulls its
// cell toward its target; a cell gathers its own four edges, so rows run in parallel.
void write_right_hand_side(const Mask& mask, const EdgeRises& rises, const Anchors* anchors, double* b) {
  const int rows = int(mask.rows()), cols = int(mask.cols());
  const bool* inside = mask.data();
  const bool rising = !rises.right.empty();
  for_each_row(rows, std::size_t(mask.size()), [&](int r) {
    for (int c = 0; c < cols; ++c) {
      const std::size_t i = std::size_t(r) * cols + c;
      double sum = 0.0;
      if (inside[i] && rising) {
        if (c + 1 < cols && inside[i + 1]) sum -= rises.right[i];
        if (c > 0 && inside[i - 1]) sum += rises.right[i - 1];
        if (r + 1 < rows && inside[i + cols]) sum -= rises.down[i];
        if (r > 0 && inside[i - std::size_t(cols)]) sum += rises.down[i - std::size_t(cols)];
      }
      if (inside[i] && anchors) sum += anchors->weight[i] * anchors->target[i];
      b[i] = sum;
    }
  });
}

constexpr int kMaxIterations = 1000;

// L z = b on a whole rectangle: the cosine transform diagonalizes its graph Laplacian (Neumann
// boundary; Simchony, Chellappa & Shao 1990), whose eigenvalue at frequencies (k, l) is
// 4 - 2 cos(pi k / rows) - 2 cos(pi l / cols). Exact up to rounding, at the cost of two transforms;
// the constant, L's null space, is set to 0.
std::vector<double> solve_rectangle(const Mask& whole, const EdgeRises& rises) {
  constexpr double kPi = 3.14159265358979323846;
  const int rows = int(whole.rows()), cols = int(whole.cols());
  std::vector<double> field(std::size_t(whole.size()));
  write_right_hand_side(whole, rises, nullptr, field.data());
  cosine_2d(field, rows, cols, FourierDirection::Forward);
  std::vector<double> column_part(static_cast<std::size_t>(cols));
  for (int c = 0; c < cols; ++c) column_part[std::size_t(c)] = 2.0 - 2.0 * std::cos(kPi * c / cols);
  for (int r = 0; r < rows; ++r) {
    const double row_part = 2.0 - 2.0 * std::cos(kPi * r / rows);
    double* line = field.data() + std::size_t(r) * cols;
    for (int c = 0; c < cols; ++c) {
      const double eigenvalue = row_part + column_part[std::size_t(c)];
      line[c] = eigenvalue > 0.0 ? line[c] / eigenvalue : 0.0;
    }
  }
  cosine_2d(field, rows, cols, FourierDirection::Inverse);
  return field;
}

// The same problem on the rectangle `box` of the grid, which holds every masked cell; solved there and written back into the whole grid.
std::vector<double> solve_in_box(const Mask& mask, const EdgeRises& rises, double relative_tolerance,
                                 const Progress& progress, const Anchors* anchors, const Box& box) {
  const int top = box.top, left = box.left, rows = box.rows, cols = box.cols;
  const Eigen::Index grid_cols = mask.cols();
  auto cropped = [&](const std::vector<double>& field) {
    if (field.empty()) return field;
    std::vector<double> box(std::size_t(rows) * std::size_t(cols));
    for (int r = 0; r < rows; ++r)
      std::copy_n(field.begin() + std::ptrdiff_t((top + r) * grid_cols + left), cols, box.begin() + std::ptrdiff_t(r * cols));
    return box;
  };
  const Mask box_mask = mask.block(top, left, rows, cols);
  const EdgeRises box_rises{cropped(rises.right), cropped(rises.down)};
  Anchors box_anchors;
  if (anchors) box_anchors = {cropped(anchors->weight), cropped(anchors->target)};
  const std::vector<double> solved =
      solve_grid_poisson(box_mask, box_rises, relative_tolerance, progress, anchors ? &box_anchors : nullptr);
  std::vector<double> depth(std::size_t(mask.size()), 0.0);
  for (int r = 0; r < rows; ++r)
    std::copy_n(solved.begin() + std::ptrdiff_t(r * cols), cols, depth.begin() + std::ptrdiff_t((top + r) * grid_cols + left));
  return depth;
}

}  // namespace

std::vector<double> solve_grid_poisson(const Mask& mask, const EdgeRises& rises, double relative_tolerance,
                                       const Progress& progress, const Anchors* anchors) {
  // Only the masked cells' bounding box is worked on: the rest would be allocated and swept for nothing.
  const std::optional<Box> box = mask_bounds(mask);
  if (!box) return std::vector<double>(std::size_t(mask.size()), 0.0);
  if (box->rows < mask.rows() || box->cols < mask.cols())
    return solve_in_box(mask, rises, relative_tolerance, progress, anchors, *box);
  if (mask.all() && !anchors) {
    std::vector<double> depth = solve_rectangle(mask, rises);
    progress.report(1.0, "integration");
    return depth;
  }
  std::vector<Level> levels = hierarchy(mask, anchors);
  Level& finest = levels.front();
  const std::size_t size = finest.size();
  const int cols = finest.cols;
  std::vector<double> row_sums(std::size_t(finest.rows));

  // Conjugate gradients on L x = b in double, preconditioned by one V-cycle in float: the finest
  // level's rhs is the residual r rounded, its solution the preconditioned residual z.
  Field<double> x_field(size, cols), r_field(size, cols), p_field(size, cols), lp_field(size, cols);
  double* x = x_field.data();
  double* r = r_field.data();
  double* p = p_field.data();
  double* lp = lp_field.data();
  float* r_single = finest.rhs.data();
  const float* z = finest.solution.data();
  write_right_hand_side(mask, rises, anchors, r);
  const double b_norm = std::sqrt(dot(finest, r, r, row_sums));
  std::vector<double> depth(size, 0.0);
  if (b_norm == 0.0) return depth;

  for_each_row(finest.rows, size, [&](int row) {
    for (auto [i, end] = finest.span(row); i < end; ++i) r_single[i] = float(r[i]);
  });
  v_cycle(levels, 0);
  for_each_row(finest.rows, size, [&](int row) {
    for (auto [i, end] = finest.span(row); i < end; ++i) p[i] = double(z[i]);
  });
  double rz = dot(finest, r, z, row_sums);
  const double log_target = std::log(relative_tolerance);
  for (int iteration = 0;; ++iteration) {
    if (iteration == kMaxIterations)
      throw std::runtime_error("integrate_normals: the Poisson solve did not converge in " +
                               std::to_string(kMaxIterations) + " iterations");
    const double step = rz / apply(finest, p, lp, row_sums);
    for_each_row(finest.rows, size, [&](int row) {
      double sum = 0.0;
      for (auto [i, end] = finest.span(row); i < end; ++i) {
        x[i] += step * p[i];
        r[i] -= step * lp[i];
        r_single[i] = float(r[i]);
        sum += r[i] * r[i];
      }
      row_sums[std::size_t(row)] = sum;
    });
    const double relative = std::sqrt(in_row_order(row_sums)) / b_norm;
    progress.report(std::clamp(std::log(std::max(relative, relative_tolerance)) / log_target, 0.0, 1.0),
                    "integration");
    if (relative <= relative_tolerance) break;
    v_cycle(levels, 0);
    const double rz_next = dot(finest, r, z, row_sums);
    const double beta = rz_next / rz;
    rz = rz_next;
    for_each_row(finest.rows, size, [&](int row) {
      for (auto [i, end] = finest.span(row); i < end; ++i) p[i] = double(z[i]) + beta * p[i];
    });
  }
  std::copy(x, x + size, depth.begin());
  return depth;
}

}  // namespace shadecut::detail
