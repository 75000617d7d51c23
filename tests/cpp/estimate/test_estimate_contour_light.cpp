#include "test_support.hpp"

#include <shadecut/estimate/estimate_light.hpp>

#include "estimate/estimate_contour_light.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace shadecut {
namespace {

Eigen::Vector3d light_of(double slant_degrees, double tilt_degrees) {
  const double s = slant_degrees * M_PI / 180.0, t = tilt_degrees * M_PI / 180.0;
  return {std::sin(s) * std::cos(t), std::sin(s) * std::sin(t), std::cos(s)};
}

double degrees_between(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::acos(std::clamp(a.normalized().dot(b.normalized()), -1.0, 1.0)) * 180.0 / M_PI;
}

TEST(EstimateContourLight, ReadsASpheresLightAtItsOutlineNearTheViewerAndAside) {
  for (double slant : {0.0, 2.0, 5.0, 10.0, 20.0}) {
    for (double tilt : {0.0, 100.0, 250.0}) {
      const Eigen::Vector3d light = light_of(slant, tilt);
      const testing::Scene scene = testing::sphere_scene(128, 0.45, light);
      const LightEstimate estimate = estimate_light(scene.image, scene.mask, LightMethod::Contour, 1.0);
      EXPECT_LT(degrees_between(estimate.light, light), slant < 15 ? 1.0 : 2.5) << slant << " " << tilt;
      EXPECT_DOUBLE_EQ(estimate.albedo, 1.0);
      EXPECT_GT(estimate.uncertainty, 0.0);
      EXPECT_LT(estimate.uncertainty, 5.0 * M_PI / 180.0);
    }
  }
}

TEST(EstimateContourLight, WithoutAnOutlineItIsZhengAndChellappasWithNoUncertainty) {
  const testing::Scene scene = testing::sphere_scene(64, 0.45, light_of(20, 30));
  const Mask everything = Mask::Constant(scene.mask.rows(), scene.mask.cols(), true);
  const LightEstimate contour = detail::estimate_contour_light(scene.image, everything, 1.0);
  const LightEstimate reference = estimate_light(scene.image, everything, LightMethod::ZhengChellappa, 1.0);
  EXPECT_TRUE(contour.light.isApprox(reference.light));
  EXPECT_TRUE(std::isnan(contour.uncertainty));
}

}  // namespace
}  // namespace shadecut
