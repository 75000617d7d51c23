#include <shadecut/support/rebase_depth.hpp>

#include <shadecut/support/mask_components.hpp>

#include <algorithm>
#include <limits>
#include <vector>

namespace shadecut {

void rebase_depth(ImageF& depth, const Mask& mask) {
  // A full frame (every relief) is one component: no labels needed.
  if (mask.size() > 0 && mask.all()) {
    depth -= depth.minCoeff();
    return;
  }
  const MaskComponents components = mask_components(mask);
  std::vector<float> minimum(std::size_t(components.count), std::numeric_limits<float>::infinity());
  for (Eigen::Index i = 0; i < depth.size(); ++i) {
    if (!mask.data()[i]) continue;
    float& lowest = minimum[std::size_t(components.labels.data()[i])];
    lowest = std::min(lowest, depth.data()[i]);
  }
  for (Eigen::Index i = 0; i < depth.size(); ++i)
    if (mask.data()[i]) depth.data()[i] -= minimum[std::size_t(components.labels.data()[i])];
}

}  // namespace shadecut
