#include "pipeline/crop.hpp"

#include <algorithm>

namespace shadecut::detail {

namespace {

// Enough for the local steps' windows and the outline's ring around the mask.
constexpr int kMargin = 16;
// A multiple of every coarse level's block (2^levels), so the coarse grids stay the frame's.
constexpr int kGrid = 64;
// A window of more than this share of the frame saves too little to be worth a copy.
constexpr double kLargestShare = 0.5;

template <typename Array>
Array cropped(const Array& image, const Box& window) {
  return image.block(window.top, window.left, window.rows, window.cols);
}

template <typename Array>
Array placed(const Array& image, const Box& window, int rows, int cols) {
  if (image.size() == 0) return image;
  Array frame = Array::Zero(rows, cols);
  frame.block(window.top, window.left, window.rows, window.cols) = image;
  return frame;
}

ColourImage placed(const ColourImage& colour, const Box& window, int rows, int cols) {
  ColourImage frame;
  for (std::size_t k = 0; k < colour.channel.size(); ++k) frame.channel[k] = placed(colour.channel[k], window, rows, cols);
  return frame;
}

NormalMap placed(const NormalMap& normals, const Box& window, int rows, int cols) {
  NormalMap frame(rows, cols);
  for (int r = 0; r < window.rows; ++r)
    frame.xyz.middleRows(Eigen::Index(window.top + r) * cols + window.left, window.cols) =
        normals.xyz.middleRows(Eigen::Index(r) * window.cols, window.cols);
  return frame;
}

}  // namespace

std::optional<Box> object_window(const Mask& mask) {
  const std::optional<Box> bounds = mask_bounds(mask);
  if (!bounds) return std::nullopt;
  const int rows = int(mask.rows()), cols = int(mask.cols());
  const int bottom = bounds->top + bounds->rows - 1, right = bounds->left + bounds->cols - 1;
  auto down_to_grid = [](int at) { return std::max(0, at - kMargin) / kGrid * kGrid; };
  auto up_to_grid = [](int at, int size) { return std::min(size, (at + kMargin + kGrid) / kGrid * kGrid); };
  Box window;
  window.top = down_to_grid(bounds->top), window.left = down_to_grid(bounds->left);
  window.rows = up_to_grid(bottom, rows) - window.top, window.cols = up_to_grid(right, cols) - window.left;
  if (double(window.rows) * window.cols > kLargestShare * double(rows) * cols) return std::nullopt;
  return window;
}

std::vector<Observation> crop_observations(const std::vector<Observation>& observations, const Box& window) {
  std::vector<Observation> inside;
  inside.reserve(observations.size());
  for (const Observation& photograph : observations) {
    Observation part;
    part.image = cropped(photograph.image, window);
    if (photograph.has_colour())
      for (std::size_t k = 0; k < part.colour.channel.size(); ++k) part.colour.channel[k] = cropped(photograph.colour.channel[k], window);
    part.light = photograph.light;
    inside.push_back(std::move(part));
  }
  return inside;
}

Mask crop_mask(const Mask& mask, const Box& window) { return cropped(mask, window); }

Reconstruction put_back(Reconstruction result, const Box& window, int rows, int cols) {
  result.normals = placed(result.normals, window, rows, cols);
  result.depth = placed(result.depth, window, rows, cols);
  result.mask = placed(result.mask, window, rows, cols);
  result.albedo_map = placed(result.albedo_map, window, rows, cols);
  result.albedo_colour = placed(result.albedo_colour, window, rows, cols);
  result.residual = placed(result.residual, window, rows, cols);
  return result;
}

}  // namespace shadecut::detail
