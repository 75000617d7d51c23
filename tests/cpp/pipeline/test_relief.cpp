// Issue 29: a relief sits on a flat carrier; forms larger than its detail are damped out, the detail
// kept, and the relief's own scale is read from its image.
#include <shadecut/pipeline/relief.hpp>
#include <shadecut/support/errors.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <tuple>
#include <vector>

namespace shadecut {
namespace {

constexpr int kSize = 256;

// z = amplitude sin(2 pi x / wavelength) along the columns.
ImageF wave(double wavelength, double amplitude) {
  ImageF depth(kSize, kSize);
  for (int r = 0; r < kSize; ++r)
    for (int c = 0; c < kSize; ++c) depth(r, c) = float(amplitude * std::sin(2.0 * M_PI * c / wavelength));
  return depth;
}

// The amplitude left in the middle half of the frame, away from its edges.
double middle_amplitude(const ImageF& depth) {
  const auto middle = depth.block(kSize / 4, kSize / 4, kSize / 2, kSize / 2);
  return (middle.maxCoeff() - middle.minCoeff()) / 2.0;
}

TEST(DampLargeForms, KeepsHalfAWaveOfTheDetailSizeAndNearlyNoneOfALongerOne) {
  const Mask mask = Mask::Constant(kSize, kSize, true);
  for (const auto& [wavelength, kept] : {std::pair{32.0, 0.5}, std::pair{8.0, 0.99}, std::pair{128.0, 0.042}}) {
    ImageF depth = wave(wavelength, 4.0);
    damp_large_forms(depth, mask, 32.0);
    // The Gaussian high-pass 1 - exp(-(sigma w)^2 / 2) with sigma = 0.187 x 32, approximated by three
    // boxes of a whole number of pixels (sigma 6.5 instead of 6.0 here: 0.55 kept at 32 px).
    EXPECT_NEAR(middle_amplitude(depth) / 4.0, kept, 0.08) << wavelength;
    EXPECT_NEAR(depth.minCoeff(), 0.0f, 1e-6);
  }
}

// The largest change of the masked depth from `expected`, up to one shift for all of it (the damping
// rebases the depth).
double largest_change(const ImageF& depth, const ImageF& expected, const Mask& mask) {
  const double shift = (mask.select(depth - expected, 0.0f)).sum() / double(mask.count());
  return (mask.select((depth - expected).cast<double>() - shift, 0.0)).abs().maxCoeff();
}

// A slope a relief's depth takes up toward an edge is a large form there too: the damping takes it away
// at the frame's edges and the mask's as in the middle (a one-sided window's mean lagged it by about
// sigma times the slope, a band of tilted normals along the edge), and keeps most of the detail there.
TEST(DampLargeForms, TakesASlopeAwayAtTheFramesAndTheMasksEdgesAndKeepsTheDetailThere) {
  Mask disc = Mask::Constant(kSize, kSize, false);
  for (int r = 0; r < kSize; ++r)
    for (int c = 0; c < kSize; ++c) disc(r, c) = std::hypot(r - 127.5, c - 100.0) < 90.0;
  ImageF slope(kSize, kSize);
  for (int r = 0; r < kSize; ++r)
    for (int c = 0; c < kSize; ++c) slope(r, c) = float(0.3 * c - 0.2 * r);  // 17 and 11 degrees
  const ImageF flat = ImageF::Zero(kSize, kSize), detail = wave(8.0, 1.0);
  for (const Mask& mask : {Mask(Mask::Constant(kSize, kSize, true)), disc}) {
    ImageF depth = slope;
    damp_large_forms(depth, mask, 32.0);
    EXPECT_LT(largest_change(depth, flat, mask), 1e-3);
    depth = slope + detail;
    damp_large_forms(depth, mask, 32.0);
    // The 8-px detail of amplitude 1 keeps 0.99 of it in the middle (the test above); at the edges the
    // window's plane, one-sided there, takes up part of its last wave.
    EXPECT_LT(largest_change(depth, detail, mask), 0.3);
  }
}

TEST(DampLargeForms, LeavesTheOutsideOfTheMaskAndRefusesANonPositiveSize) {
  Mask mask = Mask::Constant(kSize, kSize, true);
  mask.block(0, 0, kSize, kSize / 2).setConstant(false);
  ImageF depth = wave(200.0, 4.0);
  const ImageF before = depth;
  damp_large_forms(depth, mask, 16.0);
  EXPECT_TRUE((depth.leftCols(kSize / 2).array() == before.leftCols(kSize / 2).array()).all());
  EXPECT_THROW(damp_large_forms(depth, mask, 0.0), InvalidArgument);
}

TEST(MedianIntensity, IsTheUpperMiddleMaskedValueAsASortWouldFindIt) {
  // Negative values, repeated values (a quarter-step grid), odd and even counts, a partial mask.
  std::mt19937 generator(7);
  std::uniform_real_distribution<float> value(-0.5f, 2.0f), coin(0.0f, 1.0f);
  for (const auto& [rows, cols, step] : {std::tuple{37, 41, 0.0f}, std::tuple{64, 64, 0.25f}, std::tuple{1, 6, 0.0f}}) {
    ImageF image(rows, cols);
    Mask mask(rows, cols);
    std::vector<float> masked;
    for (Eigen::Index i = 0; i < image.size(); ++i) {
      const float v = value(generator);
      image.data()[i] = step > 0.0f ? step * std::round(v / step) : v;
      mask.data()[i] = rows == 1 || coin(generator) < 0.7f;
      if (mask.data()[i]) masked.push_back(image.data()[i]);
    }
    std::nth_element(masked.begin(), masked.begin() + std::ptrdiff_t(masked.size() / 2), masked.end());
    EXPECT_EQ(median_intensity(image, mask), double(masked[masked.size() / 2])) << rows << " x " << cols;
  }
  EXPECT_THROW(median_intensity(ImageF::Constant(4, 4, -1.0f), Mask::Constant(4, 4, true)), InvalidArgument);
  EXPECT_THROW(median_intensity(ImageF::Constant(4, 4, 1.0f), Mask::Constant(4, 4, false)), InvalidArgument);
}

TEST(ReliefScale, IsTheWavelengthOfAShadingWave) {
  for (const double wavelength : {12.0, 24.0, 48.0}) {
    ImageF image(kSize, kSize);
    for (int r = 0; r < kSize; ++r)
      for (int c = 0; c < kSize; ++c) image(r, c) = float(std::exp(0.3 * std::sin(2.0 * M_PI * c / wavelength)));
    // The blur against noise (about a pixel) lowers the slope's variance a little at short wavelengths.
    EXPECT_NEAR(relief_scale(image, Mask::Constant(kSize, kSize, true)) / wavelength, 1.0, 0.1) << wavelength;
  }
  EXPECT_TRUE(std::isinf(relief_scale(ImageF::Constant(16, 16, 0.5f), Mask::Constant(16, 16, true))));
}

TEST(BrightLines, MarksWhatTheirDefinitionSaysOnRandomMaskedImages) {
  // The definition read plainly: a masked pixel whose darkest masked neighbour within width / 2 on
  // each side, across a row or down a column, is darker by more than the contrast; a side with no
  // masked pixel does not qualify; nothing marked when the marks cover over a quarter of the mask.
  std::mt19937 generator(11);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  for (const int width : {2, 5, 9}) {
    ImageF image(48, 53);
    Mask mask(48, 53);
    for (Eigen::Index i = 0; i < image.size(); ++i) {
      image.data()[i] = 0.2f + 0.3f * unit(generator) + (unit(generator) < 0.05f ? 2.0f : 0.0f);
      mask.data()[i] = unit(generator) < 0.85f;
    }
    const int reach = width / 2;
    auto darkest_side = [&](int r, int c, int dr, int dc, int sign) {
      double darkest = std::numeric_limits<double>::infinity();
      for (int k = 1; k <= reach; ++k) {
        const int rr = r + sign * k * dr, cc = c + sign * k * dc;
        if (rr >= 0 && cc >= 0 && rr < 48 && cc < 53 && mask(rr, cc)) darkest = std::min(darkest, std::log(double(image(rr, cc))));
      }
      return darkest;
    };
    Mask expected = Mask::Constant(48, 53, false);
    for (int r = 0; r < 48; ++r)
      for (int c = 0; c < 53; ++c) {
        if (!mask(r, c)) continue;
        const double centre = std::log(double(image(r, c))), step = std::log(2.0);
        auto across = [&](int dr, int dc) {
          return centre - darkest_side(r, c, dr, dc, -1) > step && centre - darkest_side(r, c, dr, dc, 1) > step;
        };
        expected(r, c) = across(0, 1) || across(1, 0);
      }
    ASSERT_GT(expected.count(), 20) << width;
    ASSERT_LT(4 * expected.count(), mask.count()) << width;
    const Mask lines = bright_lines(image, mask, width, 2.0);
    EXPECT_EQ((lines != expected).count(), 0) << width;
  }
}

TEST(BrightLines, MarksAThinBrightLineNotABrightFaceOrASlope) {
  ImageF image = ImageF::Constant(64, 64, 0.3f);
  image.col(20).setConstant(0.9f);                 // a line of paint, 1 px wide, 3x as bright
  image.block(40, 40, 20, 20).setConstant(0.9f);   // a bright face wider than the square
  for (int c = 0; c < 64; ++c) image.block(0, c, 12, 1).setConstant(0.3f + 0.005f * float(c));  // a face brightening gently
  const Mask mask = Mask::Constant(64, 64, true);
  const Mask lines = bright_lines(image, mask, 7, 2.0);
  Mask expected = Mask::Constant(64, 64, false);
  expected.col(20).tail(52).setConstant(true);
  EXPECT_TRUE((lines == expected).all()) << lines.count() << " marked";
  EXPECT_EQ(bright_lines(image, mask, 0, 2.0).count(), 0);   // off
  EXPECT_EQ(bright_lines(image, mask, 7, 4.0).count(), 0);   // not that much brighter
  EXPECT_THROW(bright_lines(image, mask, 7, 1.0), InvalidArgument);
  ImageF ridges = ImageF::Constant(64, 64, 0.3f);
  for (int c = 0; c < 64; c += 3) ridges.col(c).setConstant(0.9f);  // a third of the pixels: texture
  EXPECT_EQ(bright_lines(ridges, mask, 7, 2.0).count(), 0);
  ImageF shadowed = image;
  shadowed.topRows(34).setZero();  // with the line's 30 lit pixels, half the relief would be black
  EXPECT_EQ(bright_lines(shadowed, mask, 7, 2.0).count(), 0);
}

TEST(BrightLines, LeavesALitBevelBesideItsShadow) {
  // A groove lit from the left, as shading draws it: flat 0.6, the bevel facing the light 1.0, the
  // one facing away black, flat again. The lit bevel stands above the shadow but not above its top.
  ImageF image = ImageF::Constant(32, 32, 0.6f);
  image.middleCols(14, 2).setConstant(1.0f);
  image.middleCols(16, 2).setConstant(0.0f);
  EXPECT_EQ(bright_lines(image, Mask::Constant(32, 32, true), 7, 2.0).count(), 0);
}

TEST(BrightLines, IgnoresWhatLiesOutsideTheMask) {
  // A bright square in a dark frame: inside the mask it is a face, not a line, although the dark
  // pixels outside would make its edge look like one.
  ImageF image = ImageF::Constant(32, 32, 0.05f);
  image.block(8, 8, 16, 16).setConstant(0.8f);
  Mask mask = Mask::Constant(32, 32, false);
  mask.block(8, 8, 16, 16).setConstant(true);
  EXPECT_EQ(bright_lines(image, mask, 7, 2.0).count(), 0);
}

}  // namespace
}  // namespace shadecut
