#include <shadecut/estimate/relief_albedo.hpp>

#include <shadecut/support/errors.hpp>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <vector>

namespace shadecut {

double median_intensity(const ImageF& image, const Mask& mask) {
  const Eigen::Index count = mask.count();
  if (count == 0) throw InvalidArgument("shadecut: the mask selects no pixel");
  // The (count / 2)-th smallest masked value, selected by two counting passes over 16 bits each of the
  // floats' order-preserving keys: no copy and no partial sort of the whole image, which a relief
  // asks for three times (docs/benchmarks.md has the cost).
  auto key = [](float value) {
    std::uint32_t bits;
    std::memcpy(&bits, &value, sizeof bits);
    return bits & 0x80000000u ? ~bits : bits | 0x80000000u;
  };
  std::uint64_t rank = std::uint64_t(count / 2);
  std::vector<std::uint64_t> histogram(std::size_t(1) << 16, 0);
  // The bin that holds the rank-th (from 0) counted key; rank becomes its rank inside the bin.
  auto bin_of_rank = [&] {
    std::uint32_t bin = 0;
    while (rank >= histogram[bin]) rank -= histogram[bin++];
    return bin;
  };
  for (Eigen::Index i = 0; i < image.size(); ++i)
    if (mask.data()[i]) ++histogram[key(image.data()[i]) >> 16];
  const std::uint32_t high = bin_of_rank();
  std::fill(histogram.begin(), histogram.end(), 0);
  for (Eigen::Index i = 0; i < image.size(); ++i) {
    if (!mask.data()[i]) continue;
    const std::uint32_t k = key(image.data()[i]);
    if (k >> 16 == high) ++histogram[k & 0xffffu];
  }
  const std::uint32_t found = high << 16 | bin_of_rank();
  const std::uint32_t bits = found & 0x80000000u ? found & 0x7fffffffu : ~found;
  float middle;
  std::memcpy(&middle, &bits, sizeof middle);
  if (!(middle > 0.0f)) throw InvalidArgument("shadecut: the image is dark in most of the relief; nothing to reconstruct");
  return double(middle);
}

double relief_albedo(const ImageF& image, const Mask& mask, const Eigen::Vector3d& light) {
  return median_intensity(image, mask) / light.z();
}

}  // namespace shadecut
