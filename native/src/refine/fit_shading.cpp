#include <shadecut/refine/fit_shading.hpp>

#include <shadecut/support/errors.hpp>
#include <shadecut/support/downsample.hpp>
#include <shadecut/local/local_shape.hpp>
#include <shadecut/support/render.hpp>

#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>

#include <algorithm>
#include <cmath>
#include <tuple>
#include <utility>
#include <vector>

namespace shadecut {

namespace {

using SparseMatrix = Eigen::SparseMatrix<double>;
using Triplets = std::vector<Eigen::Triplet<double>>;

// The linear maps from the masked depth (a vector over the masked pixels, row-major) to what the cost
// reads of it: p = dz/dx and q = dz/dy (y up) as masked_gradient takes them, and the second
// differences along x and y wherever both neighbours are masked.
struct DepthOperators {
  SparseMatrix dx, dy, second;
};

DepthOperators depth_operators(const Mask& mask, const Eigen::ArrayXXi& index, int unknowns) {
  const int rows = int(mask.rows()), cols = int(mask.cols());
  auto at = [&](int r, int c) { return r < 0 || r >= rows || c < 0 || c >= cols || !mask(r, c) ? -1 : index(r, c); };
  Triplets dx, dy, second;
  int second_rows = 0;
  // d/d(step) at pixel i between `before` and `after` (-1 = not masked), as masked_gradient.
  auto difference = [](Triplets& out, int i, int before, int after) {
    if (before >= 0 && after >= 0) {
      out.emplace_back(i, after, 0.5);
      out.emplace_back(i, before, -0.5);
    } else if (after >= 0) {
      out.emplace_back(i, after, 1.0);
      out.emplace_back(i, i, -1.0);
    } else if (before >= 0) {
      out.emplace_back(i, i, 1.0);
      out.emplace_back(i, before, -1.0);
    }
  };
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) {
      const int i = at(r, c);
      if (i < 0) continue;
      const int left = at(r, c - 1), right = at(r, c + 1), down = at(r + 1, c), up = at(r - 1, c);
      difference(dx, i, left, right);
      difference(dy, i, down, up);
      for (const auto [before, after] : {std::pair{left, right}, std::pair{down, up}}) {
        if (before < 0 || after < 0) continue;
        second.emplace_back(second_rows, before, 1.0);
        second.emplace_back(second_rows, i, -2.0);
        second.emplace_back(second_rows, after, 1.0);
        ++second_rows;
      }
    }
  }
  DepthOperators operators{SparseMatrix(unknowns, unknowns), SparseMatrix(unknowns, unknowns),
                           SparseMatrix(second_rows, unknowns)};
  operators.dx.setFromTriplets(dx.begin(), dx.end());
  operators.dy.setFromTriplets(dy.begin(), dy.end());
  operators.second.setFromTriplets(second.begin(), second.end());
  return operators;
}

// The brightness residual rho max(0, n . S) - I of every fitted pixel (0 elsewhere) at depth z, and
// its derivatives with respect to p and q.
struct Shading {
  Eigen::VectorXd residual, by_p, by_q;
  double sum_of_squares = 0.0;
};

Shading shading(const DepthOperators& operators, const Eigen::VectorXd& z, const Eigen::VectorXd& intensity,
                const std::vector<char>& fitted, const Eigen::Vector3d& light, double albedo) {
  const Eigen::VectorXd p = operators.dx * z, q = operators.dy * z;
  Shading s{Eigen::VectorXd::Zero(z.size()), Eigen::VectorXd::Zero(z.size()), Eigen::VectorXd::Zero(z.size())};
  for (Eigen::Index i = 0; i < z.size(); ++i) {
    if (!fitted[std::size_t(i)]) continue;
    const double g2 = 1.0 + p[i] * p[i] + q[i] * q[i], g = std::sqrt(g2);
    const double facing = -p[i] * light.x() - q[i] * light.y() + light.z();  // n . S times g
    const double lit = facing > 0.0 ? facing / g : 0.0;
    s.residual[i] = albedo * lit - intensity[i];
    if (facing > 0.0) {
      // d(facing / g)/dp = (-S_x g^2 - facing p) / g^3, and alike for q.
      s.by_p[i] = albedo * (-light.x() * g2 - facing * p[i]) / (g2 * g);
      s.by_q[i] = albedo * (-light.y() * g2 - facing * q[i]) / (g2 * g);
    }
  }
  s.sum_of_squares = s.residual.squaredNorm();
  return s;
}

// fit_shading at the images' own resolution.
FitShadingStats fit_at_resolution(ImageF& depth, const ImageF& image, const Mask& mask, const Mask& fitted_pixels,
                                  const Eigen::Vector3d& light, double albedo, const FitShadingParams& params,
                                  const Progress& progress) {
  Eigen::ArrayXXi index = Eigen::ArrayXXi::Constant(mask.rows(), mask.cols(), -1);
  int unknowns = 0;
  for (int r = 0; r < mask.rows(); ++r)
    for (int c = 0; c < mask.cols(); ++c)
      if (mask(r, c)) index(r, c) = unknowns++;
  FitShadingStats stats;
  if (unknowns == 0) return stats;
  Eigen::VectorXd z(unknowns), intensity(unknowns);
  std::vector<char> fitted(std::size_t(unknowns), 0);
  for (int r = 0; r < mask.rows(); ++r) {
    for (int c = 0; c < mask.cols(); ++c) {
      const int i = index(r, c);
      if (i < 0) continue;
      z[i] = depth(r, c);
      intensity[i] = image(r, c);
      fitted[std::size_t(i)] = fitted_pixels(r, c);
    }
  }
  const DepthOperators operators = depth_operators(mask, index, unknowns);
  const double mu = params.smoothness * object_size(mask) / kReferenceObjectSize;
  const SparseMatrix smoothing = mu * mu * SparseMatrix(operators.second.transpose() * operators.second);
  const Eigen::VectorXd start = z;
  auto cost_of = [&](const Eigen::VectorXd& depth_vector, double residual) {
    const Eigen::VectorXd correction = depth_vector - start;
    return residual + correction.dot(smoothing * correction);
  };

  Shading current = shading(operators, z, intensity, fitted, light, albedo);
  stats.residual_before = stats.residual_after = current.sum_of_squares;
  double cost = cost_of(z, current.sum_of_squares);
  double damping = 1e-3;
  // The constant of the damping keeps the depth's free offset determined, and puts every diagonal
  // entry in the pattern (an isolated pixel has none otherwise).
  SparseMatrix regularization(unknowns, unknowns);
  regularization.setIdentity();
  regularization *= 1e-9;
  Eigen::SimplicialLDLT<SparseMatrix> solver;
  for (int step = 0; step < params.max_steps; ++step) {
    progress.report(double(step) / params.max_steps, "fit_shading");
    const SparseMatrix jacobian = current.by_p.asDiagonal() * operators.dx + current.by_q.asDiagonal() * operators.dy;
    const SparseMatrix normal = SparseMatrix(jacobian.transpose() * jacobian) + smoothing + regularization;
    const Eigen::VectorXd gradient = jacobian.transpose() * current.residual + smoothing * (z - start);
    // Sparse products keep explicit zeros, so every step's matrix has the pattern of the first.
    if (step == 0) solver.analyzePattern(normal);
    bool improved = false;
    while (damping < 1e8) {
      SparseMatrix damped = normal;  // Levenberg-Marquardt's damping, scaled by the diagonal
      damped.diagonal() += damping * normal.diagonal();
      solver.factorize(damped);
      if (solver.info() != Eigen::Success) throw InvalidArgument("shadecut: fit_shading's linear solve failed");
      const Eigen::VectorXd trial = z - solver.solve(gradient);
      const Shading tried = shading(operators, trial, intensity, fitted, light, albedo);
      const double trial_cost = cost_of(trial, tried.sum_of_squares);
      if (trial_cost < cost && tried.sum_of_squares <= stats.residual_before) {
        const double gain = (cost - trial_cost) / cost;
        z = trial;
        current = tried;
        cost = trial_cost;
        damping = std::max(damping / 3.0, 1e-7);
        improved = gain >= params.tolerance;
        ++stats.steps;
        break;
      }
      damping *= 10.0;
    }
    if (!improved) break;
  }
  stats.residual_after = current.sum_of_squares;
  for (int r = 0; r < mask.rows(); ++r)
    for (int c = 0; c < mask.cols(); ++c)
      if (index(r, c) >= 0) depth(r, c) = float(z[index(r, c)]);
  return stats;
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
        for (const auto [dr, dc] : {std::pair{-1, 0}, std::pair{1, 0}, std::pair{0, -1}, std::pair{0, 1}}) {
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
      for (const auto [rr, cc, w] : {std::tuple{r0, c0, (1 - wy) * (1 - wx)}, std::tuple{r0, c1, (1 - wy) * wx},
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

}  // namespace

FitShadingStats fit_shading(ImageF& depth, const ImageF& image, const Mask& mask, const Mask& fitted,
                            const Eigen::Vector3d& light, double albedo, const FitShadingParams& params,
                            const Progress& progress) {
  if (depth.rows() != mask.rows() || depth.cols() != mask.cols() || image.rows() != mask.rows() ||
      image.cols() != mask.cols() || fitted.rows() != mask.rows() || fitted.cols() != mask.cols())
    throw InvalidArgument("shadecut: fit_shading needs depth, image, mask and fitted pixels of one size");
  if (!(albedo > 0.0) || !(light.z() > 0.0) || !(params.smoothness >= 0.0) || params.max_steps < 0 ||
      !(params.max_object_size >= 8.0))
    throw InvalidArgument("shadecut: fit_shading needs albedo > 0, S_z > 0, smoothness >= 0, max_steps >= 0 and "
                          "max_object_size >= 8");
  const int factor = int(std::ceil(object_size(mask) / params.max_object_size));
  if (factor <= 1) {
    const FitShadingStats stats = fit_at_resolution(depth, image, mask, fitted, light, albedo, params, progress);
    progress.report(1.0, "fit_shading");
    return stats;
  }
  // Too large to fit at its own resolution in reasonable time: the correction, smooth by the model,
  // is fitted on blocks of factor x factor pixels and interpolated back.
  const Downsampled coarse = downsample(image, mask, factor, 1.0);
  const Mask coarse_fitted = downsample(image, fitted, factor, 1.0).mask;
  const ImageF start = downsample(depth, mask, factor, 1.0).image / float(factor);  // pixel units shrink too
  ImageF coarse_depth = start;
  FitShadingStats stats = fit_at_resolution(coarse_depth, coarse.image, coarse.mask, coarse_fitted && coarse.mask, light,
                                            albedo, params, progress.range(0.0, 0.9));
  const ImageF correction =
      upsample((coarse_depth - start) * float(factor), coarse.mask, factor, int(depth.rows()), int(depth.cols()));
  // The guarantee holds at the image's own resolution: the largest share of the correction that does
  // not raise the residual there (none at worst).
  const int coarse_steps = stats.steps;
  stats.residual_before = stats.residual_after = brightness_residual(depth, image, mask, fitted, light, albedo);
  stats.steps = 0;  // until a share of the coarse steps' correction is applied
  for (float share = 1.0f; share >= 0.125f; share *= 0.5f) {
    const ImageF corrected = mask.select(depth + share * correction, depth);
    const double residual = brightness_residual(corrected, image, mask, fitted, light, albedo);
    if (residual <= stats.residual_before) {
      depth = corrected;
      stats.residual_after = residual;
      stats.steps = coarse_steps;
      break;
    }
  }
  progress.report(1.0, "fit_shading");
  return stats;
}

}  // namespace shadecut
