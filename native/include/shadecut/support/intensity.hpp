// From stored colour values to the linear intensity the method reads: the one rule for image files
// (image_io) and for buffers handed over by other programs (the Blender add-on).
#pragma once

#include <shadecut/support/types.hpp>

namespace shadecut {

/// The exact piecewise sRGB transfer functions (IEC 61966-2-1), not the 2.2 power approximation.
double srgb_to_linear(double encoded);
double linear_to_srgb(double linear);

/// The alpha channel of a pixel with `channels` values when nothing else names it: the second of
/// grey + alpha, the fourth of RGBA; -1 (none) otherwise.
int default_alpha_channel(int channels);

struct Intensity {
  ImageF intensity;  ///< H x W linear intensity
  /// H x W x 3 linear RGB of a colour image (the three channels the luminance is read from); empty
  /// (0 x 0 channels) for a grey one.
  ColourImage colour;
  Mask mask;         ///< H x W: alpha > 0.5, or every pixel when there is no alpha channel
};

/// Linear intensity of interleaved pixels: the Rec. 709 luminance (0.2126 R + 0.7152 G + 0.0722 B)
/// of the first three channels that are not alpha, or the only such channel of a grey image, after
/// sRGB decoding when `srgb`. Alpha is read as stored (never premultiplied, never decoded). Non-finite
/// values pass through.
///
/// @param[in] pixels   rows * cols * channels values, row 0 first, channels interleaved.
/// @param[in] channels >= 1, at least one of them not alpha.
/// @param[in] alpha    the alpha channel in [0, channels), or -1 for none.
/// @param[in] srgb     whether the colour values are sRGB-encoded.
/// @throws InvalidArgument for a bad channel count or alpha index.
Intensity intensity_from_pixels(const float* pixels, int rows, int cols, int channels, int alpha, bool srgb);

}  // namespace shadecut
