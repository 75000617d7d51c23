#include "estimate/estimate_relief_light.hpp"

#include <shadecut/support/errors.hpp>
#include <shadecut/estimate/relief_albedo.hpp>

#include "integrate/fourier.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <cstddef>
#include <vector>

namespace shadecut::detail {

namespace {

// The share of the relief's pixels brighter than the one taken to face the light: a robust maximum,
// which a few saturated or noisy pixels do not move.
constexpr double kBrightestShare = 0.005;
// Frequencies nearly perpendicular to the light carry almost no shading, and dividing by (w . tau)^2
// would let them alone decide: the divisor is (w . tau)^2 + kAxisSoftening |w|^2, i.e. frequencies
// within about 13 degrees of perpendicular count as perpendicular. Chosen a priori, not tuned.
constexpr double kAxisSoftening = 0.05;
// Frequency directions over [0, pi) and candidate tilts over [0, pi): half-degree steps.
constexpr int kDirections = 360;

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

// Signed frequency of DFT bin k of n in cycles per pixel (the Nyquist bin keeps its direction).
double signed_frequency(int k, int n) { return double(2 * k < n ? k : k - n) / n; }

// The tilt axis in [0, pi) whose implied relief has the least energy (see the header).
double tilt_axis(const std::vector<double>& field, int rows, int cols) {
  const std::vector<std::complex<double>> spectrum = periodic_spectrum(field, rows, cols);
  // The energy of the image integrated along its frequency direction, per direction.
  std::array<double, kDirections> energy{};
  for (int r = 0; r < rows; ++r) {
    const double wy = -signed_frequency(r, rows);  // y grows as the row index falls
    for (int c = 0; c < cols; ++c) {
      const double wx = signed_frequency(c, cols);
      const double w2 = wx * wx + wy * wy;
      if (w2 == 0.0) continue;
      double direction = std::atan2(wy, wx);
      if (direction < 0.0) direction += M_PI;
      const int bin = std::min(kDirections - 1, int(direction / M_PI * kDirections));
      energy[std::size_t(bin)] += std::norm(spectrum[std::size_t(r) * std::size_t(cols) + std::size_t(c)]) / w2;
    }
  }
  double best_tilt = 0.0, least = INFINITY;
  for (int t = 0; t < kDirections; ++t) {
    const double tilt = M_PI * t / kDirections;
    double implied = 0.0;
    for (int b = 0; b < kDirections; ++b) {
      const double along = std::cos(M_PI * (b + 0.5) / kDirections - tilt);
      implied += energy[std::size_t(b)] / (along * along + kAxisSoftening);
    }
    if (implied < least) least = implied, best_tilt = tilt;
  }
  return best_tilt;
}

}  // namespace

LightEstimate estimate_relief_light(const ImageF& image, const Mask& mask, std::optional<double> albedo) {
  const double median = median_intensity(image, mask);
  double brightest = 0.0;
  if (albedo) {
    brightest = *albedo;
  } else {
    std::vector<float> values;
    values.reserve(std::size_t(mask.count()));
    for (Eigen::Index i = 0; i < image.size(); ++i)
      if (mask.data()[i]) values.push_back(image.data()[i]);
    const auto at = values.begin() + std::ptrdiff_t((1.0 - kBrightestShare) * double(values.size() - 1));
    std::nth_element(values.begin(), at, values.end());
    brightest = double(*at);
  }
  if (!(brightest > 0.0)) throw InvalidArgument("shadecut: the albedo must be > 0");

  const int rows = int(image.rows()), cols = int(image.cols());
  std::vector<double> field(std::size_t(image.size()), 0.0);
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c)
      if (mask(r, c)) field[std::size_t(r) * std::size_t(cols) + std::size_t(c)] = double(image(r, c)) - median;

  LightEstimate estimate;
  const double light_z = std::clamp(median / brightest, std::cos(kMaxEstimatedSlant), 1.0);
  estimate.slant = std::acos(light_z);
  estimate.tilt = tilt_axis(field, rows, cols);
  estimate.albedo = median / light_z;
  estimate.light = Eigen::Vector3d(std::sin(estimate.slant) * std::cos(estimate.tilt),
                                   std::sin(estimate.slant) * std::sin(estimate.tilt), light_z);
  return estimate;
}

}  // namespace shadecut::detail
