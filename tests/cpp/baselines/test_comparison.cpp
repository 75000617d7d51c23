// The paper's comparison methods (Brooks & Horn, Tsai & Shah) and the light estimators.
#include "test_support.hpp"

#include <shadecut/support/angular_error.hpp>
#include <shadecut/baselines/brooks_horn.hpp>
#include <shadecut/support/errors.hpp>
#include <shadecut/estimate/estimate_light.hpp>
#include <shadecut/pipeline/reconstruct.hpp>
#include <shadecut/baselines/pentland.hpp>
#include <shadecut/baselines/tsai_shah.hpp>
#include <shadecut/support/render.hpp>

#include <gtest/gtest.h>

#include <cmath>

namespace shadecut {
namespace {

double degrees(double radians) { return radians * 180.0 / M_PI; }

double tilt_difference(double a, double b) { return degrees(std::abs(std::remainder(a - b, 2.0 * M_PI))); }

TEST(EstimateLight, ZhengChellappaIsExactOnASphereImage) {
  for (const Eigen::Vector3d& light : {Eigen::Vector3d(1, 0, 1), Eigen::Vector3d(1.5, 0.866, 1),
                                       Eigen::Vector3d(-0.939, 1.867, 1), Eigen::Vector3d(0.3, -0.2, 1)}) {
    const testing::Scene scene = testing::sphere_scene(128, 0.45, light);
    const ImageF image = 0.8f * scene.image;
    const LightFrame truth = LightFrame::from_direction(light);
    const LightEstimate estimate = estimate_light(image, scene.mask, LightMethod::ZhengChellappa);
    EXPECT_LT(tilt_difference(estimate.tilt, truth.tilt), 1.0);
    EXPECT_NEAR(degrees(estimate.slant), degrees(truth.slant), 1.0);
    EXPECT_NEAR(estimate.albedo, 0.8, 0.01);
    EXPECT_NEAR(estimate.light.norm(), 1.0, 1e-12);
  }
}

TEST(EstimateLight, LeeRosenfeldIgnoresTheAttachedShadowSoUnderestimatesObliqueSlants) {
  const Eigen::Vector3d frontal(0, 0, 1), oblique(1.5, 0.866, 1);
  const testing::Scene lit = testing::sphere_scene(128, 0.45, frontal);
  const LightEstimate exact = estimate_light(lit.image, lit.mask, LightMethod::LeeRosenfeld);
  EXPECT_LT(degrees(exact.slant), 3.0);  // no shadow: the model holds
  EXPECT_NEAR(exact.albedo, 1.0, 0.02);
  const testing::Scene shadowed = testing::sphere_scene(128, 0.45, oblique);
  const LightEstimate biased = estimate_light(shadowed.image, shadowed.mask, LightMethod::LeeRosenfeld);
  const LightFrame truth = LightFrame::from_direction(oblique);
  EXPECT_LT(tilt_difference(biased.tilt, truth.tilt), 1.0);
  EXPECT_LT(degrees(biased.slant), degrees(truth.slant) - 10.0);
  EXPECT_LT(biased.albedo, 0.9);
}

TEST(EstimateLight, RejectsBadInput) {
  const Mask all = Mask::Constant(8, 8, true);
  EXPECT_THROW(estimate_light(ImageF::Zero(8, 8), all, LightMethod::LeeRosenfeld), InvalidArgument);
  EXPECT_THROW(estimate_light(ImageF::Constant(8, 8, -1.0f), all, LightMethod::ZhengChellappa), InvalidArgument);
  EXPECT_THROW(estimate_light(ImageF::Ones(1, 8), Mask::Constant(1, 8, true), LightMethod::LeeRosenfeld), InvalidArgument);
  EXPECT_THROW(parse_light_method("pentland"), InvalidArgument);
}

TEST(BrooksHorn, RecoversTheSphereFromItsSilhouette) {
  const Eigen::Vector3d light(1, 0, 1);
  const testing::Scene scene = testing::sphere_scene(128, 0.45, light);
  BrooksHornParams params;
  params.iterations = 2000;
  const BrooksHornResult result = brooks_horn(scene.image, scene.mask, LightFrame::from_direction(light), 1.0, params);
  EXPECT_LT(mean_angular_error(result.normals, scene.normals, erode_mask(scene.mask, 2)), 15.0);
  EXPECT_EQ(result.iterations, 2000);
}

TEST(BrooksHorn, WithoutABoundaryTheFieldAlongTheLightNeverMoves) {
  const Eigen::Vector3d light(1, 0, 1);
  const testing::Scene scene = testing::sphere_scene(64, 0.45, light);
  BrooksHornParams params;
  params.iterations = 50;
  params.tolerance = 1e-6;  // float rounding only
  params.occluding_contour = false;
  const LightFrame frame = LightFrame::from_direction(light);
  const BrooksHornResult result = brooks_horn(scene.image, scene.mask, frame, 1.0, params);
  EXPECT_EQ(result.iterations, 1);  // the first sweep changes nothing
  const Eigen::Index centre = 32 * 64 + 32;
  EXPECT_LT((result.normals.xyz.row(centre).cast<double>().transpose() - frame.direction).norm(), 1e-6);
}

TEST(BrooksHorn, OnlyConvergesForASmoothnessAboveAQuarter) {
  const Eigen::Vector3d light(1, 0, 1);
  const testing::Scene scene = testing::sphere_scene(64, 0.45, light);
  const LightFrame frame = LightFrame::from_direction(light);
  BrooksHornParams params;
  params.iterations = 8000;
  params.tolerance = 1e-5;
  params.smoothness = kStableSmoothness;
  const BrooksHornResult stable = brooks_horn(scene.image, scene.mask, frame, 1.0, params);
  EXPECT_LT(stable.iterations, 2000);
  EXPECT_LT(mean_angular_error(stable.normals, scene.normals, erode_mask(scene.mask, 2)), 15.0);
  params.smoothness = 0.25;
  EXPECT_THROW(brooks_horn(scene.image, scene.mask, frame, 1.0, params), InvalidArgument);
}

TEST(Reconstruct, BrooksHornKeepsSmallObjectsAtTheStableSmoothness) {
  // The default lambda scaled to this 51-px object would be 0.6 (51/128)^2 = 0.095 per pixel.
  const Eigen::Vector3d light(1, 0, 1);
  const testing::Scene scene = testing::sphere_scene(64, 0.45, light);
  ReconstructOptions options;
  options.method = Method::BrooksHorn;
  const Reconstruction result = reconstruct(scene.image, light, &scene.mask, 1.0, options);
  EXPECT_LT(result.stats.iterations, 2000);
  EXPECT_LT(mean_angular_error(result.normals, scene.normals, erode_mask(scene.mask, 2)), 15.0);
}

TEST(TsaiShah, FirstSweepIsOneNewtonStepFromTheFlatSurface) {
  const Eigen::Vector3d light(1, 0.5, 1);
  const testing::Scene scene = testing::sphere_scene(32, 0.45, light);
  const LightFrame frame = LightFrame::from_direction(light);
  const TsaiShahResult result = tsai_shah(scene.image, scene.mask, frame, 1.0, 1);
  // From Z = 0: R = S_z and dR/dZ = -(S_x + S_y), so Z = (E - S_z) / -(S_x + S_y).
  const double expected = (scene.image(16, 16) - frame.direction.z()) / -(frame.direction.x() + frame.direction.y());
  EXPECT_NEAR(result.depth(16, 16), expected, 1e-5);
  EXPECT_EQ(result.depth(0, 0), 0.0f);
  EXPECT_EQ(result.iterations, 1);
}

// Bumps and dents up to 1.5 pixels high, 6 pixels wide (slopes up to about 10 degrees), on 80 x 80, flat
// ground at the frame's edge (where pentland's padding assumes it).
ImageF shallow_relief() {
  ImageF depth = ImageF::Zero(80, 80);
  const double bumps[][3] = {{28, 30, 1.5}, {50, 34, -1.2}, {38, 52, 1.0}, {54, 54, -1.5}, {26, 52, 0.8}};
  for (const auto& bump : bumps)
    for (int r = 0; r < 80; ++r)
      for (int c = 0; c < 80; ++c)
        depth(r, c) += float(bump[2] * std::exp(-((r - bump[0]) * (r - bump[0]) + (c - bump[1]) * (c - bump[1])) / 72.0));
  return depth;
}

TEST(Pentland, ReadsAShallowReliefFromItsShadingAndTheSquareRootBringsTheRest) {
  const Mask mask = Mask::Constant(80, 80, true);
  const NormalMap truth = normals_from_depth(shallow_relief(), mask);
  NormalMap flat(80, 80);
  flat.xyz.col(2).setOnes();
  for (const Eigen::Vector3d light : {Eigen::Vector3d(0.5, 0.3, 1), Eigen::Vector3d(-0.2, -0.6, 1)}) {
    const LightFrame frame = LightFrame::from_direction(light);
    const ImageF image = render_lambertian(truth, frame.direction, 0.8, mask);
    const PentlandResult first_order = pentland(image, mask, frame, 0.8, 0.001, 1);
    const PentlandResult result = pentland(image, mask, frame, 0.8, 0.001, 4);
    const double error = mean_angular_error(normals_from_depth(result.depth, mask), truth, mask);
    // Measured 0.30 and 0.51 degrees against flat's 2.07, and 0.56 and 0.75 after the first-order solve.
    EXPECT_LT(error, 0.3 * mean_angular_error(flat, truth, mask)) << light.transpose();
    EXPECT_LT(error, 0.75 * mean_angular_error(normals_from_depth(first_order.depth, mask), truth, mask)) << light.transpose();
    EXPECT_NEAR(result.depth.mean(), 0.0, 1e-4);
    EXPECT_EQ(result.iterations, 4);
  }
  const LightFrame frame = LightFrame::from_direction(Eigen::Vector3d(0.5, 0.3, 1));
  EXPECT_THROW(pentland(ImageF::Ones(8, 8), Mask::Constant(8, 8, true), frame, 1.0, 0.0, 1), InvalidArgument);
  EXPECT_THROW(pentland(ImageF::Ones(8, 8), Mask::Constant(8, 8, true), frame, 1.0, 0.1, 0), InvalidArgument);
}

TEST(Reconstruct, EveryMethodReportsIterationsHonoursCancellationAndRejectsBadInput) {
  const Eigen::Vector3d light(1, 0, 1);
  const testing::Scene scene = testing::sphere_scene(32, 0.45, light);
  for (const std::string& name : method_names()) {
    ReconstructOptions options;
    options.method = parse_method(name);
    const Reconstruction result = reconstruct(scene.image, light, &scene.mask, 1.0, options);
    EXPECT_GT(result.stats.seconds.at("total"), 0.0) << name;
    EXPECT_EQ(result.stats.iterations > 0, name != "lee_rosenfeld") << name;
    options.progress = [](double, const std::string&) { return false; };
    EXPECT_THROW(reconstruct(scene.image, light, &scene.mask, 1.0, options), Cancelled) << name;
    options.progress = nullptr;
    EXPECT_THROW(reconstruct(ImageF::Zero(32, 32), light, nullptr, std::nullopt, options), InvalidArgument) << name;
    EXPECT_THROW(reconstruct(scene.image, Eigen::Vector3d(1, 0, -1), nullptr, std::nullopt, options), InvalidArgument) << name;
  }
  ReconstructOptions bad;
  bad.method = Method::BrooksHorn;
  bad.smoothness = 0.0;
  EXPECT_THROW(reconstruct(scene.image, light, &scene.mask, 1.0, bad), InvalidArgument);
  bad.method = Method::TsaiShah;
  bad.iterations = 0;
  EXPECT_THROW(reconstruct(scene.image, light, &scene.mask, 1.0, bad), InvalidArgument);
}

TEST(Reconstruct, EstimatesTheLightAndAlbedoWhenNoneIsGiven) {
  const Eigen::Vector3d light(1, 0, 1);
  const testing::Scene scene = testing::sphere_scene(96, 0.45, light);
  const ImageF image = 0.6f * scene.image;
  const Reconstruction given = reconstruct(image, light, &scene.mask, std::nullopt, ReconstructOptions{});
  EXPECT_FALSE(given.stats.light_estimated);
  const Reconstruction estimated = reconstruct(image, std::nullopt, &scene.mask, std::nullopt, ReconstructOptions{});
  EXPECT_TRUE(estimated.stats.light_estimated);
  EXPECT_LT(degrees(std::acos(std::min(1.0, estimated.light.dot(light.normalized())))), 1.0);
  EXPECT_NEAR(estimated.albedo, 0.6, 0.01);
  const Mask inner = erode_mask(scene.mask, 2);
  EXPECT_LT(mean_angular_error(estimated.normals, scene.normals, inner),
            mean_angular_error(given.normals, scene.normals, inner) + 1.0);
}

}  // namespace
}  // namespace shadecut
