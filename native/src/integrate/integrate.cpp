#include <shadecut/support/errors.hpp>
#include <shadecut/integrate/integrate.hpp>
#include <shadecut/support/mask_components.hpp>
#include <shadecut/support/validate.hpp>

#include "support/enum_names.hpp"
#include "integrate/grid_poisson.hpp"
#include "integrate/fourier.hpp"
#include "support/parallel.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace shadecut {

namespace {

// Below this n_z a normal is treated as grazing: its slope is the clamp value, in the direction the
// normal tilts.
constexpr double kGrazingNz = 1e-6;

// Relative residual at which the Poisson solve stops: the depth then matches the exact least-squares
// solution to about 1e-7 of its range (tests/cpp/test_integrate.cpp compares it with a direct solve).
constexpr double kPoissonTolerance = 1e-8;

struct Gradients {
  std::vector<double> p;  // dz/dx per pixel, x = column
  std::vector<double> q;  // dz/dy per pixel, y up, so dz/drow = -q
};

void validate(const NormalMap& normals, const Mask& mask, double max_slope) {
  if (normals.rows <= 0 || normals.cols <= 0) {
    throw InvalidArgument("integrate_normals: the normal map is empty");
  }
  if (normals.xyz.rows() != normals.size()) {
    throw InvalidArgument("integrate_normals: the normal map holds " + std::to_string(normals.xyz.rows()) +
                          " vectors for " + std::to_string(normals.rows) + " x " + std::to_string(normals.cols) +
                          " pixels");
  }
  if (mask.rows() != normals.rows || mask.cols() != normals.cols) {
    throw InvalidArgument("integrate_normals: the mask is " + std::to_string(mask.rows()) + " x " +
                          std::to_string(mask.cols()) + " but the normals are " + std::to_string(normals.rows) +
                          " x " + std::to_string(normals.cols));
  }
  if (!(max_slope >= kMinMaxSlope) || !std::isfinite(max_slope)) {
    throw InvalidArgument("shadecut: max_slope must be finite and at least " + number_text(kMinMaxSlope) +
                          " (depth pixels per pixel; below, every normal is clamped to within a degree of the "
                          "viewer: a flat surface); got " + number_text(max_slope));
  }
}

Gradients surface_gradients(const NormalMap& normals, const Mask& mask, double max_slope) {
  const Eigen::Index count = normals.size();
  Gradients gradients{std::vector<double>(count, 0.0), std::vector<double>(count, 0.0)};
  const bool* inside = mask.data();
  for (Eigen::Index i = 0; i < count; ++i) {
    if (!inside[i]) continue;
    const double nx = normals.xyz(i, 0);
    const double ny = normals.xyz(i, 1);
    const double nz = normals.xyz(i, 2);
    if (!std::isfinite(nx) || !std::isfinite(ny) || !std::isfinite(nz)) {
      throw InvalidArgument("integrate_normals: non-finite normal at pixel (" + std::to_string(i / normals.cols) +
                            ", " + std::to_string(i % normals.cols) + ")");
    }
    if (nx == 0.0 && ny == 0.0 && nz == 0.0) {
      throw InvalidArgument("integrate_normals: zero normal at pixel (" + std::to_string(i / normals.cols) + ", " +
                            std::to_string(i % normals.cols) + ") inside the mask");
    }
    if (nz < 0.0) {
      throw InvalidArgument("integrate_normals: the normal at pixel (" + std::to_string(i / normals.cols) + ", " +
                            std::to_string(i % normals.cols) + ") faces away from the viewer (n_z = " +
                            std::to_string(nz) + "), which no depth map has; fold_back_facing turns such normals "
                            "into grazing ones");
    }
    const double depth_axis = std::max(nz, kGrazingNz);
    gradients.p[i] = std::clamp(-nx / depth_axis, -max_slope, max_slope);
    gradients.q[i] = std::clamp(-ny / depth_axis, -max_slope, max_slope);
  }
  return gradients;
}

// The depth of each component is only defined up to a constant; fixing its minimum at 0 is the
// documented gauge. Pixels outside the mask become 0.
ImageF shift_components_to_zero(const std::vector<double>& depth, const MaskComponents& components) {
  const int rows = int(components.labels.rows());
  const int cols = int(components.labels.cols());
  std::vector<double> minimum(std::size_t(components.count), std::numeric_limits<double>::infinity());
  for (int r = 0; r < rows; ++r) {
    const std::int32_t* label = &components.labels(r, 0);
    for (int c = 0; c < cols; ++c) {
      if (label[c] >= 0) minimum[label[c]] = std::min(minimum[label[c]], depth[std::size_t(r) * cols + c]);
    }
  }
  ImageF shifted = ImageF::Zero(rows, cols);
  for (int r = 0; r < rows; ++r) {
    const std::int32_t* label = &components.labels(r, 0);
    for (int c = 0; c < cols; ++c) {
      if (label[c] >= 0) shifted(r, c) = float(depth[std::size_t(r) * cols + c] - minimum[label[c]]);
    }
  }
  return shifted;
}

// Least squares over the mask's own edges: sum over 4-neighbour pairs (a, b) of (z_b - z_a - g_ab)^2,
// g_ab being the mean of the two pixels' gradients along the edge.
std::vector<double> integrate_poisson(const Gradients& gradients, const Mask& mask, const Progress& progress) {
  const std::size_t cols = std::size_t(mask.cols());
  const std::size_t pixel_count = std::size_t(mask.size());
  detail::EdgeRises rises{std::vector<double>(pixel_count, 0.0), std::vector<double>(pixel_count, 0.0)};
  for (std::size_t a = 0; a < pixel_count; ++a) {
    if (a % cols + 1 < cols) rises.right[a] = 0.5 * (gradients.p[a] + gradients.p[a + 1]);
    if (a + cols < pixel_count) rises.down[a] = -0.5 * (gradients.q[a] + gradients.q[a + cols]);  // y is up
  }
  return detail::solve_grid_poisson(mask, rises, kPoissonTolerance, progress);
}

// Frankot & Chellappa (1988): the depth whose Fourier-domain gradient is closest to (p, q), computed
// over the whole rectangle with zero gradients outside the mask. The periodic Fourier basis cannot
// hold a linear ramp, so the mean masked gradient is taken out first and, with keep_ramp, added back
// as a plane; without that a tilted plane would come out flat (and the depth tiles).
std::vector<double> integrate_frankot_chellappa(Gradients gradients, const Mask& mask, bool keep_ramp) {
  const int rows = int(mask.rows());
  const int cols = int(mask.cols());
  const std::size_t pixel_count = std::size_t(rows) * cols;
  const bool* inside = mask.data();

  double mean_p = 0.0;
  double mean_q = 0.0;
  std::size_t inside_count = 0;
  for (std::size_t i = 0; i < pixel_count; ++i) {
    if (!inside[i]) continue;
    mean_p += gradients.p[i];
    mean_q += gradients.q[i];
    ++inside_count;
  }
  std::vector<double> depth(pixel_count, 0.0);
  if (inside_count == 0) return depth;
  mean_p /= double(inside_count);
  mean_q /= double(inside_count);

  // One complex transform carries both real fields: f = p + i q.
  std::vector<std::complex<double>> field(pixel_count, 0.0);
  for (std::size_t i = 0; i < pixel_count; ++i) {
    if (inside[i]) field[i] = {gradients.p[i] - mean_p, gradients.q[i] - mean_q};
  }
  gradients = {};  // the spectra need the memory more
  detail::fourier_2d(field, rows, cols, detail::FourierDirection::Forward);

  std::vector<std::complex<double>> z_spectrum(pixel_count);
  const std::complex<double> j(0.0, 1.0);
  for (int r = 0; r < rows; ++r) {
    const double wy = -detail::angular_frequency(r, rows);  // y grows as the row index falls
    const int mirror_r = r == 0 ? 0 : rows - r;
    for (int c = 0; c < cols; ++c) {
      const double wx = detail::angular_frequency(c, cols);
      const double norm = wx * wx + wy * wy;
      const std::size_t i = std::size_t(r) * cols + c;
      if (norm == 0.0) {
        z_spectrum[i] = 0.0;
        continue;
      }
      // P and Q from F(k) and F(-k): p and q are real, so their spectra are Hermitian.
      const std::complex<double> f = field[i];
      const std::complex<double> f_mirror = std::conj(field[std::size_t(mirror_r) * cols + (c == 0 ? 0 : cols - c)]);
      const std::complex<double> p_hat = 0.5 * (f + f_mirror), q_hat = -0.5 * j * (f - f_mirror);
      z_spectrum[i] = -j * (wx * p_hat + wy * q_hat) / norm;
    }
  }
  field = {};
  detail::fourier_2d(z_spectrum, rows, cols, detail::FourierDirection::Inverse);
  for (int r = 0; r < rows; ++r) {
    const double y = -r;
    for (int c = 0; c < cols; ++c) {
      const std::size_t i = std::size_t(r) * cols + c;
      depth[i] = z_spectrum[i].real() + (keep_ramp ? mean_p * c + mean_q * y : 0.0);
    }
  }
  return depth;
}

}  // namespace

const std::vector<std::string>& integrator_names() {
  static const std::vector<std::string> names{"poisson", "frankot_chellappa"};
  return names;
}

Integrator parse_integrator(const std::string& name) { return parse_enum<Integrator>(integrator_names(), name, "integrator"); }

std::string to_string(Integrator integrator) { return integrator_names().at(std::size_t(integrator)); }

int fold_back_facing(NormalMap& normals, const Mask& mask) {
  if (mask.rows() != normals.rows || mask.cols() != normals.cols || normals.xyz.rows() != normals.size())
    throw InvalidArgument("fold_back_facing: the mask and the normal map differ in size");
  int folded = 0;
  for (Eigen::Index i = 0; i < normals.size(); ++i) {
    if (!mask.data()[i] || !(normals.xyz(i, 2) < 0.0f)) continue;
    const Eigen::Vector2f tilt = normals.xyz.block<1, 2>(i, 0).transpose();
    const float length = tilt.norm();
    normals.xyz.row(i) = length > 0.0f ? Eigen::RowVector3f(tilt.x() / length, tilt.y() / length, 0.0f)
                                       : Eigen::RowVector3f(0.0f, 0.0f, 1.0f);
    ++folded;
  }
  return folded;
}

ImageF integrate_normals(const NormalMap& normals, const Mask& mask, Integrator method, double max_slope,
                         const Progress& progress) {
  validate(normals, mask, max_slope);
  Gradients gradients = surface_gradients(normals, mask, max_slope);
  const MaskComponents components = mask_components(mask);
  switch (method) {
    case Integrator::Poisson:
      return shift_components_to_zero(integrate_poisson(gradients, mask, progress), components);
    case Integrator::FrankotChellappa:
      return shift_components_to_zero(integrate_frankot_chellappa(std::move(gradients), mask, true), components);
  }
  throw InvalidArgument("integrate_normals: unknown integrator " + std::to_string(int(method)));
}

ImageF integrate_periodic(const NormalMap& normals, double max_slope) {
  const Mask everywhere = Mask::Constant(normals.rows, normals.cols, true);
  validate(normals, everywhere, max_slope);
  const std::vector<double> depth =
      integrate_frankot_chellappa(surface_gradients(normals, everywhere, max_slope), everywhere, false);
  return shift_components_to_zero(depth, mask_components(everywhere));
}

}  // namespace shadecut
