// The Poisson integrator's solves (the cosine transform on a whole frame, the iteration on any other
// mask) against the exact least-squares solution of the same system, computed here by a sparse direct
// factorisation, and their independence of the thread count.
#include <shadecut/support/errors.hpp>
#include <shadecut/integrate/integrate.hpp>
#include <shadecut/support/mask_components.hpp>

#include "support/parallel.hpp"

#include <Eigen/SparseCholesky>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

namespace {

using shadecut::ImageF;
using shadecut::Integrator;
using shadecut::Mask;
using shadecut::NormalMap;

// Random unit normals within 60 degrees of the viewer: gradients that no surface has.
NormalMap random_normals(int rows, int cols, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> tilt(-1.0, 1.0);
  NormalMap normals(rows, cols);
  for (Eigen::Index i = 0; i < normals.size(); ++i) {
    const Eigen::Vector3d n = Eigen::Vector3d(tilt(rng), tilt(rng), 1.2).normalized();
    normals.xyz.row(i) = n.cast<float>().transpose();
  }
  return normals;
}

// A disk with two holes, an island inside one of them, a one-pixel component and a thin bar.
Mask holes_and_islands(int rows, int cols) {
  Mask mask(rows, cols);
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) {
      const double x = c - 0.45 * cols, y = r - 0.5 * rows;
      const double hole = std::hypot(c - 0.3 * cols, r - 0.45 * rows);
      bool inside = x * x + y * y < 0.16 * rows * rows && hole > 0.12 * rows && std::hypot(c - 0.55 * cols, r - 0.7 * rows) > 3.0;
      if (hole < 0.05 * rows) inside = true;
      if (c == cols - 2 && r > 2) inside = true;
      mask(r, c) = inside;
    }
  }
  mask(1, 1) = true;
  return mask;
}

// The least-squares depth of the documented system, by Eigen's sparse LDLT: p = -n_x / n_z,
// q = -n_y / n_z, each edge wanting the mean of its ends' gradients; one pixel of each component
// pinned; each component shifted to a minimum of 0.
ImageF direct_poisson(const NormalMap& normals, const Mask& mask) {
  const int rows = normals.rows, cols = normals.cols;
  const shadecut::MaskComponents components = shadecut::mask_components(mask);
  std::vector<int> unknown(std::size_t(rows) * cols, -1);
  std::vector<bool> pinned(std::size_t(components.count), false);
  int count = 0;
  for (int i = 0; i < rows * cols; ++i) {
    const int label = components.labels.data()[i];
    if (label < 0) continue;
    if (pinned[std::size_t(label)]) unknown[std::size_t(i)] = count++;
    pinned[std::size_t(label)] = true;
  }
  auto p = [&](int i) { return -double(normals.xyz(i, 0)) / double(normals.xyz(i, 2)); };
  auto q = [&](int i) { return -double(normals.xyz(i, 1)) / double(normals.xyz(i, 2)); };
  std::vector<Eigen::Triplet<double>> entries;
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(count);
  auto edge = [&](int a, int b, double rise) {
    const int ua = unknown[std::size_t(a)], ub = unknown[std::size_t(b)];
    if (ua >= 0) entries.emplace_back(ua, ua, 1.0), rhs[ua] -= rise;
    if (ub >= 0) entries.emplace_back(ub, ub, 1.0), rhs[ub] += rise;
    if (ua >= 0 && ub >= 0) entries.emplace_back(ua, ub, -1.0), entries.emplace_back(ub, ua, -1.0);
  };
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) {
      const int i = r * cols + c;
      if (!mask(r, c)) continue;
      if (c + 1 < cols && mask(r, c + 1)) edge(i, i + 1, 0.5 * (p(i) + p(i + 1)));
      if (r + 1 < rows && mask(r + 1, c)) edge(i, i + cols, -0.5 * (q(i) + q(i + cols)));
    }
  }
  Eigen::SparseMatrix<double> laplacian(count, count);
  laplacian.setFromTriplets(entries.begin(), entries.end());
  const Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(laplacian);
  const Eigen::VectorXd solution = solver.solve(rhs);

  std::vector<double> minimum(std::size_t(components.count), 0.0);  // the pinned pixel is at 0
  for (int i = 0; i < rows * cols; ++i) {
    if (unknown[std::size_t(i)] >= 0) {
      double& low = minimum[std::size_t(components.labels.data()[i])];
      low = std::min(low, solution[unknown[std::size_t(i)]]);
    }
  }
  ImageF depth = ImageF::Zero(rows, cols);
  for (int i = 0; i < rows * cols; ++i) {
    const int label = components.labels.data()[i];
    if (label >= 0)
      depth.data()[i] = float((unknown[std::size_t(i)] >= 0 ? solution[unknown[std::size_t(i)]] : 0.0) - minimum[std::size_t(label)]);
  }
  return depth;
}

TEST(IntegratePoisson, EqualsTheDirectSparseSolve) {
  struct Case {
    int rows, cols;
    bool full_frame;
  };
  // Whole frames of even and odd sides, and of one and two lines, where the transform's pairing of
  // lines and its reordering of a line's samples each take their other branch.
  for (const Case& shape : {Case{48, 64, false}, Case{97, 61, false}, Case{40, 33, true}, Case{1, 50, true},
                            Case{64, 48, true}, Case{2, 7, true}, Case{33, 1, true}, Case{45, 31, true}}) {
    const NormalMap normals = random_normals(shape.rows, shape.cols, unsigned(shape.rows * 1000 + shape.cols));
    const Mask mask = shape.full_frame ? Mask::Constant(shape.rows, shape.cols, true) : holes_and_islands(shape.rows, shape.cols);
    const ImageF expected = direct_poisson(normals, mask);
    const ImageF depth = shadecut::integrate_normals(normals, mask, Integrator::Poisson);
    const double range = mask.select(expected, 0.0f).maxCoeff();
    ASSERT_GT(range, 1.0);
    const double difference = (depth - expected).abs().maxCoeff();
    EXPECT_LE(difference, 1e-6 * range) << shape.rows << " x " << shape.cols << ", " << mask.count() << " masked";
    EXPECT_TRUE((mask || depth == 0.0f).all()) << "outside the mask the depth is 0";
  }
}

// Large enough (> 2^18 cells) that the finest level runs in parallel.
TEST(IntegratePoisson, OneThreadAndTwoGiveTheSameBits) {
  const NormalMap normals = random_normals(600, 480, 7);
  for (const Mask& mask : {holes_and_islands(600, 480), Mask(Mask::Constant(600, 480, true))}) {
    auto integrate_on = [&](int threads) {
      const shadecut::detail::ThreadCountScope scope(threads);
      return ImageF(shadecut::integrate_normals(normals, mask, Integrator::Poisson));
    };
    EXPECT_TRUE((integrate_on(1) == integrate_on(2)).all()) << mask.count() << " masked";
  }
}

TEST(IntegratePoisson, ReportsProgressAndCanBeCancelled) {
  const NormalMap normals = random_normals(120, 90, 3);
  const Mask mask = holes_and_islands(120, 90);
  std::vector<double> fractions;
  shadecut::integrate_normals(normals, mask, Integrator::Poisson, 10.0,
                              shadecut::Progress([&](double fraction, const std::string& stage) {
                                EXPECT_EQ(stage, "integration");
                                fractions.push_back(fraction);
                                return true;
                              }));
  ASSERT_GE(fractions.size(), 3u);
  EXPECT_TRUE(std::is_sorted(fractions.begin(), fractions.end()));
  EXPECT_DOUBLE_EQ(fractions.back(), 1.0);
  EXPECT_THROW(shadecut::integrate_normals(normals, mask, Integrator::Poisson, 10.0,
                                           shadecut::Progress([](double, const std::string&) { return false; })),
               shadecut::Cancelled);
}

}  // namespace
