#include "integrate/grid_poisson.hpp"

#include "integrate/fourier.hpp"
#include "support/parallel.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <stdexcept>

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
class Field {
 public:
  Field() = default;
  Field(std::size_t size, int cols) : pad_(std::size_t(cols) + 1), values_(size + 2 * pad_, 0.0) {}
  double* data() { return values_.data() + pad_; }
  const double* data() const { return values_.data() + pad_; }
  void fill(double value) { std::fill(values_.begin(), values_.end(), value); }

 private:
  std::size_t pad_ = 0;
  std::vector<double> values_;
};

// One level of the hierarchy: a graph Laplacian with weighted 4-neighbour edges on a rows x cols grid.
struct Level {
  int rows = 0, cols = 0;
  Field right, down;         // weight of the edge to (r, c + 1), to (r + 1, c); 0 where there is none
  Field diagonal, inverse;   // sum of a cell's edge weights, its inverse (0 for a cell without edges)
  Field solution, rhs;

  Level(int rows_, int cols_) : rows(rows_), cols(cols_) {
    for (Field* field : {&right, &down, &diagonal, &inverse, &solution, &rhs}) *field = Field(size(), cols);
  }
  std::size_t size() const { return std::size_t(rows) * std::size_t(cols); }

  void set_diagonal() {
    const double* r = right.data();
    const double* d = down.data();
    double* diag = diagonal.data();
    double* inv = inverse.data();
    for (std::size_t i = 0; i < size(); ++i) {
      diag[i] = r[i] + r[i - 1] + d[i] + d[i - std::size_t(cols)];
      inv[i] = diag[i] > 0.0 ? 1.0 / diag[i] : 0.0;
    }
  }
};

Level finest_level(const Mask& mask) {
  Level level(int(mask.rows()), int(mask.cols()));
  const bool* inside = mask.data();
  double* right = level.right.data();
  double* down = level.down.data();
  const int rows = level.rows, cols = level.cols;
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) {
      const std::size_t i = std::size_t(r) * cols + c;
      if (!inside[i]) continue;
      right[i] = c + 1 < cols && inside[i + 1] ? 1.0 : 0.0;
      down[i] = r + 1 < rows && inside[i + cols] ? 1.0 : 0.0;
    }
  }
  level.set_diagonal();
  return level;
}

// Aggregation of 2 x 2 blocks: the Galerkin product P^T L P with piecewise-constant P is again a
// graph Laplacian, whose edge between two blocks carries the summed weights of the fine edges
// between them.
Level coarsen(const Level& fine) {
  Level coarse((fine.rows + 1) / 2, (fine.cols + 1) / 2);
  const double* fine_right = fine.right.data();
  const double* fine_down = fine.down.data();
  double* right = coarse.right.data();
  double* down = coarse.down.data();
  for (int r = 0; r < coarse.rows; ++r) {
    for (int c = 0; c < coarse.cols; ++c) {
      const std::size_t i = std::size_t(r) * coarse.cols + c;
      const int fr = 2 * r, fc = 2 * c;
      for (int k = 0; k < 2; ++k) {
        if (fr + k < fine.rows && fc + 1 < fine.cols) right[i] += fine_right[std::size_t(fr + k) * fine.cols + fc + 1];
        if (fc + k < fine.cols && fr + 1 < fine.rows) down[i] += fine_down[std::size_t(fr + 1) * fine.cols + fc + k];
      }
    }
  }
  coarse.set_diagonal();
  return coarse;
}

// A level's weights as seen from one cell: its neighbours are read through the padding.
struct Stencil {
  const double* right;
  const double* down;
  const double* diagonal;
  std::ptrdiff_t cols;

  explicit Stencil(const Level& level)
      : right(level.right.data()), down(level.down.data()), diagonal(level.diagonal.data()), cols(level.cols) {}
  double neighbours(const double* x, std::ptrdiff_t i) const {
    return right[i] * x[i + 1] + right[i - 1] * x[i - 1] + down[i] * x[i + cols] + down[i - cols] * x[i - cols];
  }
  double laplacian(const double* x, std::ptrdiff_t i) const { return diagonal[i] * x[i] - neighbours(x, i); }
};

// Sums of one value per row, added in row order: the same bits for any thread count.
double in_row_order(const std::vector<double>& row_sums) {
  double total = 0.0;
  for (double sum : row_sums) total += sum;
  return total;
}

// out = L x; returns x . out.
double apply(const Level& level, const double* x, double* out, std::vector<double>& row_sums) {
  const Stencil stencil(level);
  const std::ptrdiff_t cols = level.cols;
  for_each_row(level.rows, level.size(), [&](int r) {
    double sum = 0.0;
    for (std::ptrdiff_t i = r * cols, end = i + cols; i < end; ++i) {
      out[i] = stencil.laplacian(x, i);
      sum += x[i] * out[i];
    }
    row_sums[std::size_t(r)] = sum;
  });
  return in_row_order(row_sums);
}

// One Gauss-Seidel half sweep over the cells with (r + c) % 2 == colour; the two colours are
// independent, so rows run in parallel and the result does not depend on the thread count.
void relax(Level& level, int colour) {
  const Stencil stencil(level);
  const double* inverse = level.inverse.data();
  const double* rhs = level.rhs.data();
  double* x = level.solution.data();
  const std::ptrdiff_t cols = level.cols;
  for_each_row(level.rows, level.size(), [&](int r) {
    for (std::ptrdiff_t i = r * cols + (r + colour) % 2, end = (r + 1) * cols; i < end; i += 2) {
      x[i] = inverse[i] * (rhs[i] + stencil.neighbours(x, i));
    }
  });
}

// Unsmoothed aggregation makes coarse corrections too small (about half for the Laplacian);
// over-correcting recovers most of the two-grid rate (Braess 1995; 1.8 is the usual factor) and,
// being below 2, keeps the preconditioner positive definite.
constexpr double kCoarseCorrectionScale = 1.8;
constexpr int kCoarsestSweeps = 8;

// Approximately solves level l's system for its rhs into its solution. Symmetric (the smoothing
// after the coarse correction mirrors the one before), so that it can precondition conjugate gradients.
void v_cycle(std::vector<Level>& levels, std::size_t l) {
  Level& level = levels[l];
  level.solution.fill(0.0);
  if (l + 1 == levels.size()) {
    for (int sweep = 0; sweep < kCoarsestSweeps; ++sweep) {
      relax(level, 0);
      relax(level, 1);
    }
    relax(level, 0);
    return;
  }
  relax(level, 0);
  relax(level, 1);
  // The residual b - L x, summed over each 2 x 2 block: the coarse level's right-hand side.
  Level& coarse = levels[l + 1];
  const double* b = level.rhs.data();
  const double* x = level.solution.data();
  const Stencil stencil(level);
  double* coarse_rhs = coarse.rhs.data();
  const std::ptrdiff_t cols = level.cols;
  for_each_row(coarse.rows, level.size(), [&](int coarse_row) {
    double* out = coarse_rhs + std::size_t(coarse_row) * coarse.cols;
    std::fill(out, out + coarse.cols, 0.0);
    for (int r = 2 * coarse_row; r < std::min(2 * coarse_row + 2, level.rows); ++r) {
      for (std::ptrdiff_t c = 0; c < cols; ++c) {
        const std::ptrdiff_t i = r * cols + c;
        out[c / 2] += b[i] - stencil.laplacian(x, i);
      }
    }
  });
  v_cycle(levels, l + 1);
  const double* correction = coarse.solution.data();
  double* solution = level.solution.data();
  for_each_row(level.rows, level.size(), [&](int r) {
    const double* from = correction + std::size_t(r / 2) * coarse.cols;
    double* to = solution + std::size_t(r) * cols;
    for (int c = 0; c < cols; ++c) to[c] += kCoarseCorrectionScale * from[c / 2];
  });
  relax(level, 1);
  relax(level, 0);
}

// Row sums in parallel, then their total in row order: the same bits for any thread count.
double dot(const Level& level, const double* a, const double* b, std::vector<double>& row_sums) {
  const std::ptrdiff_t cols = level.cols;
  for_each_row(level.rows, level.size(), [&](int r) {
    double sum = 0.0;
    for (std::ptrdiff_t i = r * cols, end = i + cols; i < end; ++i) sum += a[i] * b[i];
    row_sums[std::size_t(r)] = sum;
  });
  return in_row_order(row_sums);
}

std::vector<Level> hierarchy(const Mask& mask) {
  std::vector<Level> levels;
  levels.push_back(finest_level(mask));
  while (levels.back().rows > 2 || levels.back().cols > 2) levels.push_back(coarsen(levels.back()));
  return levels;
}

// b = div(rise) into b (H * W, row-major): each edge of two masked 4-neighbours pulls its ends apart
// by its rise; a cell gathers its own four edges, so rows run in parallel.
void write_divergence(const Mask& mask, const EdgeRises& rises, double* b) {
  const int rows = int(mask.rows()), cols = int(mask.cols());
  const bool* inside = mask.data();
  for_each_row(rows, std::size_t(mask.size()), [&](int r) {
    for (int c = 0; c < cols; ++c) {
      const std::size_t i = std::size_t(r) * cols + c;
      double sum = 0.0;
      if (inside[i]) {
        if (c + 1 < cols && inside[i + 1]) sum -= rises.right[i];
        if (c > 0 && inside[i - 1]) sum += rises.right[i - 1];
        if (r + 1 < rows && inside[i + cols]) sum -= rises.down[i];
        if (r > 0 && inside[i - std::size_t(cols)]) sum += rises.down[i - std::size_t(cols)];
      }
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
  write_divergence(whole, rises, field.data());
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

}  // namespace

std::vector<double> solve_grid_poisson(const Mask& mask, const EdgeRises& rises, double relative_tolerance,
                                       const Progress& progress) {
  if (mask.all()) {
    std::vector<double> depth = solve_rectangle(mask, rises);
    progress.report(1.0, "integration");
    return depth;
  }
  std::vector<Level> levels = hierarchy(mask);
  Level& finest = levels.front();
  const std::size_t size = finest.size();
  const int cols = finest.cols;
  write_divergence(mask, rises, finest.rhs.data());
  std::vector<double> row_sums(std::size_t(finest.rows));

  // Conjugate gradients on L x = b, preconditioned by one V-cycle; the finest level's rhs doubles as
  // the CG residual, its solution as the preconditioned residual.
  double* r = finest.rhs.data();
  double* z = finest.solution.data();
  Field x_field(size, cols), p_field(size, cols), lp_field(size, cols);
  double* x = x_field.data();
  double* p = p_field.data();
  double* lp = lp_field.data();
  const double b_norm = std::sqrt(dot(finest, r, r, row_sums));
  const std::ptrdiff_t stride = cols;
  std::vector<double> depth(size, 0.0);
  if (b_norm == 0.0) return depth;

  v_cycle(levels, 0);
  std::copy(z, z + size, p);
  double rz = dot(finest, r, z, row_sums);
  const double log_target = std::log(relative_tolerance);
  for (int iteration = 0;; ++iteration) {
    if (iteration == kMaxIterations)
      throw std::runtime_error("integrate_normals: the Poisson solve did not converge in " +
                               std::to_string(kMaxIterations) + " iterations");
    const double step = rz / apply(finest, p, lp, row_sums);
    for_each_row(finest.rows, size, [&](int row) {
      double sum = 0.0;
      for (std::ptrdiff_t i = row * stride, end = i + stride; i < end; ++i) {
        x[i] += step * p[i];
        r[i] -= step * lp[i];
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
      for (std::ptrdiff_t i = row * stride, end = i + stride; i < end; ++i) p[i] = z[i] + beta * p[i];
    });
  }
  std::copy(x, x + size, depth.begin());
  return depth;
}

}  // namespace shadecut::detail
