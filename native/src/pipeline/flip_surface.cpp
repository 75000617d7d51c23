#include <shadecut/pipeline/flip_surface.hpp>

#include <shadecut/support/errors.hpp>
#include <shadecut/support/rebase_depth.hpp>

namespace shadecut {

void flip_surface(ImageF& depth, NormalMap& normals, const Mask& mask) {
  if (depth.rows() != mask.rows() || depth.cols() != mask.cols() || normals.rows != mask.rows() ||
      normals.cols != mask.cols())
    throw InvalidArgument("shadecut: flip_surface needs depth, normals and mask of one shape");
  for (Eigen::Index i = 0; i < depth.size(); ++i) {
    if (!mask.data()[i]) continue;
    depth.data()[i] = -depth.data()[i];
    normals.xyz(i, 0) = -normals.xyz(i, 0);
    normals.xyz(i, 1) = -normals.xyz(i, 1);
  }
  rebase_depth(depth, mask);
}

}  // namespace shadecut
