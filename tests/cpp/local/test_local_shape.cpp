#include "test_support.hpp"

#include <shadecut/support/angular_error.hpp>
#include <shadecut/support/errors.hpp>
#include <shadecut/support/light.hpp>
#include <shadecut/local/local_shape.hpp>

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

// kappa reads about L / R = sqrt(pi) = 1.77 on a sphere seen whole, at every resolution and slant, and
// more toward the silhouette (foreshortening): under 1.77 every lit pixel has a tilt, above it only an
// outer ring, of the same share at every size (to 0.06: at 64 px the 2-pixel erosion takes more of
// the ring). A per-pixel gradient threshold left a disc around the brightest point undefined whose
// share grew with the resolution.
TEST(LocalShape, TheTiltIsDefinedOnTheSameShareOfASphereAtEveryResolution) {
  const Eigen::Vector3d light(1, 0, 1);
  const LightFrame frame = LightFrame::from_direction(light);
  for (double min_curvature : {1.0, 2.5}) {
    std::vector<double> shares;
    for (int size : {64, 128, 256}) {
      const testing::Scene scene = testing::sphere_scene(size, 0.45, light);
      // Lit pixels only: an attached shadow has no gradient and never a tilt.
      const Mask lit = erode_mask(scene.mask, 2) && (scene.image > 0.0f);
      const LocalShape local = local_shape(scene.image, scene.mask, frame, 1.0, min_curvature);
      shares.push_back(double((local.tilt_defined && lit).count()) / double(lit.count()));
    }
    const auto [low, high] = std::minmax_element(shares.begin(), shares.end());
    EXPECT_LT(*high - *low, 0.06) << "min_curvature " << min_curvature;
    if (min_curvature < 1.77) EXPECT_GT(*low, 0.95);
    else EXPECT_LT(*high, 0.5);
  }
}

// A plane tilted by the curvature of a sphere 100 object sizes across reads as flat: kappa = 0.01.
TEST(LocalShape, AGentleRampReadsAsFlat) {
  const int size = 32;
  ImageF ramp(size, size);
  const double slope = 0.5 / (100.0 * size);  // |grad I| = sin(s) / (100 L) at s = 30 degrees (I = cos s)
  for (int r = 0; r < size; ++r)
    for (int c = 0; c < size; ++c) ramp(r, c) = float(std::cos(M_PI / 6) + slope * (c - size / 2));
  const Mask all = Mask::Constant(size, size, true);
  const LightFrame frame = LightFrame::from_direction({1, 0, 1});
  EXPECT_FALSE(local_shape(ramp, all, frame, 1.0, 0.02).tilt_defined.any());
  EXPECT_EQ(local_shape(ramp, all, frame, 1.0, 0.005).tilt_defined.count(), size * size);
  EXPECT_THROW(local_shape(ramp, all, frame, 1.0, -1.0), InvalidArgument);
}

}  // namespace
}  // namespace shadecut
