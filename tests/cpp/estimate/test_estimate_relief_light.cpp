// The relief light estimator (LightMethod::Relief) on reliefs whose truth is known.
#include "test_support.hpp"

#include <shadecut/support/errors.hpp>
#include <shadecut/estimate/estimate_light.hpp>
#include <shadecut/pipeline/reconstruct.hpp>
#include <shadecut/support/render.hpp>

#include <gtest/gtest.h>

#include <cmath>

namespace shadecut {
namespace {

double degrees(double radians) { return radians * 180.0 / M_PI; }

// The smaller angle between two axes (directions modulo 180 degrees), in degrees.
double axis_difference(double a, double b) { return degrees(std::abs(std::remainder(a - b, M_PI))); }

// Ripples in twelve directions 15 degrees apart, 10 periods across, phases spread: a relief whose
// height spectrum is the same in every direction, as the estimator assumes. It tiles the image.
// `sign` -1 turns it inside out.
testing::Scene ripples(int size, const Eigen::Vector3d& light, double sign = 1.0) {
  constexpr int kWaves = 12;
  constexpr double kSlopePerWave = 0.12;
  testing::Scene scene{ImageF::Zero(size, size), NormalMap(size, size), ImageF::Zero(size, size),
                       Mask::Constant(size, size, true)};
  for (int r = 0; r < size; ++r) {
    for (int c = 0; c < size; ++c) {
      double z = 0.0, dz_dx = 0.0, dz_dy = 0.0;
      for (int k = 0; k < kWaves; ++k) {
        const double direction = M_PI * k / kWaves;
        const double wx = 2.0 * M_PI * std::round(10.0 * std::cos(direction)) / size;
        const double wy = 2.0 * M_PI * std::round(10.0 * std::sin(direction)) / size;
        const double amplitude = sign * kSlopePerWave / std::hypot(wx, wy);
        const double phase = wx * c + wy * (size - 1 - r) + 2.4 * k;
        z += amplitude * std::cos(phase);
        dz_dx -= amplitude * wx * std::sin(phase);
        dz_dy -= amplitude * wy * std::sin(phase);
      }
      scene.depth(r, c) = float(z);
      scene.normals.xyz.row(Eigen::Index(r) * size + c) = Eigen::Vector3d(-dz_dx, -dz_dy, 1.0).normalized().cast<float>();
    }
  }
  scene.image = render_lambertian(scene.normals, light, 0.7, scene.mask);
  return scene;
}

const Eigen::Vector3d kLights[] = {{0.6, 0.3, 1.0}, {-0.5, 0.4, 1.0}, {0.0, 1.0, 1.0}, {1.0, 0.0, 1.0}, {0.3, 0.8, 0.6}};

// Measured: tilt axis within 8.1 degrees, slant within 4.6, albedo 0.62-0.69. The deviations come
// from the image's departure from the small-slope model (slopes up to about 1 here) and from twelve
// waves being only roughly isotropic.
TEST(EstimateReliefLight, FindsTheTiltAxisAndSlantOfARelief) {
  for (const Eigen::Vector3d& light : kLights) {
    const LightFrame truth = LightFrame::from_direction(light);
    const testing::Scene scene = ripples(192, light);
    const LightEstimate estimate = estimate_light(scene.image, scene.mask, LightMethod::Relief);
    SCOPED_TRACE(::testing::Message() << "light " << light.transpose() << ": slant " << degrees(estimate.slant)
                                      << " (true " << degrees(truth.slant) << "), tilt " << degrees(estimate.tilt)
                                      << " (true " << degrees(truth.tilt) << "), albedo " << estimate.albedo);
    EXPECT_LT(axis_difference(estimate.tilt, truth.tilt), 10.0);
    EXPECT_NEAR(degrees(estimate.slant), degrees(truth.slant), 5.0);
    EXPECT_NEAR(estimate.albedo, 0.7, 0.1);
    EXPECT_NEAR(estimate.light.norm(), 1.0, 1e-12);
  }
}

// The sphere estimators read a relief as lit from the front (measured: slant 0.0 for every light).
TEST(EstimateReliefLight, ZhengChellappaIsFarOff) {
  for (const Eigen::Vector3d& light : kLights) {
    const testing::Scene scene = ripples(192, light);
    const LightEstimate sphere = estimate_light(scene.image, scene.mask, LightMethod::ZhengChellappa);
    EXPECT_LT(degrees(sphere.slant), degrees(LightFrame::from_direction(light).slant) - 25.0);
  }
}

TEST(EstimateReliefLight, TakesTheLightFromAboveSinceARelief_AndItsInverseLitFromBelow_LookAlike) {
  const Eigen::Vector3d from_above(0.3, 0.8, 1.0), from_below(-0.3, -0.8, 1.0);
  const testing::Scene relief = ripples(192, from_above), inverse = ripples(192, from_below, -1.0);
  ASSERT_LT((relief.image - inverse.image).abs().maxCoeff(), 1e-5f);  // the ambiguity is exact
  const LightEstimate estimate = estimate_light(inverse.image, inverse.mask, LightMethod::Relief);
  EXPECT_GE(estimate.light.y(), 0.0);
  EXPECT_LT(axis_difference(estimate.tilt, LightFrame::from_direction(from_above).tilt), 5.0);
}

TEST(EstimateReliefLight, AGivenAlbedoFixesTheSlant) {
  const Eigen::Vector3d light(0.6, 0.3, 1.0);
  const testing::Scene scene = ripples(128, light);
  const LightEstimate estimate = estimate_light(scene.image, scene.mask, LightMethod::Relief, 0.7);
  EXPECT_DOUBLE_EQ(estimate.albedo, 0.7);
  const double median_light_z = estimate.light.z();
  EXPECT_NEAR(degrees(std::acos(median_light_z)), degrees(LightFrame::from_direction(light).slant), 5.0);
}

TEST(EstimateReliefLight, AFlatImageIsLitFromTheViewer) {
  const LightEstimate estimate = estimate_light(ImageF::Constant(32, 32, 0.5f), Mask::Constant(32, 32, true), LightMethod::Relief);
  EXPECT_DOUBLE_EQ(estimate.light.z(), 1.0);
  EXPECT_DOUBLE_EQ(estimate.albedo, 0.5);
}

TEST(EstimateReliefLight, RejectsAReliefDarkInMostPixels) {
  ImageF image = ImageF::Zero(16, 16);
  image.topRows(4).setConstant(1.0f);
  EXPECT_THROW(estimate_light(image, Mask::Constant(16, 16, true), LightMethod::Relief), InvalidArgument);
}

TEST(EstimateReliefLight, IsWhatReconstructUsesForAReliefWithoutALight) {
  ReconstructOptions options;
  EXPECT_EQ(light_method_used(options), LightMethod::ZhengChellappa);
  options.scene = SceneKind::Relief;
  EXPECT_EQ(light_method_used(options), LightMethod::Relief);
  options.light_method = LightMethod::LeeRosenfeld;
  EXPECT_EQ(light_method_used(options), LightMethod::LeeRosenfeld);

  options = ReconstructOptions{};
  options.scene = SceneKind::Relief;
  options.method = Method::LeeRosenfeld;
  options.paint_line_width = 0;  // with paint lines, every stage (the light too) reads them as shadow
  const testing::Scene scene = ripples(64, Eigen::Vector3d(0.6, 0.3, 1.0));
  const Reconstruction result = reconstruct(scene.image, std::nullopt, nullptr, std::nullopt, options);
  const LightEstimate estimate = estimate_light(scene.image, scene.mask, LightMethod::Relief);
  EXPECT_TRUE(result.stats.light_estimated);
  EXPECT_LT((result.light - estimate.light).norm(), 1e-12);
  EXPECT_NEAR(result.albedo, estimate.albedo, 1e-9);
}

}  // namespace
}  // namespace shadecut
