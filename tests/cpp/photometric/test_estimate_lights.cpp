// Uncalibrated photometric stereo against the lights the photographs were rendered under.
#include "photometric/photometric_scenes.hpp"

#include <shadecut/photometric/estimate_lights.hpp>
#include <shadecut/support/errors.hpp>

#include <gtest/gtest.h>

namespace shadecut {
namespace {

using testing::lights_around;

double degrees(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::acos(std::clamp(a.normalized().dot(b.normalized()), -1.0, 1.0)) * 180.0 / M_PI;
}

TEST(EstimatePhotometricLights, FourLightsAroundASphereAtOneSlant) {
  const auto scene = testing::sphere_scene(128, 0.45, {0, 0, 1});
  const LightDirections lights = lights_around(4, 40.0, 90.0, 90.0);
  const auto images = testing::photographs(scene, lights, testing::painted_albedo(128, 128));
  LightHint hint;
  hint.slant = 40.0;
  const PhotometricLights estimate = estimate_photometric_lights(images, scene.mask, hint);
  for (Eigen::Index k = 0; k < 4; ++k)
    EXPECT_LT(degrees(estimate.lights.row(k).transpose(), lights.row(k).transpose()), 2.0)
        << "light " << k << ": " << estimate.lights.row(k) << " uncertainty " << estimate.uncertainty[std::size_t(k)];
  EXPECT_GT(estimate.pixels, 1000);
}

TEST(EstimatePhotometricLights, UnevenTiltsComeFromThePhotographsTheSlantFromTheHint) {
  const auto scene = testing::sphere_scene(128, 0.45, {0, 0, 1});
  LightDirections lights(5, 3);
  const double tilts[5] = {95.0, 160.0, 230.0, 290.0, 20.0};
  for (int k = 0; k < 5; ++k) lights.row(k) = lights_around(1, 35.0, tilts[k], 0.0).row(0);
  const auto images = testing::photographs(scene, lights, testing::painted_albedo(128, 128));
  LightHint hint;
  hint.slant = 45.0;  // ten degrees off
  const PhotometricLights estimate = estimate_photometric_lights(images, scene.mask, hint);
  for (Eigen::Index k = 0; k < 5; ++k) {
    const Eigen::Vector3d found = estimate.lights.row(k).transpose();
    const double tilt = std::atan2(found.y(), found.x()) * 180.0 / M_PI;
    EXPECT_LT(std::abs(std::remainder(tilt - tilts[k], 360.0)), 2.0) << "light " << k << ": " << found.transpose();
    EXPECT_LT(degrees(found, lights.row(k).transpose()), 12.0) << "light " << k;
  }
}

TEST(EstimatePhotometricLights, RefusesWhatCannotBeEstimated) {
  const auto scene = testing::sphere_scene(64, 0.45, {0, 0, 1});
  const LightDirections lights = lights_around(4, 40.0, 90.0, 90.0);
  const auto images = testing::photographs(scene, lights, ImageF::Ones(64, 64));
  EXPECT_THROW(estimate_photometric_lights({images[0], images[1], images[2]}, scene.mask), InvalidArgument);
  LightHint none;
  none.same_slant = false;
  EXPECT_THROW(estimate_photometric_lights(images, scene.mask, none), InvalidArgument);
  std::vector<ImageF> dark(4, ImageF::Zero(64, 64));
  EXPECT_THROW(estimate_photometric_lights(dark, scene.mask), InvalidArgument);
}

}  // namespace
}  // namespace shadecut
