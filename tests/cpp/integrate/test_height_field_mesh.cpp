#include <shadecut/support/errors.hpp>
#include <shadecut/integrate/height_field_mesh.hpp>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <limits>

namespace shadecut {
namespace {

TEST(HeightFieldMesh, OneVertexPerMaskedPixelAndQuadsCounterClockwise) {
  ImageF depth(3, 3);
  depth << 0, 1, 2, 3, 4, 5, 6, 7, 8;
  Mask mask = Mask::Constant(3, 3, true);
  mask(2, 2) = false;
  const HeightFieldMesh mesh = height_field_mesh(depth, mask);
  ASSERT_EQ(mesh.vertices.rows(), 8);
  EXPECT_EQ(mesh.vertices.row(4), Eigen::RowVector3f(1, -1, 4));  // pixel (1, 1)
  EXPECT_EQ(mesh.vertices.row(6), Eigen::RowVector3f(0, -2, 6));  // pixel (2, 0)
  ASSERT_EQ(mesh.quads.rows(), 3);  // the block touching the unmasked corner has no quad
  // top-left, bottom-left, bottom-right, top-right
  EXPECT_EQ(mesh.quads.row(0), (Eigen::Matrix<std::int32_t, 1, 4>() << 0, 3, 4, 1).finished());
  EXPECT_EQ(mesh.quads.row(2), (Eigen::Matrix<std::int32_t, 1, 4>() << 3, 6, 7, 4).finished());
  // Counter-clockwise seen from +z: the cross product of two edges points toward the viewer.
  const Eigen::Vector3f a = mesh.vertices.row(0), b = mesh.vertices.row(3), c = mesh.vertices.row(4);
  EXPECT_GT((b - a).cross(c - a).z(), 0.0f);
  EXPECT_FLOAT_EQ(mesh.uvs(4, 0), 0.5f);
  EXPECT_FLOAT_EQ(mesh.uvs(4, 1), 0.5f);
  EXPECT_FLOAT_EQ(mesh.uvs(0, 1), 1.0f - 0.5f / 3.0f);
}

TEST(HeightFieldMesh, SamplesEveryStepPixels) {
  const ImageF depth = ImageF::Zero(5, 5);
  const HeightFieldMesh mesh = height_field_mesh(depth, Mask::Constant(5, 5, true), 2);
  EXPECT_EQ(mesh.vertices.rows(), 9);  // rows and columns 0, 2, 4
  EXPECT_EQ(mesh.quads.rows(), 4);
  EXPECT_EQ(mesh.vertices.row(8), Eigen::RowVector3f(4, -4, 0));
}

TEST(HeightFieldMesh, RejectsBadInput) {
  ImageF depth = ImageF::Zero(3, 3);
  EXPECT_THROW(height_field_mesh(depth, Mask::Constant(3, 3, true), 0), InvalidArgument);
  EXPECT_THROW(height_field_mesh(depth, Mask::Constant(2, 3, true)), InvalidArgument);
  depth(1, 1) = std::numeric_limits<float>::quiet_NaN();
  EXPECT_THROW(height_field_mesh(depth, Mask::Constant(3, 3, true)), InvalidArgument);
  Mask around = Mask::Constant(3, 3, true);
  around(1, 1) = false;  // a NaN outside the mask is never read
  EXPECT_EQ(height_field_mesh(depth, around).vertices.rows(), 8);
}

}  // namespace
}  // namespace shadecut
