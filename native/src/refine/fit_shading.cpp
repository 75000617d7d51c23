#include <shadecut/refine/fit_shading.hpp>

#include <shadecut/local/local_shape.hpp>
#include <shadecut/support/downsample.hpp>
#include <shadecut/support/errors.hpp>
#include <shadecut/support/mask_components.hpp>

#include "integrate/grid_poisson.hpp"
#include "support/masked_gradient.hpp"
#include "support/parallel.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <tuple>
#include <utility>
#include <vector>

namespace shadecut {

namespace {

using Field = Eigen::Array<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

// Rows are handed out in small chunks, so that a thread that lost its core holds up the others by
// one chunk only (as in the Poisson solve).
constexpr int kRowsPerChunk = 16;

// body(row) for every row, on every thread.
template <class Body>
void for_each_row(int rows, Body&& body) {
  detail::parallel_for(rows, kRowsPerChunk, 0, body);
}

// The brightness residual rho max(0, n . S) - I at a pixel of gradient (p, q), and its derivatives
// with respect to p and q (0 where the pixel faces away from the light).
struct Shading {
  double residual = 0.0, by_p = 0.0, by_q = 0.0;
};

Shading shading(double p, double q, double intensity, const Eigen::Vector3d& light, double albedo) {
  const double g2 = 1.0 + p * p + q * q, g = std::sqrt(g2);
  const double facing = -p * light.x() - q * light.y() + light.z();  // n . S times g
  Shading s;
  s.residual = albedo * (facing > 0.0 ? facing / g : 0.0) - intensity;
  if (facing > 0.0) {
    // d(facing / g)/dp = (-S_x g^2 - facing p) / g^3, and alike for q.
    s.by_p = albedo * (-light.x() * g2 - facing * p) / (g2 * g);
    s.by_q = albedo * (-light.y() * g2 - facing * q) / (g2 * g);
  }
  return s;
}

// One level of the fit: what it reads and keeps fixed.
struct Problem {
  const ImageF& image;
  const Mask& mask;
  const Mask& fitted;
  Eigen::Vector3d light;  // unit
  double albedo = 1.0;
  double weight = 0.0;    // mu^2 at this level's object size
  Field start;            // z0
  MaskComponents components;

  // (L x)(r, c), L the mask's graph Laplacian: the sum over masked 4-neighbours of x(r, c) - x(neighbour).
  template <class X>
  double laplacian(const X& x, int r, int c, int* degree = nullptr) const {
    double sum = 0.0;
    int count = 0;
    for (const auto& [rr, cc] : {std::pair{r, c - 1}, std::pair{r, c + 1}, std::pair{r - 1, c}, std::pair{r + 1, c}}) {
      if (rr < 0 || rr >= mask.rows() || cc < 0 || cc >= mask.cols() || !mask(rr, cc)) continue;
      sum += x(r, c) - x(rr, cc);
      ++count;
    }
    if (degree) *degree = count;
    return sum;
  }
};

// The cost's two terms at depth z: the brightness residual over the fitted pixels (with
// normals_from_depth's differences) and mu^2 |L (z - z0)|^2. Summed per row, then in row order: the
// same bits for any thread count.
struct Cost {
  double residual = 0.0, smoothing = 0.0;
  double total() const { return residual + smoothing; }
};

Cost cost_of(const Problem& problem, const Field& z) {
  const int rows = int(z.rows()), cols = int(z.cols());
  const auto correction = z - problem.start;
  std::vector<Cost> row_costs(static_cast<std::size_t>(rows));
  for_each_row(rows, [&](int r) {
    Cost row;
    for (int c = 0; c < cols; ++c) {
      if (!problem.mask(r, c)) continue;
      if (problem.fitted(r, c)) {
        const detail::MaskedGradient g = detail::masked_gradient(z, problem.mask, r, c);
        const double residual = shading(g.dx, g.dy, problem.image(r, c), problem.light, problem.albedo).residual;
        row.residual += residual * residual;
      }
      const double curvature = problem.laplacian(correction, r, c);
      row.smoothing += curvature * curvature;
    }
    row_costs[std::size_t(r)] = row;
  });
  Cost total;
  for (const Cost& row : row_costs) {
    total.residual += row.residual;
    total.smoothing += row.smoothing;
  }
  total.smoothing *= problem.weight;
  return total;
}

// The per-pixel gradients of ADMM's splitting g = C z (C: normals_from_depth's differences), u its
// scaled dual variable; both 0 outside the fitted pixels.
struct Split {
  Field change_p, change_q;  // d of the gradient step: g = C z + u + d
  Field dual_p, dual_q;      // u
};

// Gauss-Newton iterations of each fitted pixel's own problem (the gradient step).
constexpr int kPixelIterations = 3;

// The gradient step: for every fitted pixel, g = C z + u + d with the d that minimizes
// (rho max(0, n(C z + u + d) . S) - I)^2 + beta |d|^2: a 2-D problem per pixel, solved by a few
// Gauss-Newton steps from d = 0 (each a 2 x 2 solve in closed form, the data term's Hessian J^T J
// having rank 1), each kept only if it lowers the pixel's cost.
void gradient_step(const Problem& problem, const Field& z, double beta, Split& split) {
  const int rows = int(z.rows()), cols = int(z.cols());
  for_each_row(rows, [&](int r) {
    for (int c = 0; c < cols; ++c) {
      split.change_p(r, c) = split.change_q(r, c) = 0.0;
      if (!problem.mask(r, c) || !problem.fitted(r, c)) continue;
      const detail::MaskedGradient h = detail::masked_gradient(z, problem.mask, r, c);
      const double p = h.dx + split.dual_p(r, c), q = h.dy + split.dual_q(r, c), intensity = problem.image(r, c);
      double dp = 0.0, dq = 0.0;
      Shading s = shading(p, q, intensity, problem.light, problem.albedo);
      double pixel_cost = s.residual * s.residual;
      for (int iteration = 0; iteration < kPixelIterations; ++iteration) {
        // (J^T J + beta I) step = -(J^T residual + beta d), by Sherman-Morrison.
        const double gp = s.by_p * s.residual + beta * dp, gq = s.by_q * s.residual + beta * dq;
        const double along = (s.by_p * gp + s.by_q * gq) / (beta + s.by_p * s.by_p + s.by_q * s.by_q);
        const double tp = dp - (gp - s.by_p * along) / beta, tq = dq - (gq - s.by_q * along) / beta;
        const Shading tried = shading(p + tp, q + tq, intensity, problem.light, problem.albedo);
        const double tried_cost = tried.residual * tried.residual + beta * (tp * tp + tq * tq);
        if (!(tried_cost < pixel_cost)) break;
        dp = tp, dq = tq, s = tried, pixel_cost = tried_cost;
      }
      split.change_p(r, c) = dp;
      split.change_q(r, c) = dq;
    }
  });
}

// The Poisson solve's relative tolerance: the step needs no more (a tighter one does not change the
// training error; docs/parameters.md, "Fitting the depth to the image").
constexpr double kPoissonTolerance = 1e-2;

// The depth step: the correction dz toward min beta |C (z + dz) - (g - u)|^2 + mu^2 |L (z + dz - z0)|^2,
// with C z + ... taken on the mask's edges: the gradient step's changes d averaged onto each edge (y is
// up: a row down is -q) are integrated by one Poisson solve (v), then the smoothness enters by one
// Jacobi step of (beta + mu^2 L) dz = beta v - mu^2 L (z - z0). Each component's correction is
// shifted to mean 0, so that the fit keeps the depth's level.
Field depth_step(const Problem& problem, const Field& z, double beta, const Split& split) {
  const int rows = int(z.rows()), cols = int(z.cols());
  const std::size_t size = std::size_t(rows) * std::size_t(cols);
  detail::EdgeRises rises{std::vector<double>(size, 0.0), std::vector<double>(size, 0.0)};
  for_each_row(rows, [&](int r) {
    for (int c = 0; c < cols; ++c) {
      if (!problem.mask(r, c)) continue;
      const std::size_t i = std::size_t(r) * cols + c;
      if (c + 1 < cols && problem.mask(r, c + 1)) rises.right[i] = 0.5 * (split.change_p(r, c) + split.change_p(r, c + 1));
      if (r + 1 < rows && problem.mask(r + 1, c)) rises.down[i] = -0.5 * (split.change_q(r, c) + split.change_q(r + 1, c));
    }
  });
  const std::vector<double> integrated = detail::solve_grid_poisson(problem.mask, rises, kPoissonTolerance);
  const auto correction = z - problem.start;
  Field step = Field::Zero(rows, cols);
  for_each_row(rows, [&](int r) {
    for (int c = 0; c < cols; ++c) {
      if (!problem.mask(r, c)) continue;
      int degree = 0;
      const double curvature = problem.laplacian(correction, r, c, &degree);
      step(r, c) = (beta * integrated[std::size_t(r) * cols + c] - problem.weight * curvature) /
                   (beta + problem.weight * degree);
    }
  });
  const Labels& labels = problem.components.labels;
  std::vector<double> sums(std::size_t(problem.components.count), 0.0);
  std::vector<int> counts(std::size_t(problem.components.count), 0);
  for (std::size_t i = 0; i < size; ++i) {
    if (labels.data()[i] < 0) continue;
    sums[std::size_t(labels.data()[i])] += step.data()[i];
    ++counts[std::size_t(labels.data()[i])];
  }
  for (std::size_t i = 0; i < size; ++i)
    if (labels.data()[i] >= 0) step.data()[i] -= sums[std::size_t(labels.data()[i])] / counts[std::size_t(labels.data()[i])];
  return step;
}

// u += C z_new - g, with g = C z + u + d the gradient step's: u becomes C z_new - C z - d.
void dual_step(const Problem& problem, const Field& z, const Field& next, Split& split) {
  for_each_row(int(z.rows()), [&](int r) {
    for (int c = 0; c < z.cols(); ++c) {
      if (!problem.mask(r, c) || !problem.fitted(r, c)) continue;
      const detail::MaskedGradient after = detail::masked_gradient(next, problem.mask, r, c);
      const detail::MaskedGradient before = detail::masked_gradient(z, problem.mask, r, c);
      split.dual_p(r, c) = after.dx - before.dx - split.change_p(r, c);
      split.dual_q(r, c) = after.dy - before.dy - split.change_q(r, c);
    }
  });
}

// The coupling beta: this share of the data term's mean curvature |J|^2 over the fitted pixels, small
// enough for large steps (the trial that chose it: docs/parameters.md, "Fitting the depth to the image").
constexpr double kCoupling = 0.1;

double coupling(const Problem& problem, const Field& z) {
  const int rows = int(z.rows()), cols = int(z.cols());
  std::vector<double> sums(std::size_t(rows), 0.0);
  std::vector<int> counts(std::size_t(rows), 0);
  for_each_row(rows, [&](int r) {
    for (int c = 0; c < cols; ++c) {
      if (!problem.mask(r, c) || !problem.fitted(r, c)) continue;
      const detail::MaskedGradient h = detail::masked_gradient(z, problem.mask, r, c);
      const Shading s = shading(h.dx, h.dy, problem.image(r, c), problem.light, problem.albedo);
      sums[std::size_t(r)] += s.by_p * s.by_p + s.by_q * s.by_q;
      ++counts[std::size_t(r)];
    }
  });
  double sum = 0.0;
  int count = 0;
  for (int r = 0; r < rows; ++r) sum += sums[std::size_t(r)], count += counts[std::size_t(r)];
  return kCoupling * std::max(count ? sum / count : 0.0, 1e-6);
}

// Bilinear interpolation of a coarse field (one value per factor x factor block, defined where
// `defined`) at every fine pixel centre; blocks left undefined first take the mean of their defined
// neighbours, ring by ring, so that the mask's edge has values on both sides.
ImageF upsample(ImageF coarse, Mask defined, int factor, int rows, int cols) {
  for (int ring = 0; ring < 3 && !defined.all(); ++ring) {
    const ImageF before = coarse;
    const Mask known = defined;
    for (int r = 0; r < coarse.rows(); ++r) {
      for (int c = 0; c < coarse.cols(); ++c) {
        if (known(r, c)) continue;
        double sum = 0.0;
        int count = 0;
        for (const auto& [dr, dc] : {std::pair{-1, 0}, std::pair{1, 0}, std::pair{0, -1}, std::pair{0, 1}}) {
          const int rr = r + dr, cc = c + dc;
          if (rr < 0 || rr >= coarse.rows() || cc < 0 || cc >= coarse.cols() || !known(rr, cc)) continue;
          sum += before(rr, cc);
          ++count;
        }
        if (count) coarse(r, c) = float(sum / count), defined(r, c) = true;
      }
    }
  }
  ImageF fine = ImageF::Zero(rows, cols);
  const int last_row = int(coarse.rows()) - 1, last_col = int(coarse.cols()) - 1;
  for (int r = 0; r < rows; ++r) {
    // The fine pixel centre in coarse pixel units, clamped to the coarse grid.
    const double y = std::clamp((r + 0.5) / factor - 0.5, 0.0, double(last_row));
    const int r0 = std::min(int(y), std::max(last_row - 1, 0)), r1 = std::min(r0 + 1, last_row);
    const double wy = y - r0;
    for (int c = 0; c < cols; ++c) {
      const double x = std::clamp((c + 0.5) / factor - 0.5, 0.0, double(last_col));
      const int c0 = std::min(int(x), std::max(last_col - 1, 0)), c1 = std::min(c0 + 1, last_col);
      const double wx = x - c0;
      double sum = 0.0, weight = 0.0;
      for (const auto& [rr, cc, w] : {std::tuple{r0, c0, (1 - wy) * (1 - wx)}, std::tuple{r0, c1, (1 - wy) * wx},
                                     std::tuple{r1, c0, wy * (1 - wx)}, std::tuple{r1, c1, wy * wx}}) {
        if (!defined(rr, cc) || w <= 0.0) continue;
        sum += w * coarse(rr, cc);
        weight += w;
      }
      if (weight > 0.0) fine(r, c) = float(sum / weight);
    }
  }
  return fine;
}

// A level's result: its depth of least cost whose residual is at most its start's, the dual variable
// there, and the steps (over this level and the coarser ones) that reached it.
struct LevelFit {
  Field depth;
  Field dual_p, dual_q;
  int steps = 0;
};

// ADMM from depth z and dual variable (dual_p, dual_q) at this level, `steps` steps. The returned dual
// variable is that of a finer level's start (`finer`); the whole image's is not needed.
LevelFit admm(const Problem& problem, Field z, Split split, int coarse_steps, int steps, bool finer,
              const Progress& progress) {
  LevelFit fit{problem.start, Field::Zero(z.rows(), z.cols()), Field::Zero(z.rows(), z.cols()), 0};
  Cost best = cost_of(problem, problem.start);
  const double residual_before = best.residual;
  auto consider = [&](const Field& depth, const Cost& cost, int steps_taken) {
    if (!(cost.total() < best.total() && cost.residual <= residual_before)) return;
    fit.depth = depth;
    fit.steps = steps_taken;
    if (finer) fit.dual_p = split.dual_p, fit.dual_q = split.dual_q;
    best = cost;
  };
  consider(z, cost_of(problem, z), coarse_steps);
  const double beta = coupling(problem, z);
  for (int step = 0; step < steps; ++step) {
    progress.report(double(step) / steps, "fit_shading");
    gradient_step(problem, z, beta, split);
    Field next = z + depth_step(problem, z, beta, split);
    if (finer || step + 1 < steps) dual_step(problem, z, next, split);
    z = std::move(next);
    consider(z, cost_of(problem, z), coarse_steps + step + 1);
  }
  return fit;
}

// Levels are made smaller by this factor until the object is at most kCoarsestSize pixels. Steps at
// a level: kStepsAtReference at the reference object size, in inverse proportion to the level's
// pixel count (the same work at every level), at least 1 and at most max_steps; chosen on the training
// surfaces (docs/parameters.md, "Fitting the depth to the image").
constexpr int kLevelFactor = 2;
constexpr double kCoarsestSize = 32.0;
constexpr double kStepsAtReference = 16.0;

int level_steps(double size, int max_steps) {
  const double steps = std::ceil(kStepsAtReference * std::pow(kReferenceObjectSize / size, 2));
  return std::clamp(int(std::min(steps, double(max_steps))), 1, max_steps);
}

LevelFit fit_level(const ImageF& depth, const ImageF& image, const Mask& mask, const Mask& fitted,
                   const Eigen::Vector3d& light, double albedo, const FitShadingParams& params, bool finer,
                   const Progress& progress) {
  const double size = object_size(mask);
  const Problem problem{image, mask, fitted, light, albedo, std::pow(params.smoothness * size / kReferenceObjectSize, 2),
                        depth.cast<double>(), mask_components(mask)};
  const int rows = int(mask.rows()), cols = int(mask.cols());
  Field z = problem.start;
  Split split{Field(rows, cols), Field(rows, cols), Field::Zero(rows, cols), Field::Zero(rows, cols)};
  int coarse_steps = 0;
  double share = 0.0;
  const Downsampled coarse = size > kCoarsestSize && rows >= 4 * kLevelFactor && cols >= 4 * kLevelFactor
                                 ? downsample(image, mask, kLevelFactor, 1.0)
                                 : Downsampled{};
  if (coarse.mask.any()) {  // none for a thin object: this level alone
    const Mask coarse_fitted = downsample(image, fitted, kLevelFactor, 1.0).mask && coarse.mask;
    const ImageF start = downsample(depth, mask, kLevelFactor, 1.0).image / float(kLevelFactor);
    share = 0.5;
    const LevelFit coarse_fit = fit_level(start, coarse.image, coarse.mask, coarse_fitted, light, albedo, params, true,
                                          progress.range(0.0, share));
    auto fine = [&](const ImageF& field) -> Field {
      return mask.select(upsample(field, coarse.mask, kLevelFactor, rows, cols), 0.0f).cast<double>();
    };
    z += fine((coarse_fit.depth.cast<float>() - start) * float(kLevelFactor));
    // The dual variable is a slope: it carries over unscaled.
    split.dual_p = fine(coarse_fit.dual_p.cast<float>());
    split.dual_q = fine(coarse_fit.dual_q.cast<float>());
    coarse_steps = coarse_fit.steps;
  }
  const int steps = level_steps(size, params.max_steps);
  LevelFit fit = admm(problem, std::move(z), split, coarse_steps, steps, finer,
                      progress.range(share, share + (1.0 - share) / 2));
  if (fit.steps == 0 && coarse_steps > 0) {
    // Neither the coarser levels' correction nor the steps from it explain this level better than
    // its start: the level is fitted again from its start.
    split.dual_p.setZero();
    split.dual_q.setZero();
    fit = admm(problem, problem.start, split, 0, steps, finer, progress.range(share + (1.0 - share) / 2, 1.0));
  }
  return fit;
}

// The pixels of `fitted` whose start normal (`depth`'s) is at most `max_slant` degrees from the viewer:
// whose gradient, the differences n(z) reads, is at most tan(max_slant) long.
Mask gentle_pixels(const ImageF& depth, const Mask& mask, const Mask& fitted, double max_slant) {
  if (max_slant >= 90.0) return fitted;
  const double steepest = std::pow(std::tan(max_slant * M_PI / 180.0), 2);
  Mask gentle = fitted;
  for_each_row(int(mask.rows()), [&](int r) {
    for (int c = 0; c < int(mask.cols()); ++c) {
      if (!gentle(r, c)) continue;
      const detail::MaskedGradient g = detail::masked_gradient(depth, mask, r, c);
      gentle(r, c) = mask(r, c) && g.dx * g.dx + g.dy * g.dy <= steepest;
    }
  });
  return gentle;
}

}  // namespace

FitShadingStats fit_shading(ImageF& depth, const ImageF& image, const Mask& mask, const Mask& fitted,
                            const Eigen::Vector3d& light, double albedo, const FitShadingParams& params,
                            const Progress& progress) {
  if (depth.rows() != mask.rows() || depth.cols() != mask.cols() || image.rows() != mask.rows() ||
      image.cols() != mask.cols() || fitted.rows() != mask.rows() || fitted.cols() != mask.cols())
    throw InvalidArgument("shadecut: fit_shading needs depth, image, mask and fitted pixels of one size");
  if (!(albedo > 0.0) || !(light.z() > 0.0) || !(params.smoothness >= 0.0) || params.max_steps < 0 ||
      !(params.max_slant > 0.0 && params.max_slant <= 90.0))
    throw InvalidArgument("shadecut: fit_shading needs albedo > 0, S_z > 0, smoothness >= 0, max_steps >= 0 and a "
                          "max_slant in (0, 90] degrees");
  const Mask fitted_here = gentle_pixels(depth, mask, fitted, params.max_slant);
  // The residual of a float depth as brightness_residual takes it (normals_from_depth's differences),
  // in parallel and without normal maps (which cost as much as the step itself at a megapixel).
  const Eigen::Vector3d direction = light.normalized();
  const auto residual_of = [&](const ImageF& candidate) {
    const Problem whole{image, mask, fitted_here, direction, albedo, 0.0, candidate.cast<double>(), MaskComponents{}};
    return cost_of(whole, whole.start).residual;
  };
  FitShadingStats stats;
  stats.residual_before = stats.residual_after = residual_of(depth);
  if (params.max_steps > 0 && mask.any()) {
    const LevelFit fit = fit_level(depth, image, mask, fitted_here, direction, albedo, params, false, progress);
    // The guarantee, on the float depth returned.
    const ImageF fitted_depth = mask.select(fit.depth.cast<float>(), depth);
    const double residual = residual_of(fitted_depth);
    if (fit.steps > 0 && residual <= stats.residual_before) {
      depth = fitted_depth;
      stats.residual_after = residual;
      stats.steps = fit.steps;
    }
  }
  progress.report(1.0, "fit_shading");
  return stats;
}

}  // namespace shadecut
