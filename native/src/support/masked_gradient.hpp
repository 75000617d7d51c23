// Internal: derivatives of an image that use masked pixels only, shared by the renderer (normals of
// a height field), the local shape step (intensity gradient) and the relief's carrier (relief.cpp),
// so all read the same differences.
#pragma once

#include <shadecut/support/types.hpp>

namespace shadecut::detail {

/// Derivatives at masked pixel (r, c) along +x (right) and +y (UP, i.e. toward row r - 1): central
/// differences between masked neighbours, one-sided where only one neighbour is masked.
struct MaskedGradient {
  double dx = 0.0, dy = 0.0;
  bool has_x = false, has_y = false;  ///< false where neither neighbour along that axis is masked
};

/// `Field`: any H x W Eigen array or matrix of float or double (an image, a depth, a blurred field).
template <class Field>
MaskedGradient masked_gradient(const Field& image, const Mask& mask, int r, int c) {
  using Scalar = typename Field::Scalar;
  const int rows = int(image.rows()), cols = int(image.cols());
  auto at = [&](int rr, int cc) -> const Scalar* {
    if (rr < 0 || rr >= rows || cc < 0 || cc >= cols || !mask(rr, cc)) return nullptr;
    return &image(rr, cc);
  };
  auto derivative = [&](const Scalar* before, const Scalar* after, bool* defined) {
    *defined = before || after;
    if (before && after) return 0.5 * (double(*after) - double(*before));
    if (after) return double(*after) - double(image(r, c));
    if (before) return double(image(r, c)) - double(*before);
    return 0.0;
  };
  MaskedGradient g;
  g.dx = derivative(at(r, c - 1), at(r, c + 1), &g.has_x);
  g.dy = derivative(at(r + 1, c), at(r - 1, c), &g.has_y);
  return g;
}

}  // namespace shadecut::detail
