// Issue 27: under a light near the viewer the outline decides the orientation, the stats say the
// image could not, and flip_surface gives the other one.
#include "test_support.hpp"

#include <shadecut/pipeline/flip_surface.hpp>
#include <shadecut/pipeline/reconstruct.hpp>
#include <shadecut/support/angular_error.hpp>
#include <shadecut/support/errors.hpp>
#include <shadecut/support/render.hpp>

#include <gtest/gtest.h>

#include <cmath>

namespace shadecut {
namespace {

NormalMap inverted(NormalMap normals) {
  normals.xyz.col(0) *= -1.0f;
  normals.xyz.col(1) *= -1.0f;
  return normals;
}

double error(const NormalMap& normals, const testing::Scene& scene) {
  return mean_angular_error(normals, scene.normals, erode_mask(scene.mask, 2));
}

TEST(Orientation, ASphereLitFromTheViewerIsADomeAndSaidToBeAmbiguous) {
  const Eigen::Vector3d frontal(0, 0, 1);
  const testing::Scene scene = testing::sphere_scene(96, 0.45, frontal);
  const Reconstruction result = reconstruct(scene.image, frontal, &scene.mask, 1.0, ReconstructOptions{});
  EXPECT_LT(error(result.normals, scene), 1.0);
  EXPECT_TRUE(result.stats.orientation_ambiguous);
  EXPECT_GT(result.stats.inverted_energy, result.stats.orientation_energy);
  EXPECT_NEAR(result.stats.inverted_residual / result.stats.orientation_residual, 1.0, 0.05);
}

TEST(Orientation, TheMozartBustLitFromTheViewerIsNotInverted) {
  for (const Eigen::Vector3d& light : {Eigen::Vector3d(0, 0, 1), Eigen::Vector3d(0.0, -0.0524, 1.0)}) {  // slant 3, tilt 270
    const testing::Scene scene = testing::mozart_scene(light);
    const Reconstruction result = reconstruct(scene.image, light, &scene.mask, 1.0, ReconstructOptions{});
    EXPECT_LT(error(result.normals, scene), 0.5 * error(inverted(result.normals), scene)) << light.transpose();
  }
}

TEST(Orientation, ABowlKeepsItsRimUnderAnObliqueLight) {
  const Eigen::Vector3d oblique(0.3, -0.6, 1);  // slant 34 degrees
  const testing::Scene bowl = testing::sphere_scene(96, 0.45, oblique, /*bowl=*/true);
  const Reconstruction result = reconstruct(bowl.image, oblique, &bowl.mask, 1.0, ReconstructOptions{});
  EXPECT_LT(error(result.normals, bowl), 5.0);
  EXPECT_FALSE(result.stats.orientation_ambiguous);
  EXPECT_GT(result.stats.inverted_residual, kAmbiguousResidualRatio * result.stats.orientation_residual);
}

TEST(Orientation, FlipInvertsDepthAndNormalsAndRebasesEachPart) {
  Mask mask = Mask::Constant(12, 20, false);
  mask.block(1, 1, 5, 8).setConstant(true);
  mask.block(7, 10, 4, 9).setConstant(true);
  ImageF depth = ImageF::Zero(12, 20);
  for (int r = 0; r < 12; ++r)
    for (int c = 0; c < 20; ++c)
      if (mask(r, c)) depth(r, c) = float(0.5 * c + 0.25 * r + (c >= 10 ? 7.0 : 0.0));
  const NormalMap normals = normals_from_depth(depth, mask);
  ImageF flipped_depth = depth;
  NormalMap flipped = normals;
  flip_surface(flipped_depth, flipped, mask);
  EXPECT_FLOAT_EQ(flipped_depth.block(1, 1, 5, 8).minCoeff(), 0.0f);
  EXPECT_FLOAT_EQ(flipped_depth.block(7, 10, 4, 9).minCoeff(), 0.0f);
  EXPECT_FLOAT_EQ(flipped_depth(1, 1), float(depth.block(1, 1, 5, 8).maxCoeff() - depth(1, 1)));
  EXPECT_LT((normals_from_depth(flipped_depth, mask).xyz - flipped.xyz).cwiseAbs().maxCoeff(), 1e-6f);
  EXPECT_TRUE((flipped.xyz.col(2).array() == normals.xyz.col(2).array()).all());
  flip_surface(flipped_depth, flipped, mask);
  EXPECT_TRUE((flipped.xyz.array() == normals.xyz.array()).all());
  ImageF small = ImageF::Zero(3, 3);
  EXPECT_THROW(flip_surface(small, flipped, mask), InvalidArgument);
}

}  // namespace
}  // namespace shadecut
