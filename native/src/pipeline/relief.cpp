#include <shadecut/pipeline/relief.hpp>

#include <shadecut/support/errors.hpp>
#include <shadecut/support/rebase_depth.hpp>

#include "support/masked_gradient.hpp"
#include "support/parallel.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <vector>

namespace shadecut {

namespace {

using Field = Eigen::Array<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

// Columns handed to a thread at once by the vertical box: a band of rows of them stays in cache.
constexpr int kColumnsPerChunk = 256;
constexpr int kRowsPerChunk = 32;

// A box of radius r along every row of a row-major field, the frame's outside taken as zero: each row
// its own prefix sums. Rows run in parallel.
void box_along_rows(Field& field, int radius) {
  const Eigen::Index length = field.cols();
  detail::parallel_ranges(int(field.rows()), kRowsPerChunk, 0, [&](int begin, int end) {
    std::vector<double> prefix(static_cast<std::size_t>(length) + 1, 0.0);
    for (int r = begin; r < end; ++r) {
      double* row = field.data() + r * length;
      for (Eigen::Index i = 0; i < length; ++i) prefix[std::size_t(i) + 1] = prefix[std::size_t(i)] + row[i];
      for (Eigen::Index i = 0; i < length; ++i)
        row[i] = prefix[std::size_t(std::min<Eigen::Index>(length, i + radius + 1))] -
                 prefix[std::size_t(std::max<Eigen::Index>(0, i - radius))];
    }
  });
}

// The same box down every column of `in`, written to `out` (the same size, not `in`): a window of rows
// slid down, its sum kept per column, so that memory is read a row at a time (a column at a time
// strides across the whole field for each value). Bands of columns run in parallel; every column's
// sums are taken in the same order.
void box_down_columns(const Field& in, Field& out, int radius) {
  const Eigen::Index rows = in.rows(), cols = in.cols();
  detail::parallel_ranges(int(cols), kColumnsPerChunk, 0, [&](int begin, int end) {
    const Eigen::Index width = end - begin;
    std::vector<double> window(static_cast<std::size_t>(width), 0.0);
    auto add_row = [&](Eigen::Index r, double sign) {
      const double* row = in.data() + r * cols + begin;
      for (Eigen::Index c = 0; c < width; ++c) window[std::size_t(c)] += sign * row[c];
    };
    for (Eigen::Index r = 0; r <= std::min<Eigen::Index>(radius, rows - 1); ++r) add_row(r, 1.0);
    for (Eigen::Index r = 0; r < rows; ++r) {
      std::copy(window.begin(), window.end(), out.data() + r * cols + begin);
      if (r + radius + 1 < rows) add_row(r + radius + 1, 1.0);
      if (r - radius >= 0) add_row(r - radius, -1.0);
    }
  });
}

// The masked Gaussian blur of `values` (standard deviation sigma pixels): three boxes each way, whose
// variance 3 (w^2 - 1) / 12 is sigma^2, over the values and over the mask, divided. 0 off the mask.
// `values` is taken by value and blurred in place: the callers hand over fields made for it.
Field masked_blur(Field values, const Mask& mask, double sigma) {
  const double largest = double(std::max(mask.rows(), mask.cols()));
  const int radius = int(std::lround((std::sqrt(4.0 * std::min(sigma, largest) * std::min(sigma, largest) + 1.0) - 1.0) / 2.0));
  // One scratch field for every column pass: a fresh 8-byte-per-pixel field each pass costs more in
  // page faults than the pass itself at 4 MP.
  Field scratch(values.rows(), values.cols());
  auto blur = [radius, &scratch](Field& field) {
    for (int pass = 0; pass < 3; ++pass) {
      box_along_rows(field, radius);
      box_down_columns(field, scratch, radius);
      field.swap(scratch);
    }
  };
  if (mask.all()) {
    // A full frame's blurred mask is separable, the product of two 1-D blurs of ones: only the values
    // are blurred in 2-D.
    auto blurred_ones = [&](Eigen::Index length) {
      Field ones = Field::Ones(1, length);
      for (int pass = 0; pass < 3; ++pass) box_along_rows(ones, radius);
      return ones;
    };
    const Field across = blurred_ones(values.cols()), down = blurred_ones(values.rows());
    blur(values);
    detail::parallel_for(int(values.rows()), kRowsPerChunk, 0, [&](int r) { values.row(r) /= down(0, r) * across.row(0); });
    return values;
  }
  Field weights = mask.cast<double>().array();
  values *= weights;
  blur(weights);
  blur(values);
  // Coefficient-wise, so written over `values` without a temporary.
  values = (weights > 0.0).select(values / weights.max(1e-300), 0.0) * mask.cast<double>().array();
  return values;
}

// log(max(image, floor)) in double, rows in parallel (a serial pass is a visible share of a large relief's call).
Field parallel_logarithm(const ImageF& image, double floor) {
  Field logarithm(image.rows(), image.cols());
  detail::parallel_for(int(image.rows()), kRowsPerChunk, 0, [&](int r) {
    logarithm.row(r) = image.row(r).cast<double>().max(floor).log();
  });
  return logarithm;
}

// log(max(image, floor)) where masked and +infinity elsewhere, in a frame of +infinity `pad` pixels
// wide: the darkest pixel on a side is then a plain minimum, and a side with no masked pixel never
// stands darker than anything.
Field padded_logarithm(const ImageF& image, const Mask& mask, double floor, int pad) {
  const double infinity = std::numeric_limits<double>::infinity();
  Field padded = Field::Constant(image.rows() + 2 * pad, image.cols() + 2 * pad, infinity);
  detail::parallel_for(int(image.rows()), kRowsPerChunk, 0, [&](int r) {
    padded.row(r + pad).segment(pad, image.cols()) =
        mask.row(r).select(image.row(r).cast<double>().max(floor).log(), infinity);
  });
  return padded;
}

}  // namespace

Mask bright_lines(const ImageF& image, const Mask& mask, int width, double contrast) {
  if (!(contrast > 1.0)) throw InvalidArgument("shadecut: a bright line's contrast must be > 1; got " + std::to_string(contrast));
  Mask lines = Mask::Constant(image.rows(), image.cols(), false);
  if (width < 2) return lines;
  const double step = std::log(contrast);
  const int reach = width / 2;
  const Field logarithm = padded_logarithm(image, mask, 1e-6, reach);
  const Eigen::Index stride = logarithm.cols();
  detail::parallel_for(int(image.rows()), kRowsPerChunk, 0, [&](int r) {
    for (Eigen::Index c = 0; c < image.cols(); ++c) {
      if (!mask(r, c)) continue;
      const double* centre = logarithm.data() + (r + reach) * stride + (c + reach);
      // The darkest pixel within `reach` on each side: left, right, above, below.
      double left = centre[-1], right = centre[1], above = centre[-stride], below = centre[stride];
      for (int k = 2; k <= reach; ++k) {
        left = std::min(left, centre[-k]), right = std::min(right, centre[k]);
        above = std::min(above, centre[-k * stride]), below = std::min(below, centre[k * stride]);
      }
      lines(r, c) = (*centre - left > step && *centre - right > step) || (*centre - above > step && *centre - below > step);
    }
  });
  const Eigen::Index marked = lines.count(), black = (mask && image.array() <= 0.0f).count();
  if (4 * marked > mask.count() || 2 * (marked + black) >= mask.count()) lines.setConstant(false);
  return lines;
}

void flatten_relief(ImageF& depth, const Mask& mask) {
  // Least squares of z = a x + b y + c with x = c, y = -r. A row's sums (count, x, x^2, z, x z) are
  // taken in parallel and added in row order: the same bits for any number of threads.
  std::vector<Eigen::Array<double, 5, 1>> row_sums(static_cast<std::size_t>(depth.rows()));
  detail::parallel_for(int(depth.rows()), kRowsPerChunk, 0, [&](int r) {
    Eigen::Array<double, 5, 1> sums = Eigen::Array<double, 5, 1>::Zero();
    for (Eigen::Index c = 0; c < depth.cols(); ++c) {
      if (!mask(r, c)) continue;
      const double x = double(c), z = double(depth(r, c));
      sums += Eigen::Array<double, 5, 1>(1.0, x, x * x, z, x * z);
    }
    row_sums[std::size_t(r)] = sums;
  });
  Eigen::Matrix3d normal_matrix = Eigen::Matrix3d::Zero();
  Eigen::Vector3d rhs = Eigen::Vector3d::Zero();
  for (std::size_t r = 0; r < row_sums.size(); ++r) {
    const Eigen::Array<double, 5, 1>& sums = row_sums[r];
    const double y = -double(r), count = sums[0], x = sums[1];
    normal_matrix += (Eigen::Matrix3d() << sums[2], y * x, x, y * x, y * y * count, y * count, x, y * count, count).finished();
    rhs += Eigen::Vector3d(sums[4], y * sums[3], sums[3]);
  }
  if (mask.count() < 3) return;
  const Eigen::Vector3d plane = normal_matrix.ldlt().solve(rhs);  // z = a x + b y + c
  detail::parallel_for(int(depth.rows()), kRowsPerChunk, 0, [&](int r) {
    for (Eigen::Index c = 0; c < depth.cols(); ++c)
      if (mask(r, c)) depth(r, c) -= float(plane.x() * double(c) - plane.y() * double(r) + plane.z());
  });
  rebase_depth(depth, mask);
}

double relief_scale(const ImageF& image, const Mask& mask) {
  const double floor = 1e-3 * median_intensity(image, mask);
  const Field logarithm = masked_blur(parallel_logarithm(image, floor), mask, 1.0);
  // Sums per row in parallel, then over the rows in order: the same bits for any number of threads.
  std::vector<Eigen::Array3d> row_sums(static_cast<std::size_t>(image.rows()), Eigen::Array3d::Zero());
  detail::parallel_for(int(image.rows()), kRowsPerChunk, 0, [&](int r) {
    Eigen::Array3d& sums = row_sums[std::size_t(r)];
    for (Eigen::Index c = 0; c < image.cols(); ++c) {
      if (!mask(r, c)) continue;
      const detail::MaskedGradient slope = detail::masked_gradient(logarithm, mask, r, int(c));
      sums += Eigen::Array3d(logarithm(r, c), logarithm(r, c) * logarithm(r, c), slope.dx * slope.dx + slope.dy * slope.dy);
    }
  });
  double sum = 0.0, squares = 0.0, slopes = 0.0;
  for (const Eigen::Array3d& sums : row_sums) {
    sum += sums[0];
    squares += sums[1];
    slopes += sums[2];
  }
  const Eigen::Index count = mask.count();
  const double mean = sum / double(count);
  const double variance = std::max(0.0, squares / double(count) - mean * mean);
  // A uniform image has no scale (its blurred logarithm differs from a constant by rounding alone).
  if (!(slopes / double(count) > 1e-12)) return std::numeric_limits<double>::infinity();
  return 2.0 * M_PI * std::sqrt(variance / (slopes / double(count)));
}

void damp_large_forms(ImageF& depth, const Mask& mask, double detail_size) {
  if (!(detail_size > 0.0)) throw InvalidArgument("shadecut: the detail size must be > 0 pixels");
  const Field low = masked_blur(depth.cast<double>().array(), mask, 0.187 * detail_size);
  detail::parallel_for(int(depth.rows()), kRowsPerChunk, 0, [&](int r) {
    for (Eigen::Index c = 0; c < depth.cols(); ++c)
      if (mask(r, c)) depth(r, c) -= float(low(r, c));
  });
  rebase_depth(depth, mask);
}

}  // namespace shadecut
