#include <shadecut/support/downsample.hpp>

#include <shadecut/support/errors.hpp>

#include <string>

namespace shadecut {

Downsampled downsample(const ImageF& image, const Mask& mask, int factor, double min_coverage) {
  if (mask.rows() != image.rows() || mask.cols() != image.cols())
    throw InvalidArgument("shadecut: the mask is " + std::to_string(mask.rows()) + " x " + std::to_string(mask.cols()) +
                          " but the image is " + std::to_string(image.rows()) + " x " + std::to_string(image.cols()));
  if (factor < 1) throw InvalidArgument("shadecut: the downsampling factor must be >= 1, got " + std::to_string(factor));
  if (!(min_coverage > 0.0 && min_coverage <= 1.0))
    throw InvalidArgument("shadecut: the block coverage must be in (0, 1], got " + std::to_string(min_coverage));
  const Eigen::Index rows = image.rows() / factor, cols = image.cols() / factor;
  const double needed = min_coverage * factor * factor;
  Downsampled small{ImageF::Zero(rows, cols), Mask::Constant(rows, cols, false)};
  for (Eigen::Index r = 0; r < rows; ++r) {
    for (Eigen::Index c = 0; c < cols; ++c) {
      const auto inside = mask.block(r * factor, c * factor, factor, factor);
      const Eigen::Index count = inside.count();
      if (count == 0 || double(count) < needed) continue;
      small.mask(r, c) = true;
      const auto block = image.block(r * factor, c * factor, factor, factor);
      // A whole block sums as it is: the coarse levels of the graph cut keep their exact values.
      const float sum = count == factor * factor ? block.sum() : inside.select(block, 0.0f).sum();
      small.image(r, c) = sum / float(count);
    }
  }
  return small;
}

}  // namespace shadecut
