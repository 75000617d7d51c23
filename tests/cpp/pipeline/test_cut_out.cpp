// cut_out(): an object on a plain or graded background is found with its outline; a textured frame,
// an empty background and a dark object meeting a dark background are said to have none.
#include <shadecut/pipeline/cut_out.hpp>
#include <shadecut/support/errors.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace shadecut {
namespace {

// A shaded disc (Lambertian sphere lit from (0.3, 0.4, 0.87), albedo 0.7) of radius `radius` at the
// centre of a size x size image whose background is `background(r, c)`; `truth` receives the disc.
template <class Background>
ImageF disc_on(int size, double radius, Background background, Mask& truth) {
  ImageF image(size, size);
  truth = Mask::Constant(size, size, false);
  const double light[3] = {0.3 / 1.0, 0.4, std::sqrt(1.0 - 0.25)};
  for (int r = 0; r < size; ++r)
    for (int c = 0; c < size; ++c) {
      const double x = (c + 0.5 - size / 2.0) / radius, y = (size / 2.0 - r - 0.5) / radius, rho2 = x * x + y * y;
      if (rho2 < 1.0) {
        truth(r, c) = true;
        image(r, c) = float(0.7 * std::max(0.02, light[0] * x + light[1] * y + light[2] * std::sqrt(1.0 - rho2)));
      } else {
        image(r, c) = float(background(r, c));
      }
    }
  return image;
}

double iou(const Mask& a, const Mask& b) {
  return double((a && b).count()) / double(std::max<Eigen::Index>(1, (a || b).count()));
}

TEST(CutOut, DiscOnWhite) {
  Mask truth;
  const ImageF image = disc_on(200, 60, [](int, int) { return 1.0; }, truth);
  const CutOut cut = cut_out(image, nullptr);
  EXPECT_EQ(cut.outcome, CutOutOutcome::Found) << cut.message;
  EXPECT_GE(iou(cut.mask, truth), 0.97);
  EXPECT_GE(cut.outline_contrast, 0.9);
}

TEST(CutOut, DiscOnGradientWithNoise) {
  std::mt19937 random(3);
  std::normal_distribution<double> noise(0.0, 0.01);
  Mask truth;
  const ImageF image = disc_on(240, 70, [&](int r, int c) { return 0.35 + 0.5 * (r + c) / 480.0 + noise(random); }, truth);
  const CutOut cut = cut_out(image, nullptr);
  EXPECT_EQ(cut.outcome, CutOutOutcome::Found) << cut.message;
  EXPECT_GE(iou(cut.mask, truth), 0.95);
}

TEST(CutOut, ColourDiscOnBlueBackgroundAtFullResolutionBand) {
  // 1000 px: the models learnt on the shrunk image, the outline labelled again at full size.
  Mask truth;
  const ImageF grey = disc_on(1000, 300, [](int, int) { return 0.4; }, truth);
  ColourImage colour;
  colour.channel = {grey, grey, grey};
  for (Eigen::Index i = 0; i < grey.size(); ++i)
    if (!truth.data()[i]) colour.channel[0].data()[i] = 0.1f, colour.channel[1].data()[i] = 0.2f, colour.channel[2].data()[i] = 0.8f;
  ImageF intensity = 0.2126f * colour.channel[0] + 0.7152f * colour.channel[1] + 0.0722f * colour.channel[2];
  const CutOut cut = cut_out(intensity, &colour);
  EXPECT_EQ(cut.outcome, CutOutOutcome::Found) << cut.message;
  EXPECT_GE(iou(cut.mask, truth), 0.98);
}

TEST(CutOut, TexturedFrameHasNoPlainBackground) {
  std::mt19937 random(5);
  std::uniform_real_distribution<double> texture(0.2, 0.9);
  Mask truth;
  const ImageF image = disc_on(160, 50, [&](int, int) { return texture(random); }, truth);
  const CutOut cut = cut_out(image, nullptr);
  EXPECT_EQ(cut.outcome, CutOutOutcome::BusyBorder) << cut.message;
  EXPECT_EQ(cut.mask.count(), 0);
}

TEST(CutOut, SurfaceFillingTheFrameIsNoObject) {
  // A sphere larger than the frame, its smooth shading over the whole border, and one whose black
  // corners alone are background: neither is an object on a background.
  for (const double radius : {120.0, 80.0}) {
    Mask truth;
    const ImageF image = disc_on(128, radius, [](int, int) { return 0.0; }, truth);
    const CutOut cut = cut_out(image, nullptr);
    EXPECT_NE(cut.outcome, CutOutOutcome::Found) << "radius " << radius << ": " << cut.message;
  }
}

TEST(CutOut, EmptyAndTinyImagesHaveNoObject) {
  EXPECT_EQ(cut_out(ImageF::Constant(64, 64, 1.0f), nullptr).outcome, CutOutOutcome::NoObject);
  EXPECT_EQ(cut_out(ImageF::Constant(2, 2, 0.5f), nullptr).outcome, CutOutOutcome::NoObject);
}

TEST(CutOut, AttachedShadowOnBlackIsLowContrast) {
  // Lit from the side, half the sphere is as black as the background: its outline there is unseen.
  const int size = 160;
  ImageF image = ImageF::Zero(size, size);
  for (int r = 0; r < size; ++r)
    for (int c = 0; c < size; ++c) {
      const double x = (c + 0.5 - size / 2.0) / 50.0, y = (size / 2.0 - r - 0.5) / 50.0, rho2 = x * x + y * y;
      if (rho2 < 1.0) image(r, c) = float(std::max(0.0, 0.9 * x + 0.436 * std::sqrt(1.0 - rho2)));
    }
  const CutOut cut = cut_out(image, nullptr);
  EXPECT_NE(cut.outcome, CutOutOutcome::Found) << cut.message;
}

TEST(CutOut, BadOptionsAreRefused) {
  CutOutOptions options;
  options.border = 0.7;
  EXPECT_THROW(cut_out(ImageF::Constant(8, 8, 1.0f), nullptr, options), InvalidArgument);
  EXPECT_THROW(cut_out(ImageF::Constant(8, 8, std::nanf("")), nullptr), InvalidArgument);
}

}  // namespace
}  // namespace shadecut
