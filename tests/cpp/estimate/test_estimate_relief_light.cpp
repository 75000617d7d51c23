// The relief light estimator (LightMethod::Relief) on reliefs whose truth is known.
#include "test_support.hpp"

#include <shadecut/support/errors.hpp>
#include <shadecut/estimate/estimate_light.hpp>
#include <shadecut/pipeline/reconstruct.hpp>
#include <shadecut/support/render.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

namespace shadecut {
namespace {

double degrees(double radians) { return radians * 180.0 / M_PI; }

// The smaller angle between two directions, in degrees.
double direction_difference(double a, double b) { return degrees(std::abs(std::remainder(a - b, 2.0 * M_PI))); }

// The light at `slant` degrees from the viewer and `tilt` degrees from the image's +x (y up).
Eigen::Vector3d light_at(double slant, double tilt) {
  const double s = slant * M_PI / 180.0, t = tilt * M_PI / 180.0;
  return Eigen::Vector3d(std::sin(s) * std::cos(t), std::sin(s) * std::sin(t), std::cos(s));
}

// Paving stones: the cells (Voronoi) of points scattered one per kCell^2 pixels, flat-topped, their
// edges rounded over kEdge pixels down into V-shaped joints kDepth pixels deep (steepest slope
// 2 kDepth / kEdge, 53 degrees): broad tops and narrow grooves, as the estimator assumes. `sign` -1
// turns it inside out (narrow ridges on broad valleys). `painted` multiplies the render by an albedo
// of 0.5 to 1 per cell of a second, independent set of larger cells.
// Distance from `at` to the border of the Voronoi cell it lies in, among `seeds`.
double distance_to_border(const std::vector<Eigen::Vector2d>& seeds, const Eigen::Vector2d& at) {
  double first = INFINITY, second = INFINITY;
  Eigen::Vector2d nearest, next;
  for (const Eigen::Vector2d& seed : seeds) {
    const double d = (seed - at).squaredNorm();
    if (d < first) second = first, next = nearest, first = d, nearest = seed;
    else if (d < second) second = d, next = seed;
  }
  return (second - first) / (2.0 * (next - nearest).norm());
}

// `count` points spread uniformly at random over the square [-margin, size + margin)^2.
std::vector<Eigen::Vector2d> scattered(int size, int margin, int count, unsigned seed) {
  std::mt19937 random(seed);
  auto coordinate = [&] { return -margin + (size + 2.0 * margin) * double(random()) / double(random.max()); };
  std::vector<Eigen::Vector2d> points;
  for (int k = 0; k < count; ++k) points.emplace_back(coordinate(), coordinate());
  return points;
}

testing::Scene stones(int size, const Eigen::Vector3d& light, double sign = 1.0, bool painted = false) {
  constexpr int kCell = 32;
  constexpr double kEdge = 6.0, kDepth = 4.0;
  const int stones_across = size / kCell + 2;
  const std::vector<Eigen::Vector2d> seeds = scattered(size, kCell, stones_across * stones_across, 7),
                                     patches = scattered(size, kCell, stones_across * stones_across / 4, 11);
  testing::Scene scene{ImageF::Zero(size, size), NormalMap(size, size), ImageF::Zero(size, size),
                       Mask::Constant(size, size, true)};
  ImageF paint = ImageF::Ones(size, size);
  for (int r = 0; r < size; ++r) {
    for (int c = 0; c < size; ++c) {
      const Eigen::Vector2d at(c, r);
      const double rounded = 1.0 - std::min(distance_to_border(seeds, at) / kEdge, 1.0);
      scene.depth(r, c) = float(sign * kDepth * (1.0 - rounded * rounded));
      if (!painted) continue;
      std::size_t patch = 0;
      for (std::size_t k = 1; k < patches.size(); ++k)
        if ((patches[k] - at).squaredNorm() < (patches[patch] - at).squaredNorm()) patch = k;
      paint(r, c) = float(0.5 + 0.5 * double((patch * 7919) % 11) / 10.0);
    }
  }
  scene.normals = normals_from_depth(scene.depth, scene.mask);
  scene.image = render_lambertian(scene.normals, light, 0.7, scene.mask) * paint;
  return scene;
}

// Measured: tilt within 6.5 degrees (the stones' joints are not spread evenly over every direction),
// slant 34.2-34.9 for the true 35 (the brightest pixels are the joints' walls that face the light;
// the median, the flat tops).
TEST(EstimateReliefLight, FindsTheTiltAndSlantOfStonesWithNarrowJoints) {
  for (double tilt = -180.0; tilt < 180.0; tilt += 30.0) {
    const Eigen::Vector3d light = light_at(35.0, tilt);
    const testing::Scene scene = stones(192, light);
    const LightEstimate estimate = estimate_light(scene.image, scene.mask, LightMethod::Relief);
    SCOPED_TRACE(::testing::Message() << "tilt " << tilt << ": read slant " << degrees(estimate.slant)
                                      << ", tilt " << degrees(estimate.tilt) << ", albedo " << estimate.albedo);
    EXPECT_LT(direction_difference(estimate.tilt, tilt * M_PI / 180.0), 8.0);
    EXPECT_NEAR(degrees(estimate.slant), 35.0, 2.0);
    EXPECT_NEAR(estimate.albedo, 0.7, 0.05);
    EXPECT_NEAR(estimate.light.norm(), 1.0, 1e-12);
  }
}

TEST(EstimateReliefLight, StonesLitFromTheTopReadAsLitFromTheTop_AndFromBelowAsFromBelow) {
  for (const double tilt : {90.0, -90.0}) {
    const testing::Scene scene = stones(192, light_at(40.0, tilt));
    const LightEstimate estimate = estimate_light(scene.image, scene.mask, LightMethod::Relief);
    EXPECT_LT(direction_difference(estimate.tilt, tilt * M_PI / 180.0), 5.0) << "tilt " << tilt;  // measured 2.5, 3
  }
}

// Paint varies the brightest pixels far more than the shading: their ratio to the median would read
// a grazing light. Measured: tilt within 11.5 degrees, slant 45 (the cap) for the true 35.
TEST(EstimateReliefLight, PaintNeitherTurnsTheTiltNorPushesTheSlantBeyond45Degrees) {
  for (double tilt = -180.0; tilt < 180.0; tilt += 45.0) {
    const testing::Scene scene = stones(192, light_at(35.0, tilt), 1.0, true);
    const LightEstimate estimate = estimate_light(scene.image, scene.mask, LightMethod::Relief);
    EXPECT_LT(direction_difference(estimate.tilt, tilt * M_PI / 180.0), 15.0) << "tilt " << tilt;
    EXPECT_LE(degrees(estimate.slant), 45.0 + 1e-9);
  }
}

// The sphere estimators read a relief as lit nearly from the front.
TEST(EstimateReliefLight, ZhengChellappaIsFarOff) {
  for (double tilt = -180.0; tilt < 180.0; tilt += 90.0) {
    const testing::Scene scene = stones(192, light_at(40.0, tilt));
    const LightEstimate sphere = estimate_light(scene.image, scene.mask, LightMethod::ZhengChellappa);
    EXPECT_LT(degrees(sphere.slant), 40.0 - 20.0);
  }
}

// Lambertian shading cannot tell stones lit from above from their inverse, ridges on broad valleys,
// lit from below: the estimator reads the grooves it assumes, both as stones lit from above.
TEST(EstimateReliefLight, ReadsTheInverseReliefAsStonesLitFromTheOtherSide) {
  const Eigen::Vector3d from_above = light_at(35.0, 80.0), from_below = light_at(35.0, -100.0);
  const testing::Scene relief = stones(192, from_above), inverse = stones(192, from_below, -1.0);
  ASSERT_LT((relief.image - inverse.image).abs().maxCoeff(), 1e-5f);  // the ambiguity is exact
  const LightEstimate estimate = estimate_light(inverse.image, inverse.mask, LightMethod::Relief);
  EXPECT_LT(direction_difference(estimate.tilt, 80.0 * M_PI / 180.0), 8.0);  // measured 5.5
}

TEST(EstimateReliefLight, AGivenAlbedoFixesTheSlant_BeyondTheCapToo) {
  const testing::Scene scene = stones(128, light_at(55.0, 30.0));
  const LightEstimate estimate = estimate_light(scene.image, scene.mask, LightMethod::Relief, 0.7);
  EXPECT_DOUBLE_EQ(estimate.albedo, 0.7);
  EXPECT_NEAR(degrees(estimate.slant), 55.0, 1.0);
}

// The scatter of the tilt over the quadrants: small where every quadrant shows the same stones lit
// the same way, large where nothing but paint varies (measured: 5.0 and 42.5 degrees).
TEST(EstimateReliefLight, ReportsHowMuchItsTiltScattersOverTheImage) {
  const testing::Scene lit = stones(192, light_at(35.0, 20.0));
  const LightEstimate relief = estimate_light(lit.image, lit.mask, LightMethod::Relief);
  // The paint alone: the painted stones' render over the plain stones' (lit from the viewer, > 0).
  const ImageF paint_only = stones(192, Eigen::Vector3d::UnitZ(), 1.0, true).image / stones(192, Eigen::Vector3d::UnitZ()).image;
  const LightEstimate paint = estimate_light(paint_only, lit.mask, LightMethod::Relief, 1.0);
  EXPECT_LT(degrees(relief.uncertainty), 8.0);
  EXPECT_GT(degrees(paint.uncertainty), 20.0);
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
  const testing::Scene scene = stones(64, light_at(35.0, 30.0));
  const Reconstruction result = reconstruct(scene.image, std::nullopt, nullptr, std::nullopt, options);
  const LightEstimate estimate = estimate_light(scene.image, scene.mask, LightMethod::Relief);
  EXPECT_TRUE(result.stats.light_estimated);
  EXPECT_LT((result.light - estimate.light).norm(), 1e-12);
  EXPECT_NEAR(result.albedo, estimate.albedo, 1e-9);
}

}  // namespace
}  // namespace shadecut
