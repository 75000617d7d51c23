#include "photometric/pixel_fit.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <limits>

namespace shadecut::detail {
namespace {

// Three lights whose triple product is below this are too near one plane to fix a normal: the
// pixel is then read as lit by its two brightest photographs.
constexpr double kMinTripleProduct = 1e-3;
// The shadow test is refitted this many times at most (it settles in one or two).
constexpr int kShadowPasses = 4;

}  // namespace

PixelFitter::PixelFitter(PixelLights& lights, double shadow_fraction, double outlier_tolerance)
    : lights_(lights),
      shadow_fraction_(shadow_fraction),
      outlier_tolerance_(outlier_tolerance),
      intensity_(lights.directions().size(), 0.0) {}

const PixelFitter::SetInverse& PixelFitter::set_inverse(const std::vector<int>& set) {
  const bool cached = !lights_.near() && lights_.directions().size() <= 64;
  std::uint64_t bits = 0;
  if (cached) {
    for (const int k : set) bits |= std::uint64_t(1) << k;
    if (last_ && bits == last_bits_) return *last_;
    last_bits_ = bits;
    const auto found = inverses_.find(bits);
    if (found != inverses_.end()) return *(last_ = &found->second);
  }
  Eigen::Matrix3d normal_matrix = Eigen::Matrix3d::Zero();
  for (const int k : set) normal_matrix.noalias() += light(k) * light(k).transpose();
  // Built in uncached_, whose buffers then serve every pixel where the lights change across the frame;
  // a set met for the first time is copied from it into the cache. spread and free hold only the set's.
  SetInverse& inverse = uncached_;
  // det(L^T L) is the sum of the squared triple products of the set's lights (Cauchy-Binet).
  inverse.determinant = normal_matrix.determinant();
  inverse.solvable = inverse.determinant > kMinTripleProduct * kMinTripleProduct;
  inverse.inverse = inverse.solvable ? Eigen::Matrix3d(normal_matrix.inverse()) : Eigen::Matrix3d::Zero();
  if (inverse.solvable) {
    inverse.spread.resize(lights_.directions().size(), Eigen::Vector3d::Zero());
    inverse.free.resize(lights_.directions().size(), 0.0);
    for (const int k : set) {
      inverse.spread[std::size_t(k)] = inverse.inverse * light(k);
      inverse.free[std::size_t(k)] = 1.0 - light(k).dot(inverse.spread[std::size_t(k)]);
    }
  }
  if (!cached) return inverse;
  return *(last_ = &inverses_.emplace(bits, inverse).first->second);
}

bool PixelFitter::solve(const std::vector<int>& set, Eigen::Vector3d& scaled_normal) {
  const SetInverse& inverse = set_inverse(set);
  if (!inverse.solvable) return false;
  Eigen::Vector3d rhs = Eigen::Vector3d::Zero();
  for (const int k : set) rhs += intensity_[std::size_t(k)] * light(k);
  scaled_normal = inverse.inverse * rhs;
  return scaled_normal.allFinite();
}

double PixelFitter::rms(const std::vector<int>& set, const Eigen::Vector3d& scaled_normal) const {
  double sum = 0.0;
  for (const int k : set) {
    const double r = intensity_[std::size_t(k)] - scaled_normal.dot(light(k));
    sum += r * r;
  }
  return set.empty() ? 0.0 : std::sqrt(sum / double(set.size()));
}

void PixelFitter::select_lit(double threshold) {
  used_.clear();
  for (const int k : available_)
    if (intensity_[std::size_t(k)] > 0.0 && intensity_[std::size_t(k)] >= threshold) used_.push_back(k);
}

// The case against photograph used_[i] being the outlier, given the fit of the others: a photograph
// brighter than they predict is a highlight, likeliest where its half vector meets the normal; a
// darker one a cast shadow, likeliest where its light grazes the surface (the light the normal would
// catch, the same evidence as a candidate's shadow conflict).
double PixelFitter::outlier_cost(int i, const Eigen::Vector3d& scaled) const {
  const Eigen::Vector3d normal = scaled.normalized();
  const Eigen::Vector3d& light = this->light(used_[std::size_t(i)]);
  if (intensity_[std::size_t(used_[std::size_t(i)])] > scaled.dot(light))
    return 1.0 - normal.dot((light + Eigen::Vector3d::UnitZ()).normalized());
  return std::max(0.0, normal.dot(light));
}

// The photograph of used_ to leave out (its position in used_), -1 if no subset can be fitted. With
// five or more the data say which: the rest that fits best (best_left_out). With four every subset of
// three fits exactly, so the physics says (outlier_cost), and the four fits are kept in four_fits_: the
// graph cut weighs the same case against each, and its neighbours.
int PixelFitter::outlier(const Eigen::Vector3d& scaled_normal) {
  if (used_.size() >= 5) return best_left_out(scaled_normal);
  int best = -1;
  double best_cost = std::numeric_limits<double>::infinity();
  has_four_fits_ = true;
  for (std::size_t i = 0; i < used_.size(); ++i) {
    trial_.assign(used_.begin(), used_.end());
    trial_.erase(trial_.begin() + std::ptrdiff_t(i));
    Eigen::Vector3d scaled;
    if (!solve(trial_, scaled) || !(scaled.norm() > 0.0)) {
      has_four_fits_ = false;
      continue;
    }
    const double cost = outlier_cost(int(i), scaled);
    four_fits_.normals[i] = scaled.normalized().cast<float>();
    four_fits_.cost[i] = float(cost);
    if (cost < best_cost) {
      best_cost = cost;
      best = int(i);
    }
  }
  return best;
}

// Of five or more, the photograph whose leaving out leaves the smallest RMS residual over the albedo.
// Each fit without one comes from the fit of all by the leave-one-out identities of least squares
// (Sherman-Morrison): x_k = x - A^-1 S_k r_k / (1 - h_k), RSS_k = RSS - r_k^2 / (1 - h_k), with
// h_k = S_k . A^-1 S_k the leverage; and det(A_k) = det(A) (1 - h_k) says whether the rest fix a normal.
// Compared squared, RSS_k / |x_k|^2, over the same count: the same order without a root per candidate.
int PixelFitter::best_left_out(const Eigen::Vector3d& scaled_normal) {
  const SetInverse& fit = set_inverse(used_);
  double rss = 0.0;
  for (const int k : used_) rss += std::pow(intensity_[std::size_t(k)] - scaled_normal.dot(light(k)), 2);
  int best = -1;
  double best_cost = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < used_.size(); ++i) {
    const std::size_t k = std::size_t(used_[i]);
    const Eigen::Vector3d& spread = fit.spread[k];
    const double free = fit.free[k];
    if (!(fit.determinant * free > kMinTripleProduct * kMinTripleProduct)) continue;
    const double residual = intensity_[k] - scaled_normal.dot(light(used_[i]));
    const Eigen::Vector3d scaled = scaled_normal - spread * (residual / free);
    const double squared_albedo = scaled.squaredNorm();
    if (!(squared_albedo > 0.0) || !scaled.allFinite()) continue;
    const double cost = std::max(0.0, rss - residual * residual / free) / squared_albedo;
    if (cost < best_cost) {
      best_cost = cost;
      best = int(i);
    }
  }
  return best;
}

double PixelFitter::largest_deviation(const Eigen::Vector3d& scaled_normal) {
  const SetInverse& fit = set_inverse(used_);
  double largest = 0.0;
  for (const int k : used_) {
    // The residual over one minus the leverage: the photograph against the fit of the others.
    const double free = fit.free[std::size_t(k)];
    const double residual = intensity_[std::size_t(k)] - scaled_normal.dot(light(k));
    if (free > 1e-9) largest = std::max(largest, std::abs(residual) / free);
  }
  return largest;
}

void PixelFitter::drop_outliers(Eigen::Vector3d& scaled_normal) {
  has_four_fits_ = false;
  while (used_.size() >= 4 && largest_deviation(scaled_normal) > outlier_tolerance_ * scaled_normal.norm()) {
    const int drop = outlier(scaled_normal);
    if (drop < 0) return;  // outlier() found no subset solvable, so it kept no four fits
    used_.erase(used_.begin() + drop);
    if (!solve(used_, scaled_normal)) return;  // cannot happen: outlier() found this subset solvable
  }
}

PixelFit PixelFitter::fit(const std::vector<ImageF>& images, const std::vector<Mask>& clipped, int r, int c) {
  lights_.at(r, c);
  available_.clear();
  double brightest = 0.0;
  for (std::size_t k = 0; k < images.size(); ++k) {
    intensity_[k] = double(images[k](r, c)) / lights_.strength(k);
    if (!clipped.empty() && clipped[k](r, c)) continue;
    available_.push_back(int(k));
    brightest = std::max(brightest, intensity_[k]);
  }
  PixelFit fit;
  if (!(brightest > 0.0)) return fit;  // dark in every photograph (or clipped in all)
  // The albedo is at least the brightest intensity: a first shadow test against it, then against
  // the fitted albedo until the set settles.
  select_lit(shadow_fraction_ * brightest);
  Eigen::Vector3d scaled = Eigen::Vector3d::Zero();
  bool solved = false;
  for (int pass = 0; pass < kShadowPasses && used_.size() >= 3; ++pass) {
    solved = solve(used_, scaled);
    if (!solved) break;
    previous_.assign(used_.begin(), used_.end());
    select_lit(shadow_fraction_ * scaled.norm());
    if (used_ == previous_) break;
    solved = false;
  }
  if (used_.size() >= 3 && !solved) solved = solve(used_, scaled);
  if (used_.size() >= 3 && !solved) {
    // Lights in one plane: only the two brightest photographs count.
    std::sort(used_.begin(), used_.end(), [&](int a, int b) { return intensity_[std::size_t(a)] > intensity_[std::size_t(b)]; });
    used_.resize(2);
    std::sort(used_.begin(), used_.end());
  }
  if (used_.size() >= 3) {
    drop_outliers(scaled);
    fit.scaled_normal = scaled;
    fit.rms = rms(used_, scaled);
    fit.has_four_fits = has_four_fits_;
    if (has_four_fits_) fit.four_fits = four_fits_;
  } else if (used_.size() == 2) {
    fit.pair = {used_[0], used_[1], float(intensity_[std::size_t(used_[0])]), float(intensity_[std::size_t(used_[1])])};
  }
  fit.usable = int(used_.size());
  return fit;
}

}  // namespace shadecut::detail
