#include <shadecut/photometric/estimate_lights.hpp>

#include <shadecut/support/errors.hpp>
#include <shadecut/support/validate.hpp>

#include <Eigen/Dense>
#include <unsupported/Eigen/NonLinearOptimization>
#include <unsupported/Eigen/NumericalDiff>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <utility>
#include <vector>

namespace shadecut {
namespace {

constexpr int kMinimumPixels = 100;
// A pixel is lit in a photograph where it is brighter than this share of its brightest photograph.
constexpr double kLitShare = 0.1;
// "Moved around the subject": from five photographs on, the row space's own azimuths are the lights'
// (on the training materials, 5.8 degrees mean light error against 6.0 when refitted to the row
// space: docs/method.md). With four, the three free azimuths have exactly as many equations, so any
// departure from one slant lands in them whole; each is then also pulled toward its place in an even
// spread, by this weight per radian against the fit in units of a light's length (a tenth for 30
// degrees), set by that reasoning, not tuned.
constexpr double kEvenSpreadWeight = 0.1 / (30.0 * M_PI / 180.0);
constexpr int kLooseCount = 4;
// The turns about the viewer tried: a whole circle in 1 degree steps, then 1/20 degree around the best.
constexpr int kCoarseTurns = 360;
constexpr int kFineTurns = 20;
// Integrability is measured on at most this many pixels: enough for a stable mean, cheap at any size.
constexpr std::size_t kCurlSample = std::size_t(1) << 16;
// Turns whose integrability misfit is within this factor of the best one count toward the uncertainty.
constexpr double kNearlyAsWell = 1.05;

void check_inputs(const std::vector<ImageF>& images, const Mask& mask, const LightHint& hint) {
  if (images.size() < std::size_t(kFewestPhotographsToEstimateLights))
    throw InvalidArgument("shadecut: estimating the lights needs " + std::to_string(kFewestPhotographsToEstimateLights) +
                          " or more photographs, got " + std::to_string(images.size()));
  if (!(hint.slant >= kLeastHintSlant && hint.slant <= kGreatestHintSlant))
    throw InvalidArgument("shadecut: the hint's slant must lie in [" + number_text(kLeastHintSlant) + ", " +
                          number_text(kGreatestHintSlant) + "] degrees, got " + number_text(hint.slant));
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

// The lights' azimuths, up to one rotation about the viewer and a mirror, from the factorization
// alone: lights at one slant are S = (sin t cos a_k, sin t sin a_k, cos t), so the row space of
// S_hat holds the constant row and (cos a_k), (sin a_k). Its part orthogonal to the constant is a
// linear image of those two rows (less their means); the conic through its columns, mapped onto the
// unit circle, gives the azimuths.
Eigen::VectorXd azimuths_from_row_space(const Eigen::MatrixXd& s_hat) {
  const Eigen::Index count = s_hat.cols();
  const Eigen::MatrixXd basis = s_hat.transpose().householderQr().householderQ() * Eigen::MatrixXd::Identity(count, 3);
  const Eigen::Vector3d constant = basis.transpose() * Eigen::VectorXd::Constant(count, 1.0 / std::sqrt(double(count)));
  const Eigen::Matrix3d off_constant = Eigen::Matrix3d::Identity() - constant * constant.transpose() / constant.squaredNorm();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> plane(off_constant);  // eigenvalues 0, 1, 1
  const Eigen::MatrixXd v = (basis * plane.eigenvectors().rightCols(2)).transpose();  // 2 x K
  // From five lights on, a conic with its own centre (uneven azimuths leave (cos a_k), (sin a_k) with
  // a mean, which the constant row takes away); with four, one centred on the origin.
  const int terms = count >= 5 ? 5 : 3;
  Eigen::MatrixXd conic_rows(count, terms);
  for (Eigen::Index k = 0; k < count; ++k) {
    const double x = v(0, k), y = v(1, k);
    conic_rows.row(k).head<3>() << x * x, 2.0 * x * y, y * y;
    if (terms == 5) conic_rows.row(k).tail<2>() << 2.0 * x, 2.0 * y;
  }
  const Eigen::VectorXd q = conic_rows.colPivHouseholderQr().solve(Eigen::VectorXd::Ones(count));
  Eigen::Matrix2d conic;
  conic << q(0), q(1), q(1), q(2);
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();
  if (terms == 5) {
    centre = -conic.inverse() * q.tail<2>();
    conic /= 1.0 + centre.dot(conic * centre);
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> axes(conic);
  const Eigen::Matrix2d root =
      axes.eigenvectors() * axes.eigenvalues().cwiseMax(1e-12).cwiseSqrt().asDiagonal() * axes.eigenvectors().transpose();
  const Eigen::MatrixXd on_circle = root * (v.colwise() - centre);
  Eigen::VectorXd azimuths(count);
  for (Eigen::Index k = 0; k < count; ++k) azimuths(k) = std::atan2(on_circle(1, k), on_circle(0, k));
  return azimuths;
}

Eigen::MatrixXd lights_at(const Eigen::VectorXd& azimuths, double slant) {
  Eigen::MatrixXd lights(3, azimuths.size());
  lights.row(0) = std::sin(slant) * azimuths.array().cos().matrix().transpose();
  lights.row(1) = std::sin(slant) * azimuths.array().sin().matrix().transpose();
  lights.row(2).setConstant(std::cos(slant));
  return lights;
}

// The angle in [-pi, pi). By floor, not std::remainder, whose glibc 2.43 symbol version would keep
// a module built on a newer system from loading into an older Blender (compatibility.OLDEST_GLIBC).
double wrapped(double angle) { return angle - 2.0 * M_PI * std::floor((angle + M_PI) / (2.0 * M_PI)); }

// How far lights at the hint's slant and the given azimuths (the first at 0) are from the row space
// of S_hat, and from an even spread around the viewer in the row space's order.
struct AzimuthFit {
  using Scalar = double;
  using InputType = Eigen::VectorXd;
  using ValueType = Eigen::VectorXd;
  using JacobianType = Eigen::MatrixXd;
  enum { InputsAtCompileTime = Eigen::Dynamic, ValuesAtCompileTime = Eigen::Dynamic };

  AzimuthFit(const Eigen::MatrixXd& s_hat, const Eigen::VectorXd& even, double slant)
      : off_row_space_(Eigen::MatrixXd::Identity(s_hat.cols(), s_hat.cols()) -
                       s_hat.transpose() * (s_hat * s_hat.transpose()).inverse() * s_hat),
        even_(even), slant_(slant) {}
  int inputs() const { return int(even_.size()) - 1; }
  int values() const { return int(4 * even_.size()) - 1; }

  int operator()(const Eigen::VectorXd& rest, Eigen::VectorXd& residual) const {
    const Eigen::Index count = even_.size();
    Eigen::VectorXd azimuths(count);
    azimuths << 0.0, rest;
    const Eigen::MatrixXd off = lights_at(azimuths, slant_) * off_row_space_;
    residual.head(3 * count) = Eigen::Map<const Eigen::VectorXd>(off.data(), 3 * count);
    for (Eigen::Index k = 1; k < count; ++k) residual(3 * count + k - 1) = kEvenSpreadWeight * wrapped(rest(k - 1) - even_(k));
    return 0;
  }

  Eigen::MatrixXd off_row_space_;
  Eigen::VectorXd even_;
  double slant_;
};

// The lights' azimuths, the first at 0: the row space's own; with four photographs, fitted to it by
// Levenberg-Marquardt with each pulled toward its place in an even spread around the viewer, in the
// order the row space gives. `misfit`: the RMS distance of lights at the hint's slant and those
// azimuths from the row space, in units of a light's length.
Eigen::VectorXd fitted_azimuths(const Eigen::MatrixXd& s_hat, double slant, double& misfit) {
  const Eigen::VectorXd found = azimuths_from_row_space(s_hat);
  const Eigen::Index count = found.size();
  Eigen::VectorXd azimuths(count);
  for (Eigen::Index k = 0; k < count; ++k) azimuths(k) = wrapped(found(k) - found(0));
  Eigen::VectorXd even(count);
  std::vector<std::pair<double, Eigen::Index>> around;
  for (Eigen::Index k = 0; k < count; ++k) around.emplace_back(std::fmod(azimuths(k) + 2.0 * M_PI, 2.0 * M_PI), k);
  std::sort(around.begin(), around.end());
  for (Eigen::Index place = 0; place < count; ++place) even(around[std::size_t(place)].second) = 2.0 * M_PI * double(place) / double(count);
  const AzimuthFit fit(s_hat, even, slant);
  Eigen::VectorXd rest = azimuths.tail(count - 1);
  if (count == kLooseCount) {
    rest = even.tail(count - 1);
    Eigen::NumericalDiff<AzimuthFit> differentiated(fit);
    Eigen::LevenbergMarquardt<Eigen::NumericalDiff<AzimuthFit>, double> solver(differentiated);
    solver.minimize(rest);
    azimuths.tail(count - 1) = rest;
  }
  Eigen::VectorXd residual(fit.values());
  fit(rest, residual);
  misfit = std::sqrt(residual.head(3 * count).squaredNorm() / double(3 * count));
  return azimuths;
}

// How far the surface of the normals B_hat T^-1 is from integrable: the mean |curl| of its gradient
// field over the mean size of the gradients' derivatives, at a sample of the pixels lit with their
// four neighbours. Rotating every light about the viewer turns every normal alike, which no surface
// does; +infinity when most of the normals would face away.
class Integrability {
 public:
  Integrability(const Vectors3& b_hat, const Mask& lit) : b_hat_(b_hat), cols_(int(lit.cols())) {
    std::vector<int> inner;
    for (int r = 1; r + 1 < lit.rows(); ++r)
      for (int c = 1; c + 1 < lit.cols(); ++c)
        if (lit(r, c) && lit(r, c - 1) && lit(r, c + 1) && lit(r - 1, c) && lit(r + 1, c)) inner.push_back(r * cols_ + c);
    const std::size_t stride = std::max<std::size_t>(1, inner.size() / kCurlSample);
    for (std::size_t i = 0; i < inner.size(); i += stride) centres_.push_back(inner[i]);
    inner_pixels_ = int(inner.size());
  }
  int inner_pixels() const { return inner_pixels_; }

  double misfit(const Eigen::Matrix3d& to_normals) const {
    double curl = 0.0, size = 0.0;
    std::size_t facing = 0;
    for (int p : centres_) {
      Eigen::Vector2d slope[5];
      const int at[5] = {p, p - 1, p + 1, p - cols_, p + cols_};
      bool ok = true;
      for (int i = 0; i < 5 && ok; ++i) {
        const Eigen::Vector3d b = to_normals.transpose() * b_hat_.row(at[i]).cast<double>().transpose();
        ok = b.z() > 0.0;
        slope[i] = -b.head<2>() / b.z();
      }
      if (!ok) continue;
      ++facing;
      // y up: the row above is +y.
      const double dp_dy = 0.5 * (slope[3].x() - slope[4].x()), dq_dx = 0.5 * (slope[2].y() - slope[1].y());
      const double dp_dx = 0.5 * (slope[2].x() - slope[1].x()), dq_dy = 0.5 * (slope[3].y() - slope[4].y());
      curl += std::abs(dp_dy - dq_dx);
      size += std::abs(dp_dx) + std::abs(dq_dy) + std::abs(dp_dy) + std::abs(dq_dx);
    }
    if (2 * facing < centres_.size() || !(size > 0.0)) return std::numeric_limits<double>::infinity();
    return curl / size;
  }

 private:
  const Vectors3& b_hat_;
  int cols_;
  std::vector<int> centres_;
  int inner_pixels_ = 0;
};

// One member of what the photographs leave open: every light turned about the viewer by `turn`,
// mirrored or not.
struct Member {
  double turn = 0.0;
  bool mirrored = false;
  double misfit = std::numeric_limits<double>::infinity();
};

Eigen::MatrixXd member_lights(const Eigen::VectorXd& azimuths, double slant, const Member& member) {
  return lights_at((member.mirrored ? -1.0 : 1.0) * azimuths.array() + member.turn, slant);
}

// T with S = T S_hat for the member's lights S; the normals are then B_hat T^-1 (rows).
Eigen::Matrix3d to_normals(const Eigen::MatrixXd& lights, const Eigen::MatrixXd& s_hat) {
  const Eigen::Matrix3d t = lights * s_hat.transpose() * (s_hat * s_hat.transpose()).inverse();
  return t.inverse();
}

}  // namespace

PhotometricLights estimate_photometric_lights(const std::vector<ImageF>& images, const Mask& mask, const LightHint& hint) {
  check_inputs(images, mask, hint);
  const Mask lit = lit_everywhere(images, mask);
  Vectors3 b_hat;
  const Eigen::MatrixXd s_hat = factorize(images, lit, b_hat);
  const Integrability integrability(b_hat, lit);
  PhotometricLights estimate;
  estimate.pixels = integrability.inner_pixels();
  if (estimate.pixels < kMinimumPixels)
    throw InvalidArgument("shadecut: only " + std::to_string(estimate.pixels) +
                          " pixels are lit in every photograph (with their neighbours); the lights cannot be estimated");
  const double slant = hint.slant * M_PI / 180.0, first_tilt = hint.first_tilt * M_PI / 180.0;
  const Eigen::VectorXd azimuths = fitted_azimuths(s_hat, slant, estimate.hint_misfit);
  auto judged = [&](Member member) {
    // The first light within 90 degrees of the hint's side: the turn by half a circle, which inverts
    // the surface (the convex / concave choice), fits the photographs as well.
    if (std::cos(member.turn - first_tilt) > 0.0)
      member.misfit = integrability.misfit(to_normals(member_lights(azimuths, slant, member), s_hat));
    return member;
  };
  std::vector<Member> coarse;
  Member best;
  for (bool mirrored : {false, true})
    for (int step = 0; step < kCoarseTurns; ++step) {
      coarse.push_back(judged(Member{2.0 * M_PI * step / kCoarseTurns, mirrored}));
      if (coarse.back().misfit < best.misfit) best = coarse.back();
    }
  if (!std::isfinite(best.misfit))
    throw InvalidArgument("shadecut: no lights at the hint's slant give normals that face the viewer");
  const Member centre = best;
  for (int step = -kFineTurns; step <= kFineTurns; ++step) {
    const Member member = judged(Member{centre.turn + step * 2.0 * M_PI / kCoarseTurns / kFineTurns, centre.mirrored});
    if (member.misfit < best.misfit) best = member;
  }
  const Eigen::MatrixXd lights = member_lights(azimuths, slant, best);
  estimate.lights = lights.transpose();
  estimate.uncertainty.assign(std::size_t(lights.cols()), 0.0);
  for (const Member& member : coarse) {
    if (member.mirrored != best.mirrored || !(member.misfit <= kNearlyAsWell * best.misfit)) continue;
    const Eigen::MatrixXd other = member_lights(azimuths, slant, member);
    for (Eigen::Index k = 0; k < lights.cols(); ++k)
      estimate.uncertainty[std::size_t(k)] = std::max(
          estimate.uncertainty[std::size_t(k)], std::acos(std::clamp(other.col(k).dot(lights.col(k)), -1.0, 1.0)) * 180.0 / M_PI);
  }
  return estimate;
}

}  // namespace shadecut
