// The paint separated from the shading (estimate_reflectance): a painted sphere's paint ratio
// recovered, a plain sphere left plain, the colour of the paint, and bad input.
#include "test_support.hpp"

#include <shadecut/estimate/estimate_reflectance.hpp>
#include <shadecut/pipeline/reconstruct.hpp>
#include <shadecut/support/angular_error.hpp>
#include <shadecut/support/errors.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace shadecut {
namespace {

const Eigen::Vector3d kLight(0.3, 0.2, 1.0);
constexpr double kLeftPaint = 0.4, kRightPaint = 0.9;

// A 96-px sphere whose left half is painted kLeftPaint in red-brown and right half kRightPaint in
// grey, rendered under kLight: (colour image, its luminance, the scene).
struct PaintedSphere {
  testing::Scene scene = testing::sphere_scene(96, 0.45, kLight);
  ColourImage colour;
  ImageF intensity;

  PaintedSphere() {
    const std::array<double, 3> left{0.6, 0.35, 0.25}, right{1.0, 1.0, 1.0};
    for (int k = 0; k < 3; ++k) colour.channel[std::size_t(k)] = ImageF::Zero(96, 96);
    for (Eigen::Index r = 0; r < 96; ++r) {
      for (Eigen::Index c = 0; c < 96; ++c) {
        const bool on_left = c < 48;
        const std::array<double, 3>& tint = on_left ? left : right;
        const double paint = on_left ? kLeftPaint : kRightPaint;
        for (int k = 0; k < 3; ++k)
          colour.channel[std::size_t(k)](r, c) = float(scene.image(r, c) * paint * tint[std::size_t(k)]);
      }
    }
    intensity = luminance(colour);
  }
};

ReflectanceParams params() { return reflectance_params(ReconstructOptions{}); }

// The median of the relative reflectance over the lit masked pixels of one half.
double median_half(const Reflectance& reflectance, const testing::Scene& scene, bool left) {
  std::vector<float> values;
  for (Eigen::Index r = 0; r < 96; ++r)
    for (Eigen::Index c = left ? 0 : 48; c < (left ? 48 : 96); ++c)
      if (scene.mask(r, c) && scene.image(r, c) > 0.1f) values.push_back(reflectance.relative(r, c));
  std::nth_element(values.begin(), values.begin() + std::ptrdiff_t(values.size() / 2), values.end());
  return values[values.size() / 2];
}

TEST(EstimateReflectance, AColourPaintStepIsRecoveredAndTheShadingLeftSmooth) {
  const PaintedSphere painted;
  // The luminance of the two paints: their ratio is what the reflectance must recover.
  const double left = kLeftPaint * (0.2126 * 0.6 + 0.7152 * 0.35 + 0.0722 * 0.25), right = kRightPaint;
  const Reflectance reflectance = estimate_reflectance(painted.intensity, &painted.colour, painted.scene.mask, params());
  const double ratio = median_half(reflectance, painted.scene, false) / median_half(reflectance, painted.scene, true);
  EXPECT_NEAR(ratio, right / left, 0.05 * right / left);
  EXPECT_GT(reflectance.edge_pairs, 0);
}

TEST(EstimateReflectance, AGreyPaintStepIsReadFromTheIntensityAlone) {
  const PaintedSphere painted;
  const double left = kLeftPaint * (0.2126 * 0.6 + 0.7152 * 0.35 + 0.0722 * 0.25), right = kRightPaint;
  const Reflectance reflectance = estimate_reflectance(painted.intensity, nullptr, painted.scene.mask, params());
  const double ratio = median_half(reflectance, painted.scene, false) / median_half(reflectance, painted.scene, true);
  EXPECT_NEAR(ratio, right / left, 0.1 * right / left);
}

// With the shading of the true surface given, each paint edge's shading step is the surface's own,
// not the image's steps beside the edge: on a full-frame bump field painted in two halves (every
// boundary pair readable) the grey cue then recovers the paint exactly; the steps beside the edge,
// bent by the bumps, do not.
TEST(EstimateReflectance, ASurfaceFoundBeforeGivesEachEdgeItsShadingStep) {
  const testing::Scene bumps = testing::bumps_scene(96, kLight);
  ImageF painted = bumps.image;
  painted.leftCols(48) *= float(kLeftPaint);
  painted.rightCols(48) *= float(kRightPaint);
  auto worst_error = [&](const ImageF* shading) {
    const Reflectance reflectance = estimate_reflectance(painted, nullptr, bumps.mask, params(), {}, shading);
    // Relative to the right half's paint, which sits at the 90th percentile.
    const ImageF truth = (ImageF(96, 96) << ImageF::Constant(96, 48, float(kLeftPaint / kRightPaint)),
                          ImageF::Ones(96, 48)).finished();
    return (reflectance.relative.log() - truth.log()).abs().maxCoeff();
  };
  const ImageF true_shading = bumps.image * 3.0f;  // any scale: only its steps count
  EXPECT_LT(worst_error(&true_shading), 1e-3);
  EXPECT_GT(worst_error(nullptr), 0.01);
}

// Shading never changes the colour: the colour cue alone leaves a plain sphere of one albedo exactly.
// (The grey cue does not: near the outline a sphere's shading falls off fast enough to read as paint,
// docs/method.md#paint-albedo_methodretinex.)
TEST(EstimateReflectance, TheColourCueLeavesAnUnpaintedSphereOfOneAlbedo) {
  const testing::Scene scene = testing::sphere_scene(96, 0.45, kLight);
  ColourImage colour;
  for (int k = 0; k < 3; ++k) colour.channel[std::size_t(k)] = scene.image * float(0.5 + 0.2 * k);
  ReflectanceParams colour_only = params();
  colour_only.intensity_edge = 0.0;
  const Reflectance reflectance = estimate_reflectance(luminance(colour), &colour, scene.mask, colour_only);
  EXPECT_EQ(reflectance.edge_pairs, 0);
  for (Eigen::Index i = 0; i < scene.mask.size(); ++i) {
    if (scene.mask.data()[i]) {
      EXPECT_FLOAT_EQ(reflectance.relative.data()[i], 1.0f);
    }
  }
}

TEST(EstimateReflectance, TheDeLitColourIsThePaintsColour) {
  const PaintedSphere painted;
  ReconstructOptions options;
  options.albedo_method = AlbedoMethod::Retinex;
  const Reconstruction result = reconstruct(painted.colour, kLight, &painted.scene.mask, std::nullopt, options);
  ASSERT_EQ(result.albedo_colour.rows(), 96);
  // On the left half the paint's red / green ratio, 0.6 / 0.35, whatever the shading.
  for (Eigen::Index r = 20; r < 76; r += 7) {
    const float red = result.albedo_colour.channel[0](r, 30), green = result.albedo_colour.channel[1](r, 30);
    if (painted.scene.mask(r, 30) && painted.scene.image(r, 30) > 0.1f) {
      EXPECT_NEAR(red / green, 0.6 / 0.35, 1e-3);
    }
  }
}

TEST(EstimateReflectance, RetinexFillsTheShadingImagesHighlightsUnlessTold) {
  ReconstructOptions options;
  EXPECT_EQ(highlight_threshold_used(options), kHighlightThreshold);
  options.albedo_method = AlbedoMethod::Retinex;
  EXPECT_EQ(highlight_threshold_used(options), kRetinexHighlightThreshold);
  options.highlight_threshold = 0.0;
  EXPECT_EQ(highlight_threshold_used(options), 0.0);

  // The painted sphere with a white glow where it faces halfway between the light and the viewer:
  // no paint edge is read in it, so it stays in the shading image, above the albedo, and is filled.
  PaintedSphere shiny;
  const Eigen::Vector3d halfway = (kLight.normalized() + Eigen::Vector3d::UnitZ()).normalized();
  for (Eigen::Index r = 0; r < 96; ++r) {
    for (Eigen::Index c = 0; c < 96; ++c) {
      if (!shiny.scene.mask(r, c)) continue;
      const Eigen::Vector3d normal = shiny.scene.normals.xyz.row(r * 96 + c).transpose().cast<double>();
      const float glow = float(0.6 * std::pow(std::max(0.0, normal.dot(halfway)), 40.0));
      for (ImageF& channel : shiny.colour.channel) channel(r, c) += glow;
    }
  }
  const Mask inner = erode_mask(shiny.scene.mask, 2);
  auto error = [&](std::optional<double> threshold) {
    ReconstructOptions retinex;
    retinex.albedo_method = AlbedoMethod::Retinex;
    retinex.highlight_threshold = threshold;
    return mean_angular_error(reconstruct(shiny.colour, kLight, &shiny.scene.mask, std::nullopt, retinex).normals,
                              shiny.scene.normals, inner);
  };
  const double unset = error(std::nullopt), filled = error(kRetinexHighlightThreshold), kept = error(0.0);
  EXPECT_EQ(unset, filled);
  EXPECT_LT(filled, kept);
}

TEST(EstimateReflectance, BadInputIsRefused) {
  const PaintedSphere painted;
  ReflectanceParams negative_rim = params();
  negative_rim.rim = -1;
  EXPECT_THROW(estimate_reflectance(painted.intensity, &painted.colour, painted.scene.mask, negative_rim), InvalidArgument);
  ReflectanceParams all_shadow = params();
  all_shadow.shadow = 1.0;
  EXPECT_THROW(estimate_reflectance(painted.intensity, &painted.colour, painted.scene.mask, all_shadow), InvalidArgument);
  ColourImage small = painted.colour;
  small.channel[2] = ImageF::Zero(4, 4);
  EXPECT_THROW(estimate_reflectance(painted.intensity, &small, painted.scene.mask, params()), InvalidArgument);
  const ImageF small_shading = ImageF::Ones(4, 4);
  EXPECT_THROW(estimate_reflectance(painted.intensity, nullptr, painted.scene.mask, params(), {}, &small_shading), InvalidArgument);
  ImageF infinite_shading = painted.scene.image;
  infinite_shading(48, 48) = INFINITY;
  EXPECT_THROW(estimate_reflectance(painted.intensity, nullptr, painted.scene.mask, params(), {}, &infinite_shading), InvalidArgument);
  ReconstructOptions options;
  options.albedo_method = AlbedoMethod::Retinex;
  options.retinex_chroma_edge = std::nan("");
  EXPECT_THROW(reconstruct(painted.colour, kLight, &painted.scene.mask, std::nullopt, options), InvalidArgument);
  options.retinex_chroma_edge = 0.02;
  options.retinex_passes = 0;
  EXPECT_THROW(reconstruct(painted.colour, kLight, &painted.scene.mask, std::nullopt, options), InvalidArgument);
}

}  // namespace
}  // namespace shadecut
