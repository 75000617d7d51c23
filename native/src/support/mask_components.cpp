#include <shadecut/support/mask_components.hpp>

#include <numeric>
#include <vector>

namespace shadecut {

namespace {

// Union-find over pixel indices; the root of a set is its smallest index, so that a component's
// root is its first pixel in raster order.
class DisjointSets {
 public:
  explicit DisjointSets(std::size_t size) : parent_(size) { std::iota(parent_.begin(), parent_.end(), std::size_t(0)); }

  std::size_t root(std::size_t i) {
    while (parent_[i] != i) i = parent_[i] = parent_[parent_[i]];
    return i;
  }

  void join(std::size_t a, std::size_t b) {
    a = root(a);
    b = root(b);
    if (a < b) parent_[b] = a;
    else parent_[a] = b;
  }

 private:
  std::vector<std::size_t> parent_;
};

}  // namespace

MaskComponents mask_components(const Mask& mask) {
  const Eigen::Index rows = mask.rows(), cols = mask.cols();
  MaskComponents result;
  // A full frame (every relief) is one component; the union-find would cost a pass over every pixel for nothing.
  if (mask.size() > 0 && mask.all()) {
    result.labels = Labels::Zero(rows, cols);
    result.count = 1;
    return result;
  }
  DisjointSets sets(std::size_t(mask.size()));
  for (Eigen::Index r = 0; r < rows; ++r) {
    for (Eigen::Index c = 0; c < cols; ++c) {
      if (!mask(r, c)) continue;
      const std::size_t p = std::size_t(r * cols + c);
      if (c > 0 && mask(r, c - 1)) sets.join(p, p - 1);
      if (r > 0 && mask(r - 1, c)) sets.join(p, p - std::size_t(cols));
    }
  }
  result.labels = Labels::Constant(rows, cols, -1);
  for (Eigen::Index p = 0; p < mask.size(); ++p) {
    if (!mask.data()[p]) continue;
    const std::size_t root = sets.root(std::size_t(p));
    // The root comes first in raster order, so it is labelled before any other pixel of its set.
    result.labels.data()[p] = std::size_t(p) == root ? result.count++ : result.labels.data()[root];
  }
  return result;
}

}  // namespace shadecut
