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
#include <functional>
#include <limits>
#include <utility>
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

// The radius of the boxes whose three passes blur by a Gaussian of standard deviation sigma pixels
// (their variance 3 (w^2 - 1) / 12 is sigma^2), sigma at most the frame's larger side.
int box_radius(double sigma, const Mask& mask) {
  const double largest = double(std::max(mask.rows(), mask.cols()));
  const double clamped = std::min(sigma, largest);
  return int(std::lround((std::sqrt(4.0 * clamped * clamped + 1.0) - 1.0) / 2.0));
}

// Three boxes of `radius` each way over `field`, in place, the frame's outside taken as zero.
// `scratch`, of the field's size, is shared by the passes: a fresh 8-byte-per-pixel field each pass
// costs more in page faults than the pass itself at 4 MP.
void box_blur(Field& field, int radius, Field& scratch) {
  for (int pass = 0; pass < 3; ++pass) {
    box_along_rows(field, radius);
    box_down_columns(field, scratch, radius);
    field.swap(scratch);
  }
}

// (i - centre)^power at i = 0 .. length - 1, blurred by the three boxes of `radius`: along one axis,
// the blurred full frame's weight (power 0) and its moments (a full frame's are products of two).
Field blurred_line(Eigen::Index length, double centre, int power, int radius) {
  Field line(1, length);
  for (Eigen::Index i = 0; i < length; ++i) line(0, i) = std::pow(double(i) - centre, power);
  for (int pass = 0; pass < 3; ++pass) box_along_rows(line, radius);
  return line;
}

// The masked Gaussian blur of `values` (standard deviation sigma pixels): three boxes each way over
// the values and over the mask, divided. 0 off the mask. `values` is taken by value and blurred in
// place: the callers hand over fields made for it.
Field masked_blur(Field values, const Mask& mask, double sigma) {
  const int radius = box_radius(sigma, mask);
  Field scratch(values.rows(), values.cols());
  if (mask.all()) {
    // Only the values are blurred in 2-D.
    const Field across = blurred_line(values.cols(), 0.0, 0, radius), down = blurred_line(values.rows(), 0.0, 0, radius);
    box_blur(values, radius, scratch);
    detail::parallel_for(int(values.rows()), kRowsPerChunk, 0, [&](int r) { values.row(r) /= down(0, r) * across.row(0); });
    return values;
  }
  Field weights = mask.cast<double>().array();
  values *= weights;
  box_blur(weights, radius, scratch);
  box_blur(values, radius, scratch);
  // Coefficient-wise, so written over `values` without a temporary.
  values = (weights > 0.0).select(values / weights.max(1e-300), 0.0) * mask.cast<double>().array();
  return values;
}

// The sums, over a pixel's blur window, of its weights w times 1, u, v, u^2, u v, v^2 (u, v the
// offsets from the pixel, columns and rows), and of w times the values d, u d and v d.
struct WindowMoments {
  double w = 0.0, u = 0.0, v = 0.0, uu = 0.0, uv = 0.0, vv = 0.0;
  double d = 0.0, ud = 0.0, vd = 0.0;
};

// The weighted least-squares plane a + b u + c v through a window's values, at the pixel: a, by
// Cramer's rule on the normal equations [w u v; u uu uv; v uv vv] (a b c) = (d ud vd). Where the
// window is symmetric about the pixel (u = v = uv = 0) it is the weighted mean d / w; where its
// points lie on a line the plane is not determined and the mean is taken too.
double plane_at_centre(const WindowMoments& m) {
  const double spread = m.uu * m.vv - m.uv * m.uv;  // the cofactor of w
  const double by_u = m.v * m.uv - m.u * m.vv, by_v = m.u * m.uv - m.uu * m.v;
  const double determinant = m.w * spread + m.u * by_u + m.v * by_v;
  // determinant / (w spread) lies in (0, 1] for a window not on a line.
  if (!(spread > 1e-9 * m.uu * m.vv) || !(determinant > 1e-9 * m.w * spread)) return m.d / m.w;
  return (spread * m.d + by_u * m.ud + by_v * m.vd) / determinant;
}

// The masked Gaussian-weighted least-squares plane through `values` around every pixel (standard
// deviation sigma pixels), evaluated there: first-order normalized convolution. Inside the frame and
// the mask it is masked_blur's mean; at their edges, where a one-sided window's mean lags a slope by
// about sigma times it (a relief's depth rising toward the frame's edge left a band of tilted normals
// there once its mean was taken away), the plane follows the slope. 0 off the mask.
//
// Moments about the pixel from moments about the frame's centre (x, y): sum w (x - x_p) d = sum w x d
// - x_p sum w d, and alike; centred coordinates keep the sums small. A full frame's weight moments are
// products of one-dimensional ones, so only the three value moments are blurred in 2-D.
Field local_plane(const Field& values, const Mask& mask, double sigma) {
  const int rows = int(values.rows()), cols = int(values.cols()), radius = box_radius(sigma, mask);
  const double centre_x = 0.5 * (cols - 1), centre_y = 0.5 * (rows - 1);
  Field scratch(rows, cols);
  const auto blurred = [&](auto&& value_at) {
    Field field(rows, cols);
    detail::parallel_for(rows, kRowsPerChunk, 0, [&](int r) {
      for (int c = 0; c < cols; ++c) field(r, c) = mask(r, c) ? value_at(r, c, c - centre_x, r - centre_y) : 0.0;
    });
    box_blur(field, radius, scratch);
    return field;
  };
  const Field d = blurred([&](int r, int c, double, double) { return values(r, c); });
  const Field xd = blurred([&](int r, int c, double x, double) { return x * values(r, c); });
  const Field yd = blurred([&](int r, int c, double, double y) { return y * values(r, c); });
  // The weight moments about the frame's centre: w, x w, y w, x^2 w, x y w, y^2 w at every pixel.
  std::function<WindowMoments(int, int)> weight_moments;
  std::vector<Field> weights;
  if (mask.all()) {
    for (const auto& [length, centre] : {std::pair{Eigen::Index(cols), centre_x}, std::pair{Eigen::Index(rows), centre_y}})
      for (int power = 0; power <= 2; ++power) weights.push_back(blurred_line(length, centre, power, radius));
    weight_moments = [&](int r, int c) {
      const double a0 = weights[0](0, c), a1 = weights[1](0, c), a2 = weights[2](0, c);
      const double b0 = weights[3](0, r), b1 = weights[4](0, r), b2 = weights[5](0, r);
      return WindowMoments{a0 * b0, a1 * b0, a0 * b1, a2 * b0, a1 * b1, a0 * b2};
    };
  } else {
    for (const auto& [px, py] : {std::pair{0, 0}, std::pair{1, 0}, std::pair{0, 1}, std::pair{2, 0}, std::pair{1, 1},
                                 std::pair{0, 2}})
      weights.push_back(blurred([&](int, int, double x, double y) { return std::pow(x, px) * std::pow(y, py); }));
    weight_moments = [&](int r, int c) {
      return WindowMoments{weights[0](r, c), weights[1](r, c), weights[2](r, c),
                           weights[3](r, c), weights[4](r, c), weights[5](r, c)};
    };
  }
  Field low = Field::Zero(rows, cols);
  detail::parallel_for(rows, kRowsPerChunk, 0, [&](int r) {
    for (int c = 0; c < cols; ++c) {
      if (!mask(r, c)) continue;
      const WindowMoments about_centre = weight_moments(r, c);
      if (!(about_centre.w > 0.0)) continue;
      const double x = c - centre_x, y = r - centre_y;
      WindowMoments m;
      m.w = about_centre.w;
      m.u = about_centre.u - x * about_centre.w;
      m.v = about_centre.v - y * about_centre.w;
      m.uu = about_centre.uu - 2.0 * x * about_centre.u + x * x * about_centre.w;
      m.uv = about_centre.uv - x * about_centre.v - y * about_centre.u + x * y * about_centre.w;
      m.vv = about_centre.vv - 2.0 * y * about_centre.v + y * y * about_centre.w;
      m.d = d(r, c);
      m.ud = xd(r, c) - x * d(r, c);
      m.vd = yd(r, c) - y * d(r, c);
      low(r, c) = plane_at_centre(m);
    }
  });
  return low;
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
  const Field low = local_plane(depth.cast<double>().array(), mask, 0.187 * detail_size);
  detail::parallel_for(int(depth.rows()), kRowsPerChunk, 0, [&](int r) {
    for (Eigen::Index c = 0; c < depth.cols(); ++c)
      if (mask(r, c)) depth(r, c) -= float(low(r, c));
  });
  rebase_depth(depth, mask);
}

}  // namespace shadecut
