// Image containers shared by every ShadeCut function.
//
// Conventions (the README's "Conventions" section is the single source of truth):
//   - an image is rows x cols (H x W) float32, row 0 at the top;
//   - camera frame: x right (column increasing), y up (row decreasing), z toward the viewer;
//   - pixel (r, c) has linear index r * cols + c.
#pragma once

#include <Eigen/Core>

#include <array>
#include <cstdint>

namespace shadecut {

/// H x W single-channel float image, row-major, row 0 at the top.
using ImageF = Eigen::Array<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

/// H x W boolean mask, row-major. true = pixel belongs to the surface.
using Mask = Eigen::Array<bool, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

/// Per-pixel unit vectors in the camera frame, stored as (H * W) x 3, row r * W + c holds (x, y, z).
using Vectors3 = Eigen::Matrix<float, Eigen::Dynamic, 3, Eigen::RowMajor>;

/// H x W field of camera-frame unit normals. Pixels outside a mask hold (0, 0, 0).
struct NormalMap {
  int rows = 0;
  int cols = 0;
  Vectors3 xyz;  // (rows * cols) x 3

  NormalMap() = default;
  NormalMap(int rows_, int cols_) : rows(rows_), cols(cols_), xyz(Vectors3::Zero(Eigen::Index(rows_) * cols_, 3)) {}
  Eigen::Index size() const { return Eigen::Index(rows) * cols; }
};

/// H x W x 3 linear RGB, one H x W plane per channel (red, green, blue).
struct ColourImage {
  std::array<ImageF, 3> channel;

  Eigen::Index rows() const { return channel[0].rows(); }
  Eigen::Index cols() const { return channel[0].cols(); }
};

/// Rec. 709 luminance, the intensity of a colour pixel (support/intensity.hpp's rule).
constexpr std::array<double, 3> kLuminanceWeights = {0.2126, 0.7152, 0.0722};

}  // namespace shadecut
