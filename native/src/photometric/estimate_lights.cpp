#include <shadecut/photometric/estimate_lights.hpp>

#include <shadecut/support/errors.hpp>
#include <shadecut/support/validate.hpp>

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

namespace shadecut {
namespace {

constexpr int kMinimumPixels = 100;
// A pixel is lit in a photograph where it is brighter than this share of its brightest photograph.
constexpr double kLitShare = 0.1;
// Members of the ambiguity whose misfit to the hint is within this factor of the best one (plus
// kMisfitFloor) count toward the uncertainty.
constexpr double kNearlyAsWell = 2.0;
constexpr double kMisfitFloor = 1e-4;

void check_inputs(const std::vector<ImageF>& images, const Mask& mask, const LightHint& hint) {
  if (images.size() < 4)
    throw InvalidArgument("shadecut: estimating the lights needs four or more photographs, got " + std::to_string(images.size()));
  if (!(hint.slant > 0.0 && hint.slant < 90.0))
    throw InvalidArgument("shadecut: the hint's slant must lie in (0, 90) degrees, got " + number_text(hint.slant));
  if (!std::isfinite(hint.first_tilt))
    throw InvalidArgument("shadecut: the hint's first_tilt must be a finite angle in degrees");
  if (!hint.same_slant)
    throw InvalidArgument("shadecut: without the hint that the lights share one slant the bas-relief ambiguity stays open; give the lights");
  for (std::size_t k = 0; k < images.size(); ++k) {
    check_image(images[k], photograph_name(k));
    check_same_size(images[k], k, images[0]);
  }
  check_mask(mask, images[0]);
}

// The pixels lit in every photograph.
Mask lit_everywhere(const std::vector<ImageF>& images, const Mask& mask) {
  Mask lit = mask;
  for (Eigen::Index p = 0; p < mask.size(); ++p) {
    if (!lit.data()[p]) continue;
    float brightest = 0.0f;
    for (const ImageF& image : images) brightest = std::max(brightest, image.data()[p]);
    for (const ImageF& image : images) lit.data()[p] = lit.data()[p] && image.data()[p] > kLitShare * brightest && brightest > 0.0f;
  }
  return lit;
}

// Rank-3 factorization M = B_hat S_hat over the lit pixels: B_hat per pixel (zero elsewhere), S_hat 3 x K.
Eigen::MatrixXd factorize(const std::vector<ImageF>& images, const Mask& lit, Vectors3& scaled_normals) {
  const int k = int(images.size());
  Eigen::MatrixXd gram = Eigen::MatrixXd::Zero(k, k);
  Eigen::VectorXd row(k);
  for (Eigen::Index p = 0; p < lit.size(); ++p) {
    if (!lit.data()[p]) continue;
    for (int i = 0; i < k; ++i) row(i) = images[std::size_t(i)].data()[p];
    gram.noalias() += row * row.transpose();
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(gram);  // ascending eigenvalues
  const Eigen::MatrixXd v = eigen.eigenvectors().rightCols(3);
  const Eigen::Vector3d root = eigen.eigenvalues().tail(3).cwiseMax(1e-300).cwiseSqrt().cwiseSqrt();  // sigma^(1/2)
  scaled_normals = Vectors3::Zero(lit.size(), 3);
  for (Eigen::Index p = 0; p < lit.size(); ++p) {
    if (!lit.data()[p]) continue;
    for (int i = 0; i < k; ++i) row(i) = images[std::size_t(i)].data()[p];
    scaled_normals.row(p) = ((v.transpose() * row).array() / root.array()).cast<float>().transpose();
  }
  return root.asDiagonal() * v.transpose();
}

// Yuille & Snow: with B = B_hat A, integrability is (b x d_y b) . (a3 x a1) = (b x d_x b) . (a3 x a2)
// at every pixel (b = B_hat's row, y up); the 6-vector (a3 x a1, a3 x a2) is the null vector.
Eigen::Matrix<double, 6, 1> integrability_vector(const Vectors3& b, const Mask& lit, int& pixels) {
  const int rows = int(lit.rows()), cols = int(lit.cols());
  Eigen::Matrix<double, 6, 6> normal = Eigen::Matrix<double, 6, 6>::Zero();
  pixels = 0;
  for (int r = 1; r + 1 < rows; ++r)
    for (int c = 1; c + 1 < cols; ++c) {
      if (!lit(r, c) || !lit(r, c - 1) || !lit(r, c + 1) || !lit(r - 1, c) || !lit(r + 1, c)) continue;
      const int p = r * cols + c;
      const Eigen::Vector3d centre = b.row(p).cast<double>().transpose();
      const Eigen::Vector3d dx = 0.5 * (b.row(p + 1) - b.row(p - 1)).cast<double>().transpose();
      const Eigen::Vector3d dy = 0.5 * (b.row(p - cols) - b.row(p + cols)).cast<double>().transpose();
      Eigen::Matrix<double, 6, 1> row;
      row << centre.cross(dy), -centre.cross(dx);
      normal.noalias() += row * row.transpose();
      ++pixels;
    }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 6, 6>> eigen(normal);
  return eigen.eigenvectors().col(0);
}

// The generalized bas-relief family that integrability leaves: A(k, s, t) = [(w x a) / k + s a,
// (u x a) / k + t a, k a], a = u x w normalized, for the null vector (w, u) = (a3 x a1, a3 x a2).
class BasReliefFamily {
 public:
  BasReliefFamily(const Eigen::Matrix<double, 6, 1>& null_vector, const Eigen::MatrixXd& s_hat, const LightHint& hint)
      : w_(null_vector.head<3>()), u_(null_vector.tail<3>()), s_hat_(s_hat),
        first_side_(std::cos(hint.first_tilt * M_PI / 180.0), std::sin(hint.first_tilt * M_PI / 180.0)),
        slant_(hint.slant * M_PI / 180.0) {
    axis_ = u_.cross(w_).normalized();
  }
  const Eigen::Vector3d& axis() const { return axis_; }

  // The lights (3 x K, unnormalized) of member (k, s, t).
  Eigen::MatrixXd lights(double k, double s, double t) const {
    Eigen::Matrix3d a;
    a.col(0) = w_.cross(axis_) / k + s * axis_;
    a.col(1) = u_.cross(axis_) / k + t * axis_;
    a.col(2) = k * axis_;
    return a.inverse() * s_hat_;
  }

  // How far the member's lights are from equal strength, the hint's slant and lights all around;
  // +infinity where a light is
  // below the horizon or the first light comes from more than 90 degrees off the hint's side.
  double misfit(const Eigen::MatrixXd& lights) const {
    const Eigen::Index count = lights.cols();
    if ((lights.row(2).array() <= 0.0).any() || !lights.allFinite()) return std::numeric_limits<double>::infinity();
    if (!(lights.col(0).head<2>().dot(first_side_) > 0.0)) return std::numeric_limits<double>::infinity();
    const Eigen::ArrayXd length = lights.colwise().norm().transpose().array();
    const Eigen::ArrayXd slant = (lights.row(2).transpose().array() / length).min(1.0).acos();
    const double relative = ((length - length.mean()) / length.mean()).square().sum() / double(count);
    const double spread = (slant - slant_).square().sum() / double(count);
    // Around the subject: the lights' image-plane directions cancel about, rather than gather (a
    // nearly singular member of the family turns every light alike).
    const Eigen::Vector2d around = lights.topRows(2).colwise().normalized().rowwise().mean();
    return relative + spread + around.squaredNorm();
  }

 private:
  Eigen::Vector3d w_, u_, axis_;
  Eigen::MatrixXd s_hat_;
  Eigen::Vector2d first_side_;
  double slant_;
};

struct Member {
  double k = 1.0, s = 0.0, t = 0.0, misfit = std::numeric_limits<double>::infinity();
};

// The best member on a grid of (log |k|, s, t) around `centre`, `steps` each way of `step`; every
// member visited is offered to `visit`.
template <class Visit>
Member search(const BasReliefFamily& family, double sign, const Member& centre, int steps, double step, Visit visit) {
  Member best;
  for (int i = -steps; i <= steps; ++i)
    for (int j = -steps; j <= steps; ++j)
      for (int l = -steps; l <= steps; ++l) {
        Member m{sign * std::abs(centre.k) * std::exp(i * step), centre.s + j * step, centre.t + l * step};
        const Eigen::MatrixXd lights = family.lights(m.k, m.s, m.t);
        m.misfit = family.misfit(lights);
        visit(m, lights);
        if (m.misfit < best.misfit) best = m;
      }
  return best;
}

Eigen::MatrixXd unit_columns(const Eigen::MatrixXd& lights) { return lights.colwise().normalized(); }

}  // namespace

LightEstimate estimate_photometric_lights(const std::vector<ImageF>& images, const Mask& mask, const LightHint& hint) {
  check_inputs(images, mask, hint);
  const Mask lit = lit_everywhere(images, mask);
  Vectors3 scaled_normals;
  Eigen::MatrixXd s_hat = factorize(images, lit, scaled_normals);
  // Lights of about unit length, so that the family's parameters are of order one.
  const double scale = std::sqrt(s_hat.colwise().squaredNorm().mean());
  s_hat /= scale;
  scaled_normals *= float(scale);
  LightEstimate estimate;
  const Eigen::Matrix<double, 6, 1> null_vector = integrability_vector(scaled_normals, lit, estimate.pixels);
  if (estimate.pixels < kMinimumPixels)
    throw InvalidArgument("shadecut: only " + std::to_string(estimate.pixels) +
                          " pixels are lit in every photograph (with their neighbours); the lights cannot be estimated");
  // The null vector's sign is the convex / concave choice: both families are searched.
  const BasReliefFamily families[2] = {BasReliefFamily(null_vector, s_hat, hint), BasReliefFamily(-null_vector, s_hat, hint)};
  // The normals face the viewer: b . a3 = k (b . axis) > 0 for most pixels fixes the sign of k.
  Eigen::Index facing = 0, counted = 0;
  for (Eigen::Index p = 0; p < lit.size(); ++p)
    if (lit.data()[p]) {
      facing += scaled_normals.row(p).cast<double>().dot(families[0].axis()) > 0.0;
      ++counted;
    }
  const double sign = 2 * facing >= counted ? 1.0 : -1.0;
  const auto ignore = [](const Member&, const Eigen::MatrixXd&) {};
  Member fine;
  int chosen = 0;
  for (int f = 0; f < 2; ++f) {
    const Member coarse = search(families[f], sign, Member{}, 30, 0.1, ignore);
    const Member refined = search(families[f], sign, coarse, 10, 0.01, ignore);
    if (refined.misfit < fine.misfit) {
      fine = refined;
      chosen = f;
    }
  }
  if (!std::isfinite(fine.misfit))
    throw InvalidArgument("shadecut: no lights above the horizon fit the photographs and the hint");
  const BasReliefFamily& family = families[chosen];
  const Eigen::MatrixXd best = unit_columns(family.lights(fine.k, fine.s, fine.t));
  estimate.lights = best.transpose();
  estimate.hint_misfit = fine.misfit;
  estimate.uncertainty.assign(std::size_t(best.cols()), 0.0);
  search(family, sign, fine, 10, 0.01, [&](const Member& m, const Eigen::MatrixXd& lights) {
    if (!(m.misfit <= kNearlyAsWell * fine.misfit + kMisfitFloor)) return;
    const Eigen::MatrixXd unit = unit_columns(lights);
    for (Eigen::Index k = 0; k < best.cols(); ++k)
      estimate.uncertainty[std::size_t(k)] = std::max(
          estimate.uncertainty[std::size_t(k)], std::acos(std::clamp(unit.col(k).dot(best.col(k)), -1.0, 1.0)) * 180.0 / M_PI);
  });
  return estimate;
}

}  // namespace shadecut
