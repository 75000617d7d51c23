#include <shadecut/support/intensity.hpp>

#include <shadecut/support/errors.hpp>

#include <cmath>
#include <string>
#include <vector>

namespace shadecut {

double srgb_to_linear(double encoded) {
  return encoded <= 0.04045 ? encoded / 12.92 : std::pow((encoded + 0.055) / 1.055, 2.4);
}

double linear_to_srgb(double linear) {
  return linear <= 0.0031308 ? linear * 12.92 : 1.055 * std::pow(linear, 1.0 / 2.4) - 0.055;
}

int default_alpha_channel(int channels) { return channels == 2 ? 1 : channels == 4 ? 3 : -1; }

Intensity intensity_from_pixels(const float* pixels, int rows, int cols, int channels, int alpha, bool srgb) {
  if (channels < 1 || (channels == 1 && alpha == 0))
    throw InvalidArgument("shadecut: pixels need at least one colour channel; got " + std::to_string(channels) +
                          " channel(s) with alpha " + std::to_string(alpha));
  if (alpha < -1 || alpha >= channels)
    throw InvalidArgument("shadecut: alpha channel " + std::to_string(alpha) + " of " + std::to_string(channels));
  std::vector<int> colour;
  for (int channel = 0; channel < channels && colour.size() < 3; ++channel)
    if (channel != alpha) colour.push_back(channel);
  auto linear = [srgb](float stored) { return srgb ? srgb_to_linear(stored) : double(stored); };

  Intensity result{ImageF(rows, cols), {}, Mask::Constant(rows, cols, true)};
  if (colour.size() == 3)
    for (ImageF& channel : result.colour.channel) channel.resize(rows, cols);
  float* intensity = result.intensity.data();
  bool* inside = result.mask.data();
  const std::size_t pixel_count = std::size_t(rows) * std::size_t(cols);
  for (std::size_t i = 0; i < pixel_count; ++i) {
    const float* pixel = &pixels[i * std::size_t(channels)];
    if (colour.size() == 3) {
      for (int k = 0; k < 3; ++k) result.colour.channel[std::size_t(k)].data()[i] = float(linear(pixel[colour[std::size_t(k)]]));
      intensity[i] = float(kLuminanceWeights[0] * linear(pixel[colour[0]]) + kLuminanceWeights[1] * linear(pixel[colour[1]]) +
                           kLuminanceWeights[2] * linear(pixel[colour[2]]));
    } else {
      intensity[i] = float(linear(pixel[colour[0]]));
    }
    if (alpha >= 0) inside[i] = pixel[alpha] > 0.5f;
  }
  return result;
}

}  // namespace shadecut
