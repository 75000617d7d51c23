#include "test_support.hpp"

#include <shadecut/integrate/shadow_fill.hpp>
#include <shadecut/support/angular_error.hpp>

#include "support/contour.hpp"

#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

namespace shadecut {
namespace {

// The harmonic fill computed the plain way, as fill_normals did before it used the multigrid solve:
// the same system (a graph Laplacian on the pixels to fill, each known masked neighbour pulling with
// weight 1, a pull of 1e-6 toward the current normal), factorized by Eigen's sparse Cholesky.
// `fixed` are the pixels fill_normals set on the outline, which the solve reads as known.
NormalMap direct_fill(NormalMap normals, const Mask& fill, const Mask& mask, const Mask& fixed) {
  const int rows = int(mask.rows()), cols = int(mask.cols());
  std::vector<int> index(std::size_t(rows * cols), -1), unknowns;
  for (int p = 0; p < rows * cols; ++p)
    if (mask.data()[p] && fill.data()[p] && !fixed.data()[p]) {
      index[std::size_t(p)] = int(unknowns.size());
      unknowns.push_back(p);
    }
  const int m = int(unknowns.size());
  std::vector<Eigen::Triplet<double>> triplets;
  Eigen::MatrixX2d rhs(m, 2);
  for (int i = 0; i < m; ++i) {
    const int p = unknowns[std::size_t(i)], r = p / cols, c = p % cols;
    double diagonal = 1e-6;
    rhs.row(i) = 1e-6 * normals.xyz.row(p).head<2>().cast<double>();
    for (const auto& [rr, cc] : {std::pair{r, c - 1}, {r, c + 1}, {r - 1, c}, {r + 1, c}}) {
      if (rr < 0 || cc < 0 || rr >= rows || cc >= cols || !mask(rr, cc)) continue;
      const int q = rr * cols + cc;
      diagonal += 1.0;
      if (index[std::size_t(q)] >= 0) triplets.emplace_back(i, index[std::size_t(q)], -1.0);
      else rhs.row(i) += normals.xyz.row(q).head<2>().cast<double>();
    }
    triplets.emplace_back(i, i, diagonal);
  }
  Eigen::SparseMatrix<double> laplacian(m, m);
  laplacian.setFromTriplets(triplets.begin(), triplets.end());
  const Eigen::MatrixX2d solved = Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>>(laplacian).solve(rhs);
  for (int i = 0; i < m; ++i) {
    Eigen::Vector2d planar = solved.row(i).transpose();
    if (planar.norm() > 1.0) planar.normalize();
    normals.xyz.row(unknowns[std::size_t(i)]) << float(planar.x()), float(planar.y()),
        float(std::sqrt(std::max(0.0, 1.0 - planar.squaredNorm())));
  }
  return normals;
}

TEST(ShadowFill, RecoversASpheresAttachedShadowAndEqualsTheDirectSolve) {
  const Eigen::Vector3d light(1, 0, 1);
  const testing::Scene scene = testing::sphere_scene(160, 0.45, light);
  const Mask shadow = scene.mask && scene.image <= 0.0f;
  ASSERT_GT(shadow.count(), 2000);
  Mask outline = Mask::Constant(shadow.rows(), shadow.cols(), false);
  for (int r = 0; r < shadow.rows(); ++r)
    for (int c = 0; c < shadow.cols(); ++c)
      outline(r, c) = shadow(r, c) && !detail::contour_outward(scene.mask, r, c).isZero();
  NormalMap filled = scene.normals;
  EXPECT_EQ(fill_normals(filled, shadow, scene.mask, true), shadow.count() - outline.count());
  NormalMap start = scene.normals;  // with the outline's normals fill_normals set
  for (Eigen::Index i = 0; i < outline.size(); ++i)
    if (outline.data()[i]) start.xyz.row(i) = filled.xyz.row(i);
  const NormalMap direct = direct_fill(start, shadow, scene.mask, outline);
  // A sphere's x and y are harmonic: what is off is the outline's, a unit vector in the image plane
  // at pixel centres half a pixel inside the true rim, steepest where z is found from x and y.
  const Mask inner = shadow && erode_mask(scene.mask, 2);
  const double error = mean_angular_error(filled, scene.normals, inner);
  std::printf("sphere's shadow filled: %.3f deg off the truth (direct solve %.3f)\n", error,
              mean_angular_error(direct, scene.normals, inner));
  EXPECT_LT(error, 5.0);  // measured 4.26
  EXPECT_LT((filled.xyz - direct.xyz).cwiseAbs().maxCoeff(), 1e-4f);
}

TEST(ShadowFill, WithoutAnOutlineAndInARegionWithNoKnownNeighbourItEqualsTheDirectSolve) {
  // A relief's dark band across the frame (no occluding contour), and a masked island wholly in
  // shadow, held only by the faint pull toward its current normals.
  const testing::Scene scene = testing::bumps_scene(96, Eigen::Vector3d(0.7, 0.2, 1));
  Mask mask = Mask::Constant(96, 96, true);
  for (int r = 0; r < 96; ++r) mask(r, 60) = false;
  Mask fill = Mask::Constant(96, 96, false);
  fill.block(30, 0, 12, 60) = true;
  fill.block(0, 61, 96, 35) = true;
  NormalMap filled = scene.normals;
  fill_normals(filled, fill, mask, false);
  const NormalMap direct = direct_fill(scene.normals, fill, mask, Mask::Constant(96, 96, false));
  EXPECT_LT((filled.xyz - direct.xyz).cwiseAbs().maxCoeff(), 1e-4f);
}

TEST(ShadowFill, ScatteredRegionsEachSolvedInTheirOwnBoxEqualTheDirectSolve) {
  // Attached shadows as a bump field has them: many small regions over the frame, single pixels
  // among them, one touching the frame's corner; the direct solve takes them as one system.
  const testing::Scene scene = testing::bumps_scene(80, Eigen::Vector3d(0.7, 0.2, 1));
  const Mask mask = Mask::Constant(80, 80, true);
  Mask fill = Mask::Constant(80, 80, false);
  for (int r = 0; r < 80; ++r)
    for (int c = 0; c < 80; ++c) fill(r, c) = (7 * r + 13 * c) % 29 == 0;
  fill.block(10, 20, 3, 5) = true;
  fill.block(50, 5, 6, 2) = true;
  fill.block(0, 0, 2, 2) = true;
  NormalMap filled = scene.normals;
  EXPECT_EQ(fill_normals(filled, fill, mask, false), fill.count());
  const NormalMap direct = direct_fill(scene.normals, fill, mask, Mask::Constant(80, 80, false));
  EXPECT_LT((filled.xyz - direct.xyz).cwiseAbs().maxCoeff(), 1e-4f);
}

}  // namespace
}  // namespace shadecut
