// Image containers shared by every ShadeCut function.
//
// Conventions (the README's "Conventions" section is the single source of truth):
//   - an image is rows x cols (H x W) float32, row 0 at the top;
//   - camera frame: x right (column increasing), y up (row decreasing), z toward the viewer;
//   - pixel (r, c) has linear index r * cols + c.
#pragma once

#include <Eigen/Core>
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

}  // namespace shadecut
