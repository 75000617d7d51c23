#include <shadecut/baselines/brooks_horn.hpp>

#include <shadecut/support/errors.hpp>
#include <shadecut/support/validate.hpp>

#include "support/contour.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace shadecut {

BrooksHornResult brooks_horn(const ImageF& image, const Mask& mask, const LightFrame& light, double albedo,
                             const BrooksHornParams& params, const Progress& progress) {
  check_image(image);
  check_mask(mask, image);
  check_albedo(albedo);
  if (!(params.smoothness > 0.25) || !std::isfinite(params.smoothness))
    throw InvalidArgument("shadecut: the smoothness of brooks_horn must be finite and > 1/4 per pixel (below, its "
                          "sweeps overshoot the brightness and never converge); got " + std::to_string(params.smoothness));
  check_iterations(params.iterations);
  if (!(params.tolerance >= 0.0) || !std::isfinite(params.tolerance))
    throw InvalidArgument("shadecut: the tolerance must be finite and >= 0");

  const int rows = int(image.rows()), cols = int(image.cols());
  const Eigen::Vector3d s = light.direction;
  const double step = 1.0 / (4.0 * params.smoothness);
  BrooksHornResult result;
  result.normals = NormalMap(rows, cols);
  Vectors3& n = result.normals.xyz;
  std::vector<char> fixed(std::size_t(rows) * cols, 0);
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) {
      if (!mask(r, c)) continue;
      const Eigen::Index p = Eigen::Index(r) * cols + c;
      const Eigen::Vector2d edge = params.occluding_contour ? detail::contour_outward(mask, r, c) : Eigen::Vector2d::Zero();
      if (edge.norm() > 0.0) {
        n.row(p) << float(edge.x()), float(edge.y()), 0.0f;
        fixed[std::size_t(p)] = 1;
      } else {
        n.row(p) = s.cast<float>().transpose();
      }
    }
  }
  const double pixels = double(mask.count());
  ReportClock clock;

  for (int iteration = 0; iteration < params.iterations; ++iteration) {
    double change = 0.0;
    // Serial on purpose: a half-sweep takes well under a millisecond, less than the two thread barriers
    // it would need on a loaded machine.
    for (int colour = 0; colour < 2; ++colour) {
      for (int r = 0; r < rows; ++r) {
        for (int c = (r + colour) % 2; c < cols; c += 2) {
          const Eigen::Index p = Eigen::Index(r) * cols + c;
          if (!mask(r, c) || fixed[std::size_t(p)]) continue;
          Eigen::Vector3d mean = Eigen::Vector3d::Zero();
          int count = 0;
          const int neighbours[4][2] = {{r, c - 1}, {r, c + 1}, {r - 1, c}, {r + 1, c}};
          for (const auto& rc : neighbours) {
            if (rc[0] < 0 || rc[0] >= rows || rc[1] < 0 || rc[1] >= cols || !mask(rc[0], rc[1])) continue;
            mean += n.row(Eigen::Index(rc[0]) * cols + rc[1]).cast<double>().transpose();
            ++count;
          }
          const Eigen::Vector3d old = n.row(p).cast<double>().transpose();
          if (count == 0) mean = old;
          else mean /= count;
          const Eigen::Vector3d m = mean + step * (image(r, c) / albedo - old.dot(s)) * s;
          if (!(m.norm() > 1e-12)) continue;
          const Eigen::Vector3d updated = m.normalized();
          change += (updated - old).norm();
          n.row(p) = updated.cast<float>().transpose();
        }
      }
    }
    result.iterations = iteration + 1;
    result.change = change / pixels;
    if (clock.due() || result.iterations == params.iterations)
      progress.report(double(result.iterations) / params.iterations, "brooks_horn");
    if (result.change <= params.tolerance) break;
  }
  return result;
}

}  // namespace shadecut
