// The albedo estimates and the treatment of pixels no Lambertian surface of that albedo shows.
#include "test_support.hpp"

#include <shadecut/estimate/estimate_albedo.hpp>
#include <shadecut/support/errors.hpp>
#include <shadecut/pipeline/relief.hpp>
#include <shadecut/integrate/shadow_fill.hpp>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include <cmath>
#include <random>

namespace shadecut {
namespace {

// The scene's image at `albedo` plus a Blinn-Phong lobe of `strength` around the half vector,
// clipped at 1 like a saturated photograph.
ImageF with_highlight(const testing::Scene& scene, const Eigen::Vector3d& light, double albedo, double strength) {
  const Eigen::Vector3d s = light.normalized(), half = (s + Eigen::Vector3d::UnitZ()).normalized();
  ImageF image = ImageF::Zero(scene.image.rows(), scene.image.cols());
  for (Eigen::Index i = 0; i < image.size(); ++i) {
    if (!scene.mask.data()[i]) continue;
    const Eigen::Vector3d n = scene.normals.xyz.row(i).cast<double>();
    const double facing = std::max(0.0, n.dot(s));
    const double lobe = facing > 0.0 ? strength * std::pow(std::max(0.0, n.dot(half)), 50.0) : 0.0;
    image.data()[i] = float(std::min(1.0, albedo * facing + lobe));
  }
  return image;
}

TEST(EstimateAlbedo, TopFitIsExactOnACleanSphereAndBrightestOnlyThere) {
  const Eigen::Vector3d light(1, 0, 1);
  const testing::Scene scene = testing::sphere_scene(128, 0.45, light);
  const ImageF clean = with_highlight(scene, light, 0.3, 0.0);
  // No highlight: the brightest value agrees with the fit and is taken.
  EXPECT_NEAR(estimate_albedo(clean, scene.mask, AlbedoMethod::TopFit), 0.3, 0.3e-3);
  EXPECT_NEAR(estimate_albedo(clean, scene.mask, AlbedoMethod::Brightest), 0.3, 0.3e-3);
  // A highlight three times as bright as the albedo: brightest takes it, top_fit reads the shading.
  const ImageF shiny = with_highlight(scene, light, 0.3, 1.0);
  EXPECT_GT(estimate_albedo(shiny, scene.mask, AlbedoMethod::Brightest), 0.9);
  // Measured 0.276: the fit's window reaches the limb under this 45-degree light (estimate_albedo.hpp).
  EXPECT_NEAR(estimate_albedo(shiny, scene.mask, AlbedoMethod::TopFit), 0.3, 0.03);
}

// brightest is the largest 3 x 3 median inside the mask; OpenCV's medianBlur (border replicated), on
// which the core relied before it had its own filter, is the reference. Single-pixel highlights and
// a highlight on the border are what the median has to remove.
TEST(EstimateAlbedo, BrightestIsTheLargestMedianOfOpenCVsFilter) {
  std::mt19937 random(7);
  std::uniform_real_distribution<float> value(0.0f, 0.5f);
  for (const auto& [rows, cols] : {std::pair{2, 2}, std::pair{2, 7}, std::pair{5, 2}, std::pair{37, 53}}) {
    ImageF image(rows, cols);
    for (Eigen::Index i = 0; i < image.size(); ++i) image.data()[i] = value(random);
    image(0, 0) = 1.0f;
    image(rows / 2, cols / 2) = 0.9f;
    Mask mask(rows, cols);
    for (Eigen::Index i = 0; i < mask.size(); ++i) mask.data()[i] = i % 3 != 1;
    cv::Mat source(rows, cols, CV_32F), filtered;
    for (int r = 0; r < rows; ++r)
      for (int c = 0; c < cols; ++c) source.at<float>(r, c) = image(r, c);
    cv::medianBlur(source, filtered, 3);
    float expected = 0.0f;
    for (int r = 0; r < rows; ++r)
      for (int c = 0; c < cols; ++c)
        if (mask(r, c)) expected = std::max(expected, filtered.at<float>(r, c));
    EXPECT_EQ(estimate_albedo(image, mask, AlbedoMethod::Brightest), expected) << rows << " x " << cols;
  }
}

TEST(EstimateAlbedo, RejectsABadWindowAndADarkImage) {
  const testing::Scene scene = testing::sphere_scene(32, 0.45, Eigen::Vector3d(0, 0, 1));
  EXPECT_THROW(estimate_albedo(scene.image, scene.mask, AlbedoMethod::TopFit, {0.5, 0.4, 0.3}), InvalidArgument);
  EXPECT_THROW(estimate_albedo(ImageF::Zero(32, 32), scene.mask), InvalidArgument);
  EXPECT_EQ(parse_albedo_method(to_string(AlbedoMethod::TopFit)), AlbedoMethod::TopFit);
  EXPECT_THROW(parse_albedo_method("median"), InvalidArgument);
}

TEST(UnreliablePixels, AreShadowsAndWhatIsBrighterThanTheAlbedoAllows) {
  ImageF image(1, 5);
  image << 0.0f, 0.05f, 0.5f, 1.04f, 1.2f;
  const Mask all = Mask::Constant(1, 5, true);
  const Mask both = unreliable_pixels(image, all, 1.0, 1e-3, 1.05);
  EXPECT_TRUE(both(0, 0) && !both(0, 1) && !both(0, 2) && !both(0, 3) && both(0, 4));
  const Mask shadows_only = unreliable_pixels(image, all, 1.0, 1e-3, 0.0);
  EXPECT_TRUE(shadows_only(0, 0) && !shadows_only(0, 4));
  const Mask highlights_only = unreliable_pixels(image, all, 1.0, -1.0, 1.05);
  EXPECT_TRUE(!highlights_only(0, 0) && highlights_only(0, 4));
}

TEST(Relief, AlbedoFromTheMeanAndNoRampAfterFlattening) {
  // A ramp of slope (0.2, -0.1) carrying two bumps.
  const int size = 64;
  ImageF depth(size, size);
  for (int r = 0; r < size; ++r) {
    for (int c = 0; c < size; ++c) {
      const double bump = 3.0 * std::exp(-(std::pow(c - 20, 2) + std::pow(r - 30, 2)) / 40.0);
      depth(r, c) = float(0.2 * c + 0.1 * r + bump);
    }
  }
  const Mask mask = Mask::Constant(size, size, true);
  flatten_relief(depth, mask);
  // Far from the bump the ramp is gone, up to the bump's share of the plane fit.
  EXPECT_NEAR(depth(size - 1, 0) - depth(size - 1, size - 1), 0.0f, 0.02f * size);
  EXPECT_NEAR(depth.minCoeff(), 0.0f, 1e-5f);
  EXPECT_LT(depth.maxCoeff() - depth.minCoeff(), 3.5f);  // the bump's 3 px, no ramp of 0.2 * 64
  const ImageF flat = ImageF::Constant(8, 8, 0.4f);
  EXPECT_NEAR(relief_albedo(flat, Mask::Constant(8, 8, true), Eigen::Vector3d(0.6, 0, 0.8)), 0.5, 1e-6);
  ImageF grooved = flat;
  grooved.row(0).setConstant(0.05f);  // a dark groove does not move the median
  EXPECT_NEAR(relief_albedo(grooved, Mask::Constant(8, 8, true), Eigen::Vector3d(0.6, 0, 0.8)), 0.5, 1e-6);
}

}  // namespace
}  // namespace shadecut
