#include "test_support.hpp"

#include <shadecut/angular_error.hpp>
#include <shadecut/errors.hpp>
#include <shadecut/light.hpp>
#include <shadecut/local_shape.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace shadecut {
namespace {

const Eigen::Vector3d kPaperLights[] = {{1.0, 0.0, 1.0}, {1.5, 0.866, 1.0}, {-0.939, 1.867, 1.0}};

TEST(LightFrame, MapsTheLightFrameZAxisOntoTheLight) {
  for (const Eigen::Vector3d& light : kPaperLights) {
    const LightFrame frame = LightFrame::from_direction(light);
    EXPECT_NEAR((frame.normal(0.0, 0.0) - light.normalized()).norm(), 0.0, 1e-12);
    EXPECT_NEAR(frame.normal(0.7, 2.0).dot(frame.direction), std::cos(0.7), 1e-12);
  }
}

TEST(LightFrame, RejectsZeroNonFiniteAndBelowHorizonLights) {
  EXPECT_THROW(LightFrame::from_direction({0, 0, 0}), InvalidArgument);
  EXPECT_THROW(LightFrame::from_direction({std::nan(""), 0, 1}), InvalidArgument);
  EXPECT_THROW(LightFrame::from_direction({1, 0, 0}), InvalidArgument);
  EXPECT_THROW(LightFrame::from_direction({1, 0, -1}), InvalidArgument);
}

TEST(LocalShape, ConvexCandidateMatchesTheSphereWithinHalfADegreeMedian) {
  for (const Eigen::Vector3d& light : kPaperLights) {
    const testing::Scene scene = testing::sphere_scene(128, 0.45, light);
    const LightFrame frame = LightFrame::from_direction(light);
    const LocalShape local = local_shape(scene.image, scene.mask, frame, 1.0, 1e-3);
    const NormalMap convex = convex_normals(local, frame, scene.mask);
    const Mask eroded = erode_mask(scene.mask, 2);
    const ImageF errors = angular_error_map(convex, scene.normals, eroded);
    std::vector<float> values;
    for (Eigen::Index i = 0; i < errors.size(); ++i)
      if (eroded.data()[i]) values.push_back(errors.data()[i]);
    std::nth_element(values.begin(), values.begin() + values.size() / 2, values.end());
    EXPECT_LT(values[values.size() / 2], 0.5) << "light " << light.transpose();
  }
}

TEST(LocalShape, SlantComesFromBrightnessAndTiltIsUndefinedOnAFlatImage) {
  const ImageF flat = ImageF::Constant(8, 8, 0.5f);
  const Mask all = Mask::Constant(8, 8, true);
  const LocalShape local = local_shape(flat, all, LightFrame::from_direction({1, 0, 1}), 1.0, 1e-3);
  EXPECT_NEAR(local.slant(3, 3), std::acos(0.5), 1e-6);
  EXPECT_FALSE(local.tilt_defined.any());
}

}  // namespace
}  // namespace shadecut
