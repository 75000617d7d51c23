// Several Lambertian photographs of one synthetic surface, for the photometric tests.
#pragma once

#include "test_support.hpp"
#include "support/contour.hpp"

#include <shadecut/photometric/choose_candidates.hpp>
#include <shadecut/photometric/photometric_stereo.hpp>
#include <shadecut/support/render.hpp>

#include <cmath>
#include <vector>

namespace shadecut::testing {

/// K lights at one slant (degrees) around the viewer, the first at tilt `first_tilt` (degrees), the
/// others `step` degrees apart.
inline LightDirections lights_around(int count, double slant, double first_tilt, double step) {
  LightDirections lights(count, 3);
  for (int k = 0; k < count; ++k) {
    const double s = slant * M_PI / 180.0, t = (first_tilt + k * step) * M_PI / 180.0;
    lights.row(k) << std::sin(s) * std::cos(t), std::sin(s) * std::sin(t), std::cos(s);
  }
  return lights;
}

/// A smoothly varying albedo in [0.4, 1.0]: paint, so that the fit must find it per pixel.
inline ImageF painted_albedo(int rows, int cols) {
  ImageF albedo(rows, cols);
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) albedo(r, c) = float(0.7 + 0.3 * std::sin(0.11 * r) * std::cos(0.07 * c));
  return albedo;
}

/// The Lambertian photographs of `scene`'s normals under each light, times `albedo`.
inline std::vector<ImageF> photographs(const Scene& scene, const LightDirections& lights, const ImageF& albedo) {
  std::vector<ImageF> images;
  for (Eigen::Index k = 0; k < lights.rows(); ++k)
    images.push_back(render_lambertian(scene.normals, lights.row(k).transpose(), 1.0, scene.mask) * albedo);
  return images;
}

/// Angle in degrees between two normals.
inline double degrees_between(const Eigen::Vector3f& a, const Eigen::Vector3f& b) {
  return std::acos(std::clamp(double(a.normalized().dot(b.normalized())), -1.0, 1.0)) * 180.0 / M_PI;
}

/// The outline's pull, for the tests and measurements: on the mask's edge a candidate costs `weight`
/// (1 - cos d) / 2 more, d the angle between the edge's outward direction and the candidate's
/// image-plane direction; the candidates' own costs (if any) plus these.
inline std::vector<ImageF> outline_costs(const NormalCandidates& candidates, const Mask& mask, double weight) {
  std::vector<ImageF> costs = candidates.data_cost;
  if (costs.empty()) costs.assign(candidates.normals.size(), ImageF::Zero(mask.rows(), mask.cols()));
  for (int r = 0; r < mask.rows(); ++r)
    for (int c = 0; c < mask.cols(); ++c) {
      const Eigen::Vector2d outward = detail::contour_outward(mask, r, c);
      if (!mask(r, c) || outward.isZero()) continue;
      for (std::size_t k = 0; k < costs.size(); ++k) {
        const Eigen::Vector2d across = candidates.normals[k].xyz.row(r * mask.cols() + c).head<2>().cast<double>();
        if (across.norm() > 0.0) costs[k](r, c) += float(weight * (1.0 - outward.dot(across.normalized())) / 2.0);
      }
    }
  return costs;
}

}  // namespace shadecut::testing
