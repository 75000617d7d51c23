#include "test_support.hpp"

#include <shadecut/support/angular_error.hpp>
#include <shadecut/support/errors.hpp>
#include <shadecut/pipeline/reconstruct.hpp>
#include <shadecut/support/render.hpp>
#include <shadecut/integrate/shadow_fill.hpp>

#include <gtest/gtest.h>

#include <limits>
#include <string>
#include <optional>

namespace shadecut {
namespace {

TEST(Reconstruct, GraphCutRecoversSphereAndBowl) {
  const Eigen::Vector3d light(1, 0, 1);
  for (bool bowl : {false, true}) {
    const testing::Scene scene = testing::sphere_scene(128, 0.45, light, bowl);
    const Reconstruction result = reconstruct(scene.image, light, &scene.mask, 1.0, ReconstructOptions{});
    EXPECT_LT(mean_angular_error(result.normals, scene.normals, erode_mask(scene.mask, 2)), bowl ? 5.0 : 3.0);
    EXPECT_FLOAT_EQ(result.depth(0, 0), 0.0f);  // outside the mask
  }
}

// An object small in a large frame is reconstructed in a window around its mask and put back: the
// same surface as the object alone, nothing outside the mask.
TEST(Reconstruct, AnObjectInALargeFrameIsTheObjectAlone) {
  const Eigen::Vector3d light(0.4, 0.7, 1);
  const testing::Scene scene = testing::sphere_scene(96, 0.45, light);
  const int top = 301, left = 517, size = 900;
  ImageF image = ImageF::Zero(size, size);
  Mask mask = Mask::Constant(size, size, false);
  image.block(top, left, 96, 96) = scene.image;
  mask.block(top, left, 96, 96) = scene.mask;
  const Reconstruction alone = reconstruct(scene.image, light, &scene.mask, 1.0, ReconstructOptions{});
  const Reconstruction framed = reconstruct(image, light, &mask, 1.0, ReconstructOptions{});
  ASSERT_EQ(framed.depth.rows(), size);
  EXPECT_TRUE((framed.mask == mask).all());
  EXPECT_LT((framed.depth.block(top, left, 96, 96) - alone.depth).abs().maxCoeff(), 1e-3f);
  EXPECT_TRUE((mask.select(0.0f, framed.depth) == 0.0f).all());
  for (int r = 0; r < 96; ++r)
    for (int c = 0; c < 96; ++c)
      EXPECT_LT((framed.normals.xyz.row(Eigen::Index(top + r) * size + left + c) - alone.normals.xyz.row(Eigen::Index(r) * 96 + c))
                    .cwiseAbs()
                    .maxCoeff(),
                1e-5f);
}

// A given albedo below much of the image is named; the true one, or one estimated, is not.
TEST(Reconstruct, AnAlbedoBelowTheImageIsNamed) {
  const Eigen::Vector3d light(0.4, 0.3, 1);
  const testing::Scene scene = testing::sphere_scene(96, 0.45, light);
  const Reconstruction low = reconstruct(scene.image, light, &scene.mask, 0.5, ReconstructOptions{});
  const double above = double((scene.mask && scene.image > 0.5f).count()) / double(scene.mask.count());
  EXPECT_DOUBLE_EQ(low.stats.brighter_than_albedo, above);
  EXPECT_NE(low.stats.albedo_message.find("brighter than the albedo given (0.500)"), std::string::npos);
  const Reconstruction right = reconstruct(scene.image, light, &scene.mask, 1.0, ReconstructOptions{});
  EXPECT_EQ(right.stats.brighter_than_albedo, 0.0);
  EXPECT_TRUE(right.stats.albedo_message.empty());
  const Reconstruction estimated = reconstruct(scene.image, light, &scene.mask, std::nullopt, ReconstructOptions{});
  EXPECT_TRUE(estimated.stats.albedo_message.empty());
}

// Every parallel loop writes its own pixels and every sum is taken in a fixed order, so the thread
// count changes no bit of the result, for each method.
TEST(Reconstruct, OneThreadAndTwoGiveTheSameBits) {
  const Eigen::Vector3d light(0.7, 0.2, 1);
  const testing::Scene scene = testing::sphere_scene(600, 0.45, light);  // parallel integration from 2^18 pixels
  for (Method method : {Method::GraphCut, Method::LeeRosenfeld, Method::BrooksHorn, Method::TsaiShah, Method::Upwind}) {
    ReconstructOptions options;
    options.method = method;
    options.iterations = method == Method::BrooksHorn ? std::optional<int>(50) : std::nullopt;
    options.threads = 1;
    const Reconstruction one = reconstruct(scene.image, light, &scene.mask, 1.0, options);
    options.threads = 2;
    const Reconstruction two = reconstruct(scene.image, light, &scene.mask, 1.0, options);
    EXPECT_TRUE((one.normals.xyz.array() == two.normals.xyz.array()).all()) << to_string(method);
    EXPECT_TRUE((one.depth == two.depth).all()) << to_string(method);
    EXPECT_TRUE((one.residual == two.residual).all()) << to_string(method);
  }
}

// The methods can find slants beyond 90 degrees; what reconstruct returns is a height field's normals.
TEST(Reconstruct, NoMethodReturnsANormalFacingAway) {
  const Eigen::Vector3d light(-0.939, 1.867, 1);
  const testing::Scene scene = testing::sphere_scene(96, 0.45, light);
  for (const std::string& name : method_names()) {
    const Method method = parse_method(name);
    ReconstructOptions options;
    options.method = method;
    const Reconstruction result = reconstruct(scene.image, light, &scene.mask, 1.0, options);
    EXPECT_GE(result.normals.xyz.col(2).minCoeff(), 0.0f) << to_string(method);
  }
}

TEST(Reconstruct, ProgressReachesOneAndCanCancel) {
  const Eigen::Vector3d light(1, 0, 1);
  const testing::Scene scene = testing::sphere_scene(48, 0.45, light);
  ReconstructOptions options;
  double last = -1.0;
  bool monotone = true;
  options.progress = [&](double fraction, const std::string&) {
    monotone = monotone && fraction >= last;
    last = fraction;
    return true;
  };
  reconstruct(scene.image, light, &scene.mask, std::nullopt, options);
  EXPECT_TRUE(monotone);
  EXPECT_DOUBLE_EQ(last, 1.0);
  options.progress = [](double, const std::string& stage) { return stage != "graphcut"; };
  EXPECT_THROW(reconstruct(scene.image, light, &scene.mask, std::nullopt, options), Cancelled);
}

// Seamless output of a relief that fills the frame: the depth steps across the image's edges no more
// than between neighbours inside, and the normals are as near the truth as without the option.
TEST(Reconstruct, SeamlessReliefTilesAndKeepsItsShape) {
  const Eigen::Vector3d light(0.6, 0.3, 1.0);
  const testing::Scene scene = testing::bumps_scene(128, light);
  ReconstructOptions relief;
  relief.scene = SceneKind::Relief;
  ReconstructOptions seamless = relief;
  seamless.seamless = true;
  const Reconstruction plain = reconstruct(scene.image, light, nullptr, 1.0, relief);
  const Reconstruction tiled = reconstruct(scene.image, light, nullptr, 1.0, seamless);
  const auto [seam, inner] = testing::seam_and_inner_steps(tiled.depth);
  EXPECT_LE(seam, inner);
  const double plain_error = mean_angular_error(plain.normals, scene.normals, scene.mask);
  const double tiled_error = mean_angular_error(tiled.normals, scene.normals, scene.mask);
  // Measured: 18.64 deg without, 16.14 deg with (normals from the integrated depth are smoother);
  // seam step 0.32 px against 0.85 px inside.
  RecordProperty("relief_error", std::to_string(plain_error));
  RecordProperty("seamless_error", std::to_string(tiled_error));
  EXPECT_LE(tiled_error, plain_error);
}

// The pull toward the viscosity solution is a second candidate: the labelling kept is the one whose
// integrated depth renders closer to the image (at one level and without fit_shading, the depth
// reconstruct returns), and on the test bumps, where the paper's energy picks a wrong surface, that
// is the pulled one, much nearer the truth.
TEST(Reconstruct, TheViscosityPullKeepsTheSurfaceThatExplainsTheImageBetter) {
  const Eigen::Vector3d light(1, 0, 1);
  for (const bool bumps : {true, false}) {
    const testing::Scene scene = bumps ? testing::bumps_scene(96, light) : testing::sphere_scene(96, 0.45, light);
    ReconstructOptions options;
    options.coarse_to_fine_band = -1;
    options.fit_shading = false;
    options.viscosity_weight = 0.0;
    const Reconstruction paper = reconstruct(scene.image, light, &scene.mask, 1.0, options);
    EXPECT_FALSE(paper.stats.pulled_kept);
    options.viscosity_weight = 0.3;
    const Reconstruction chosen = reconstruct(scene.image, light, &scene.mask, 1.0, options);
    const Mask counted = scene.mask && !unreliable_pixels(scene.image, scene.mask, 1.0, options.shadow_threshold,
                                                          highlight_threshold_used(options));
    auto residual = [&](const ImageF& depth) {
      return brightness_residual(depth, scene.image, scene.mask, counted, light, 1.0) / double(counted.count());
    };
    EXPECT_NEAR(chosen.stats.paper_residual, residual(paper.depth), 1e-9);
    EXPECT_NEAR(residual(chosen.depth), std::min(chosen.stats.paper_residual, chosen.stats.pulled_residual), 1e-9);
    EXPECT_EQ(chosen.stats.pulled_kept, chosen.stats.pulled_residual < chosen.stats.paper_residual);
    EXPECT_GT(chosen.stats.seconds.at("upwind"), 0.0);
    const Mask inner = erode_mask(scene.mask, 2);
    const double before = mean_angular_error(paper.normals, scene.normals, inner);
    const double after = mean_angular_error(chosen.normals, scene.normals, inner);
    if (bumps) {
      EXPECT_TRUE(chosen.stats.pulled_kept);
      EXPECT_LT(after, 0.5 * before) << before << " -> " << after;
    } else {
      EXPECT_LE(after, before + 0.5) << before << " -> " << after;
    }
  }
}

TEST(Reconstruct, RejectsBadInput) {
  const Eigen::Vector3d light(1, 0, 1);
  const testing::Scene scene = testing::sphere_scene(16, 0.45, light);
  const ReconstructOptions defaults;
  EXPECT_THROW(reconstruct(ImageF::Zero(1, 1), light, nullptr, std::nullopt, defaults), InvalidArgument);
  EXPECT_THROW(reconstruct(ImageF::Zero(0, 0), light, nullptr, std::nullopt, defaults), InvalidArgument);
  ImageF with_nan = scene.image;
  with_nan(3, 3) = std::numeric_limits<float>::quiet_NaN();
  EXPECT_THROW(reconstruct(with_nan, light, nullptr, std::nullopt, defaults), InvalidArgument);
  const Mask wrong_shape = Mask::Constant(15, 16, true);
  EXPECT_THROW(reconstruct(scene.image, light, &wrong_shape, std::nullopt, defaults), InvalidArgument);
  EXPECT_THROW(reconstruct(scene.image, Eigen::Vector3d(0, 0, 0), nullptr, std::nullopt, defaults), InvalidArgument);
  EXPECT_THROW(reconstruct(scene.image, Eigen::Vector3d(1, 0, -0.5), nullptr, std::nullopt, defaults), InvalidArgument);
  EXPECT_THROW(reconstruct(ImageF::Zero(16, 16), light, nullptr, std::nullopt, defaults), InvalidArgument);
  ReconstructOptions few_labels;
  few_labels.labels = 3;
  EXPECT_THROW(reconstruct(scene.image, light, &scene.mask, std::nullopt, few_labels), InvalidArgument);
  ReconstructOptions seamless_object;
  seamless_object.seamless = true;
  EXPECT_THROW(reconstruct(scene.image, light, nullptr, std::nullopt, seamless_object), InvalidArgument);
  ReconstructOptions seamless_relief = seamless_object;
  seamless_relief.scene = SceneKind::Relief;
  EXPECT_THROW(reconstruct(scene.image, light, &scene.mask, std::nullopt, seamless_relief), InvalidArgument);
  for (const double weight : {-1.0, std::numeric_limits<double>::quiet_NaN()}) {
    ReconstructOptions bad_pull;
    bad_pull.viscosity_weight = weight;
    EXPECT_THROW(reconstruct(scene.image, light, &scene.mask, std::nullopt, bad_pull), InvalidArgument);
  }
}

}  // namespace
}  // namespace shadecut
