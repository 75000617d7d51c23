#include "estimate/estimate_relief_light.hpp"

#include <shadecut/support/errors.hpp>
#include <shadecut/estimate/relief_albedo.hpp>

#include "integrate/fourier.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <cstddef>
#include <tuple>
#include <utility>
#include <vector>

namespace shadecut::detail {

namespace {

// The share of the relief's pixels brighter than the one taken to face the light: a robust maximum,
// which a few saturated or noisy pixels do not move.
constexpr double kBrightestShare = 0.005;
// The largest slant read from the brightest pixels: paint brighter than the relief's base makes the
// ratio median / brightest small, i.e. the light grazing; the slant stops at this a-priori 45 degrees
// (the middle of the possible range) rather than follow paint toward the horizon.
constexpr double kMostObliqueReadSlant = 45.0 * M_PI / 180.0;
// Standard deviation (pixels) of the Gaussian the image is smoothed with before its derivatives are
// taken: it damps pixel noise and JPEG blocks; much wider, it blurs a joint's lit and dark walls into
// one symmetric dip. How it was chosen: docs/comparison_methods.md, "Reliefs".
constexpr double kGrooveScale = 2.0;
// Candidate tilts over [0, 2 pi): half-degree steps.
constexpr int kTilts = 720;

// The image's periodic component (Moisan, "Periodic plus smooth image decomposition", 2011),
// transformed: the image minus the smooth field whose Laplacian is the jump across the frame's
// opposite edges, so that those edges add no spectrum along the axes.
std::vector<std::complex<double>> periodic_spectrum(const std::vector<double>& field, int rows, int cols) {
  auto at = [cols](int r, int c) { return std::size_t(r) * std::size_t(cols) + std::size_t(c); };
  // The jumps lie on the frame's edges only, so their spectrum is two 1-D transforms: the jump down
  // column c, j(c), added at (0, c) and taken at (rows - 1, c), transforms to
  // (1 - e^{2 pi i u / rows}) J(v), and likewise across the rows. (A 2-D transform of the jumps' field
  // cost as much as the image's own.)
  std::vector<std::complex<double>> down(static_cast<std::size_t>(cols)), across(static_cast<std::size_t>(rows));
  for (int c = 0; c < cols; ++c) down[std::size_t(c)] = field[at(rows - 1, c)] - field[at(0, c)];
  for (int r = 0; r < rows; ++r) across[std::size_t(r)] = field[at(r, cols - 1)] - field[at(r, 0)];
  fourier_2d(down, 1, cols, FourierDirection::Forward);
  fourier_2d(across, rows, 1, FourierDirection::Forward);
  std::vector<double> row_cosine(static_cast<std::size_t>(rows)), column_cosine(static_cast<std::size_t>(cols));
  std::vector<std::complex<double>> row_edge(static_cast<std::size_t>(rows)), column_edge(static_cast<std::size_t>(cols));
  for (int r = 0; r < rows; ++r) {
    row_cosine[std::size_t(r)] = std::cos(2.0 * M_PI * r / rows);
    row_edge[std::size_t(r)] = 1.0 - std::polar(1.0, 2.0 * M_PI * r / rows);
  }
  for (int c = 0; c < cols; ++c) {
    column_cosine[std::size_t(c)] = std::cos(2.0 * M_PI * c / cols);
    column_edge[std::size_t(c)] = 1.0 - std::polar(1.0, 2.0 * M_PI * c / cols);
  }

  std::vector<std::complex<double>> spectrum(field.begin(), field.end());
  fourier_2d(spectrum, rows, cols, FourierDirection::Forward);
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) {
      if (r == 0 && c == 0) continue;
      const double laplacian = 2.0 * row_cosine[std::size_t(r)] + 2.0 * column_cosine[std::size_t(c)] - 4.0;
      const std::complex<double> boundary = row_edge[std::size_t(r)] * down[std::size_t(c)] +
                                            column_edge[std::size_t(c)] * across[std::size_t(r)];
      spectrum[at(r, c)] -= boundary / laplacian;
    }
  }
  return spectrum;
}

// The third moments of the image's gradient (gx, gy), summed: gx^3, gx^2 gy, gx gy^2 and gy^3. Only
// their direction is used, so they are not divided by the count.
struct GradientSkew {
  double xxx = 0.0, xxy = 0.0, xyy = 0.0, yyy = 0.0;
  long count = 0;

  void add(double gx, double gy) {
    xxx += gx * gx * gx, xxy += gx * gx * gy, xyy += gx * gy * gy, yyy += gy * gy * gy;
    ++count;
  }
  // The summed cube of the derivative along the direction at `angle` (radians from +x, y up).
  double along(double angle) const {
    const double c = std::cos(angle), s = std::sin(angle);
    return xxx * c * c * c + 3.0 * xxy * c * c * s + 3.0 * xyy * c * s * s + yyy * s * s * s;
  }
  // The direction along which the derivative is most negatively skewed; 0 without a gradient.
  double most_negative() const {
    double best = 0.0, least = 0.0;
    for (int t = 0; t < kTilts; ++t) {
      const double angle = 2.0 * M_PI * t / kTilts, value = along(angle);
      if (value < least) least = value, best = angle;
    }
    return best;
  }
};

// The gradient (x right, y up, per pixel) of the image's periodic component smoothed by a Gaussian of
// kGrooveScale pixels, both taken in the Fourier domain: x into `gx`, y into `gy`, row-major.
void smoothed_gradient(const std::vector<double>& field, int rows, int cols, std::vector<double>& gx,
                       std::vector<double>& gy) {
  const std::vector<std::complex<double>> spectrum = periodic_spectrum(field, rows, cols);
  std::vector<std::complex<double>> along_x(spectrum.size()), along_y(spectrum.size());
  const std::complex<double> i(0.0, 1.0);
  for (int r = 0; r < rows; ++r) {
    const double wy = -angular_frequency(r, rows);  // y grows as the row index falls
    for (int c = 0; c < cols; ++c) {
      const double wx = angular_frequency(c, cols);
      const std::size_t at = std::size_t(r) * std::size_t(cols) + std::size_t(c);
      const double gaussian = std::exp(-0.5 * kGrooveScale * kGrooveScale * (wx * wx + wy * wy));
      along_x[at] = i * wx * gaussian * spectrum[at];
      along_y[at] = i * wy * gaussian * spectrum[at];
    }
  }
  fourier_2d(along_x, rows, cols, FourierDirection::Inverse);
  fourier_2d(along_y, rows, cols, FourierDirection::Inverse);
  gx.resize(spectrum.size()), gy.resize(spectrum.size());
  for (std::size_t k = 0; k < spectrum.size(); ++k) gx[k] = along_x[k].real(), gy[k] = along_y[k].real();
}

// The relief's light tilt (see the header) and its scatter: the RMS angle (radians) between the
// light at `slant` with the whole relief's tilt and with each quadrant's own.
std::pair<double, double> tilt_and_scatter(const std::vector<double>& field, const Mask& mask, double slant) {
  const int rows = int(mask.rows()), cols = int(mask.cols());
  std::vector<double> gx, gy;
  smoothed_gradient(field, rows, cols, gx, gy);
  GradientSkew whole;
  std::array<GradientSkew, 4> quadrants;
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) {
      if (!mask(r, c)) continue;
      const std::size_t at = std::size_t(r) * std::size_t(cols) + std::size_t(c);
      whole.add(gx[at], gy[at]);
      quadrants[std::size_t(2 * (2 * r >= rows) + (2 * c >= cols))].add(gx[at], gy[at]);
    }
  const double tilt = whole.most_negative();
  double squares = 0.0;
  int counted = 0;
  for (const GradientSkew& quadrant : quadrants) {
    if (quadrant.count == 0) continue;
    const double cosine = std::cos(slant) * std::cos(slant) +
                          std::sin(slant) * std::sin(slant) * std::cos(quadrant.most_negative() - tilt);
    const double angle = std::acos(std::clamp(cosine, -1.0, 1.0));
    squares += angle * angle, ++counted;
  }
  return {tilt, std::sqrt(squares / std::max(counted, 1))};
}

// The brightest of the relief's pixels that are not outliers: the (1 - kBrightestShare) quantile.
double brightest_intensity(const ImageF& image, const Mask& mask) {
  std::vector<float> values;
  values.reserve(std::size_t(mask.count()));
  for (Eigen::Index i = 0; i < image.size(); ++i)
    if (mask.data()[i]) values.push_back(image.data()[i]);
  const auto at = values.begin() + std::ptrdiff_t((1.0 - kBrightestShare) * double(values.size() - 1));
  std::nth_element(values.begin(), at, values.end());
  return double(*at);
}

}  // namespace

LightEstimate estimate_relief_light(const ImageF& image, const Mask& mask, std::optional<double> albedo) {
  const double median = median_intensity(image, mask);
  const double brightest = albedo ? *albedo : brightest_intensity(image, mask);
  if (!(brightest > 0.0)) throw InvalidArgument("shadecut: the albedo must be > 0");

  const int rows = int(image.rows()), cols = int(image.cols());
  std::vector<double> field(std::size_t(image.size()), 0.0);
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c)
      if (mask(r, c)) field[std::size_t(r) * std::size_t(cols) + std::size_t(c)] = double(image(r, c)) - median;

  LightEstimate estimate;
  const double read_slant = std::acos(std::clamp(median / brightest, std::cos(kMaxEstimatedSlant), 1.0));
  estimate.slant = albedo ? read_slant : std::min(read_slant, kMostObliqueReadSlant);
  const double light_z = std::cos(estimate.slant);
  std::tie(estimate.tilt, estimate.uncertainty) = tilt_and_scatter(field, mask, estimate.slant);
  estimate.albedo = median / light_z;
  estimate.light = Eigen::Vector3d(std::sin(estimate.slant) * std::cos(estimate.tilt),
                                   std::sin(estimate.slant) * std::sin(estimate.tilt), light_z);
  return estimate;
}

}  // namespace shadecut::detail
