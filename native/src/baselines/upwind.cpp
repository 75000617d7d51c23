#include <shadecut/baselines/upwind.hpp>

#include <shadecut/support/errors.hpp>
#include <shadecut/support/validate.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>

namespace shadecut {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();
// Below this, shading says nothing of the slope; the floor keeps sqrt(I^2 - S_x^2) and the roots finite.
constexpr double kDarkest = 1e-3;
constexpr double kConverged = 1e-4;

// Stands for a neighbour not reached yet: far enough that it never constrains the update, finite so
// that the slopes through it stay ordinary numbers.
constexpr double kUnreached = 1e7;

// H(p, q) = I sqrt(1 + p^2 + q^2) + S_x p + S_y q - S_z of one pixel, and the extrema the Godunov
// flux needs, in closed form: H is convex, so a minimum over an interval is at the clamped
// unconstrained minimizer and a maximum at an end.
class Hamiltonian {
 public:
  Hamiltonian(double shade, double sx, double sy, double sz) : i_(shade), sx_(sx), sy_(sy), sz_(sz) {}

  double operator()(double p, double q) const { return i_ * std::sqrt(1.0 + p * p + q * q) + sx_ * p + sy_ * q - sz_; }

  /// Godunov's numerical Hamiltonian: ext over p between the backward slope a and the forward slope
  /// b, of ext over q between c and d (ext = min over [a, b] when a <= b, max over [b, a] otherwise).
  double godunov(double a, double b, double c, double d) const {
    if (a > b) return std::max(extremum_q(a, c, d), extremum_q(b, c, d));
    if (c <= d) return box_minimum(a, b, c, d);
    // min over p in [a, b] of max(H(p, c), H(p, d)): at an end, where one of the two is least and
    // above the other, or where they cross.
    double best = std::min(upper(a, c, d), upper(b, c, d));
    best = std::min(best, upper(std::clamp(minimizer(c, sx_), a, b), c, d));
    best = std::min(best, upper(std::clamp(minimizer(d, sx_), a, b), c, d));
    for (const double p : crossings(c, d))
      if (p >= a && p <= b) best = std::min(best, upper(p, c, d));
    return best;
  }

 private:
  // The slope along one axis minimizing H when the slope along the other is `across` (s_min: the
  // light's component along the minimized axis); +-infinity when H is monotone along it.
  double minimizer(double across, double s_min) const {
    if (i_ <= std::abs(s_min)) return s_min > 0.0 ? -kInfinity : kInfinity;
    return -s_min * std::sqrt(1.0 + across * across) / std::sqrt(i_ * i_ - s_min * s_min);
  }

  double upper(double p, double c, double d) const { return std::max((*this)(p, c), (*this)(p, d)); }

  double extremum_q(double p, double c, double d) const {
    if (c > d) return upper(p, c, d);
    return (*this)(p, std::clamp(minimizer(p, sy_), c, d));
  }

  double box_minimum(double a, double b, double c, double d) const {
    const double room = i_ * i_ - sx_ * sx_ - sy_ * sy_;
    if (room > 0.0) {
      const double p = -sx_ / std::sqrt(room), q = -sy_ / std::sqrt(room);
      if (p >= a && p <= b && q >= c && q <= d) return (*this)(p, q);
    }
    return std::min({(*this)(a, std::clamp(minimizer(a, sy_), c, d)), (*this)(b, std::clamp(minimizer(b, sy_), c, d)),
                     (*this)(std::clamp(minimizer(c, sx_), a, b), c), (*this)(std::clamp(minimizer(d, sx_), a, b), d)});
  }

  // The p where H(p, c) = H(p, d): with A = 1 + p^2, sqrt(A + c^2) - sqrt(A + d^2) = delta.
  std::array<double, 2> crossings(double c, double d) const {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    if (i_ <= 0.0) return {nan, nan};
    const double delta = sy_ * (d - c) / i_;
    if (std::abs(delta) < 1e-15) return {nan, nan};
    const double root_c = 0.5 * ((c * c - d * d) / delta + delta);
    if (root_c < 0.0) return {nan, nan};
    const double p2 = root_c * root_c - c * c - 1.0;
    if (p2 < 0.0) return {nan, nan};
    return {std::sqrt(p2), -std::sqrt(p2)};
  }

  double i_, sx_, sy_, sz_;
};

struct Neighbours {
  double left, right, below, above;
};

// The largest u whose Godunov flux is <= 0 (the flux grows with u: the scheme is monotone), found by
// regula falsi (Illinois) between a u below every neighbour and `current`, an upper bound.
double update(const Hamiltonian& h, const Neighbours& n, double current) {
  auto flux = [&](double u) { return h.godunov(u - n.left, n.right - u, u - n.below, n.above - u); };
  double high = current, f_high = flux(high);
  if (f_high <= 0.0) return current;
  double step = 1.0;
  double low = std::min({n.left, n.right, n.below, n.above, current}) - step, f_low = flux(low);
  for (int tries = 0; f_low > 0.0; ++tries) {
    if (tries == 60) return current;
    step *= 2.0;
    high = low, f_high = f_low;
    low -= step, f_low = flux(low);
  }
  int side = 0;
  for (int iteration = 0; iteration < 100 && high - low > 1e-7 * (1.0 + std::abs(high)); ++iteration) {
    const double u = (low * f_high - high * f_low) / (f_high - f_low);
    const double f = flux(u);
    if (f > 0.0) {
      high = u, f_high = f;
      if (side == 1) f_low *= 0.5;
      side = 1;
    } else {
      low = u, f_low = f;
      if (side == -1) f_high *= 0.5;
      side = -1;
    }
  }
  return low;
}

}  // namespace

UpwindResult upwind(const ImageF& image, const Mask& mask, const LightFrame& light, double albedo, int iterations,
                    const Progress& progress, double brightest_shade) {
  check_iterative_input(image, mask, albedo, iterations);
  if (!(brightest_shade > kDarkest && brightest_shade <= 1.0))
    throw InvalidArgument("shadecut: upwind's brightest shade must be above 0.001 and at most 1");

  const int rows = int(image.rows()), cols = int(image.cols());
  const double sx = light.direction.x(), sy = light.direction.y(), sz = light.direction.z();
  Eigen::ArrayXXd depth = mask.select(Eigen::ArrayXXd::Constant(rows, cols, kUnreached), 0.0);
  auto inside = [&](int r, int c) { return r >= 0 && r < rows && c >= 0 && c < cols && mask(r, c); };
  const Eigen::ArrayXXd shade = (image.cast<double>() / albedo).min(brightest_shade);
  // The edge pixels hold z = 0: the silhouette passes through them, and a first step from outside
  // with the rim's near-infinite slope would lift the whole object unevenly.
  Mask solved = mask;
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c)
      solved(r, c) = mask(r, c) && inside(r, c - 1) && inside(r, c + 1) && inside(r - 1, c) && inside(r + 1, c);
  depth = (mask && !solved).select(0.0, depth);

  UpwindResult result;
  for (int round = 0; round < iterations && !result.converged; ++round) {
    double largest_change = 0.0;
    for (int order = 0; order < 4; ++order) {
      const bool down = order & 1, right = order & 2;
      for (int i = 0; i < rows; ++i) {
        const int r = down ? i : rows - 1 - i;
        for (int j = 0; j < cols; ++j) {
          const int c = right ? j : cols - 1 - j;
          if (!solved(r, c)) continue;
          const Neighbours n{depth(r, c - 1), depth(r, c + 1), depth(r + 1, c), depth(r - 1, c)};
          const double updated = update(Hamiltonian(std::max(shade(r, c), kDarkest), sx, sy, sz), n, depth(r, c));
          if (updated < depth(r, c)) {
            largest_change = std::max(largest_change, depth(r, c) - updated);
            depth(r, c) = updated;
          }
        }
      }
    }
    result.iterations = round + 1;
    result.converged = largest_change <= kConverged;
    progress.report(double(round + 1) / iterations, "upwind");
  }
  // A pixel no stencil reached (a mask part too thin to have an inside) keeps the edge's depth.
  result.depth = mask.select(depth.unaryExpr([](double z) { return z < kUnreached ? z : 0.0; }), 0.0).cast<float>();
  return result;
}

}  // namespace shadecut
