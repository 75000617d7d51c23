// How far photographs are from a surface: nothing where the surface and its paint explain them, the
// excess where one photograph holds what they do not.
#include "photometric/photometric_scenes.hpp"

#include <shadecut/photometric/residual_map.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace shadecut {
namespace {

using testing::lights_around;

std::vector<Eigen::Vector3d> directions(const LightDirections& lights) {
  std::vector<Eigen::Vector3d> unit;
  for (Eigen::Index k = 0; k < lights.rows(); ++k) unit.push_back(lights.row(k).transpose().normalized());
  return unit;
}

TEST(ResidualMap, IsZeroWherePaintAndSurfaceExplainThePhotographs) {
  const testing::Scene scene = testing::sphere_scene(64, 0.45, {0, 0, 1});
  const LightDirections lights = lights_around(3, 40.0, 90.0, 120.0);
  const ImageF albedo = testing::painted_albedo(64, 64);
  const ImageF residual = residual_map(testing::photographs(scene, lights, albedo), directions(lights), NearLamps{},
                                       scene.normals, albedo, scene.mask);
  EXPECT_LT(residual.maxCoeff(), 1e-6f);
}

TEST(ResidualMap, IsTheRmsOfWhatOnePhotographHoldsBeyondTheSurface) {
  const testing::Scene scene = testing::sphere_scene(64, 0.45, {0, 0, 1});
  const ImageF albedo = testing::painted_albedo(64, 64);
  for (const int count : {1, 4}) {
    const LightDirections lights = lights_around(count, 30.0, 90.0, 360.0 / count);
    std::vector<ImageF> images = testing::photographs(scene, lights, albedo);
    const int highlight = 32 * 64 + 32;  // the centre, inside the mask
    images.front().data()[highlight] += 0.2f;
    const ImageF residual = residual_map(images, directions(lights), NearLamps{}, scene.normals, albedo, scene.mask);
    EXPECT_NEAR(residual.data()[highlight], 0.2 / std::sqrt(double(count)), 1e-6) << count << " photographs";
    EXPECT_EQ((residual.array() > 1e-6f).count(), 1) << count << " photographs";
    EXPECT_TRUE((residual.array() >= 0.0f).all() && (scene.mask.select(ImageF::Zero(64, 64), residual).array() == 0.0f).all());
  }
}

}  // namespace
}  // namespace shadecut
