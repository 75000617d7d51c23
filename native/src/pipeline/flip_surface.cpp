#include <shadecut/pipeline/flip_surface.hpp>

#include <shadecut/support/errors.hpp>
#include <shadecut/support/rebase_depth.hpp>

#include <cmath>
#include <string>

namespace shadecut {

void flip_surface(ImageF& depth, NormalMap& normals, const Mask& mask) {
  if (depth.rows() != mask.rows() || depth.cols() != mask.cols() || normals.rows != mask.rows() ||
      normals.cols != mask.cols())
    throw InvalidArgument("shadecut: flip_surface needs depth, normals and mask of one shape");
  // Checked before anything changes: a NaN or infinite depth would make every other one NaN when the
  // lowest point is set to 0 again.
  for (Eigen::Index i = 0; i < depth.size(); ++i)
    if (mask.data()[i] && !std::isfinite(depth.data()[i]))
      throw InvalidArgument("shadecut: the depth is NaN or infinite inside the mask, at pixel (" +
                            std::to_string(i / depth.cols()) + ", " + std::to_string(i % depth.cols()) + "); nothing flipped");
  for (Eigen::Index i = 0; i < depth.size(); ++i) {
    if (!mask.data()[i]) continue;
    depth.data()[i] = -depth.data()[i];
    normals.xyz(i, 0) = -normals.xyz(i, 0);
    normals.xyz(i, 1) = -normals.xyz(i, 1);
  }
  rebase_depth(depth, mask);
}

}  // namespace shadecut
