#include <shadecut/support/downsample.hpp>
#include <shadecut/support/errors.hpp>

#include <gtest/gtest.h>

namespace shadecut {
namespace {

ImageF counting_image(int rows, int cols) {
  ImageF image(rows, cols);
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) image(r, c) = float(r * cols + c);
  return image;
}

TEST(Downsample, WholeBlocksOnlyAtFullCoverage) {
  const ImageF image = counting_image(5, 4);
  Mask mask = Mask::Constant(5, 4, true);
  mask(0, 3) = false;
  const Downsampled half = downsample(image, mask, 2, 1.0);
  ASSERT_EQ(half.image.rows(), 2);  // the odd last row is dropped
  ASSERT_EQ(half.image.cols(), 2);
  EXPECT_TRUE(half.mask(0, 0));
  EXPECT_FALSE(half.mask(0, 1));  // one of its four pixels is outside the mask
  EXPECT_EQ(half.image(0, 1), 0.0f);
  EXPECT_FLOAT_EQ(half.image(0, 0), (0 + 1 + 4 + 5) / 4.0f);
  EXPECT_FLOAT_EQ(half.image(1, 1), (10 + 11 + 14 + 15) / 4.0f);
}

TEST(Downsample, PartialBlocksAverageTheirMaskedPixels) {
  const ImageF image = counting_image(6, 6);
  Mask mask = Mask::Constant(6, 6, false);
  mask.block(0, 0, 3, 3).setConstant(true);
  mask(0, 0) = false;          // block (0, 0): 8 of 9 pixels
  mask.block(3, 3, 2, 2).setConstant(true);  // block (1, 1): 4 of 9, below half
  const Downsampled third = downsample(image, mask, 3, 0.5);
  EXPECT_TRUE(third.mask(0, 0));
  EXPECT_FLOAT_EQ(third.image(0, 0), (1 + 2 + 6 + 7 + 8 + 12 + 13 + 14) / 8.0f);
  EXPECT_FALSE(third.mask(1, 1));
  EXPECT_FALSE(third.mask(0, 1));
}

TEST(Downsample, RejectsBadArguments) {
  const ImageF image = counting_image(4, 4);
  const Mask mask = Mask::Constant(4, 4, true);
  EXPECT_THROW(downsample(image, mask, 0, 1.0), InvalidArgument);
  EXPECT_THROW(downsample(image, mask, 2, 0.0), InvalidArgument);
  EXPECT_THROW(downsample(image, Mask::Constant(3, 4, true), 2, 1.0), InvalidArgument);
}

}  // namespace
}  // namespace shadecut
