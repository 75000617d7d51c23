// The two candidate normals of a pixel lit in exactly two photographs.
#include "photometric/pixel_fit.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <vector>

namespace shadecut::detail {
namespace {

// The part of n in the plane of the lights a and b given n . a = shade_a and n . b = shade_b.
Eigen::Vector3d in_plane_part(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double shade_a, double shade_b) {
  const double cosine = a.dot(b);
  const double det = 1.0 - cosine * cosine;  // > 0: the lights differ (kSameLightDegrees)
  return ((shade_a - cosine * shade_b) * a + (shade_b - cosine * shade_a) * b) / det;
}

// The smallest albedo at which the pair's two cones meet: the in-plane part at albedo 1 is this long.
double smallest_albedo(const UsablePair& pair, const std::vector<Eigen::Vector3d>& lights) {
  return in_plane_part(lights[std::size_t(pair.a)], lights[std::size_t(pair.b)], pair.intensity_a, pair.intensity_b)
      .norm();
}

// The mean albedo of the nearest pixels fitted from three or more photographs, by 4-neighbour rings
// inside the mask grown from them; 0 where a part of the mask has none.
ImageF nearest_fitted_albedo(const PhotometricStereoResult& result, const Mask& mask) {
  const int rows = int(mask.rows()), cols = int(mask.cols());
  ImageF albedo = ImageF::Zero(rows, cols);
  std::vector<int> ring, next;
  std::vector<std::uint8_t> reached(std::size_t(rows) * std::size_t(cols), 0);
  for (int p = 0; p < rows * cols; ++p)
    if (result.usable.data()[p] >= 3) {
      albedo.data()[p] = result.albedo.data()[p];
      reached[std::size_t(p)] = 1;
      ring.push_back(p);
    }
  const int steps[4][2] = {{-1, 0}, {1, 0}, {0, -1}, {0, 1}};
  while (!ring.empty()) {
    next.clear();
    for (const int p : ring)
      for (const auto& s : steps) {
        const int r = p / cols + s[0], c = p % cols + s[1];
        if (r < 0 || c < 0 || r >= rows || c >= cols || !mask(r, c) || reached[std::size_t(r * cols + c)]) continue;
        reached[std::size_t(r * cols + c)] = 2;  // in the next ring: its albedo is the mean of the rings before
        next.push_back(r * cols + c);
      }
    for (const int q : next) {
      double sum = 0.0;
      int count = 0;
      for (const auto& s : steps) {
        const int r = q / cols + s[0], c = q % cols + s[1];
        if (r < 0 || c < 0 || r >= rows || c >= cols || reached[std::size_t(r * cols + c)] != 1) continue;
        sum += albedo(r, c);
        ++count;
      }
      albedo.data()[q] = float(sum / count);
    }
    for (const int q : next) reached[std::size_t(q)] = 1;
    ring.swap(next);
  }
  return albedo;
}

// kTwoLightAlbedoQuantile of the smallest albedos of the pixels that have none yet.
double uniform_pair_albedo(const std::vector<UsablePair>& pairs, PixelLights& lights, const ImageF& albedo) {
  const int cols = int(albedo.cols());
  std::vector<double> smallest;
  for (std::size_t p = 0; p < pairs.size(); ++p) {
    if (pairs[p].a < 0 || albedo.data()[p] > 0.0f) continue;
    lights.at(int(p) / cols, int(p) % cols);
    smallest.push_back(smallest_albedo(pairs[p], lights.directions()));
  }
  if (smallest.empty()) return 0.0;
  const std::size_t at = std::min(smallest.size() - 1, std::size_t(kTwoLightAlbedoQuantile * double(smallest.size())));
  std::nth_element(smallest.begin(), smallest.begin() + std::ptrdiff_t(at), smallest.end());
  return smallest[at];
}

// The light `normal` would catch beyond what the photographs other than the pair's show, at pixel p.
double shadow_conflict(const Eigen::Vector3d& normal, const UsablePair& pair, double albedo, std::size_t p,
                       const std::vector<ImageF>& images, const std::vector<Mask>& clipped,
                       const PixelLights& lights) {
  double conflict = 0.0;
  for (std::size_t k = 0; k < images.size(); ++k) {
    if (int(k) == pair.a || int(k) == pair.b || (!clipped.empty() && clipped[k].data()[p])) continue;
    const double shade = double(images[k].data()[p]) / (lights.strength(k) * albedo);
    conflict += std::max(0.0, normal.dot(lights.directions()[k]) - shade);
  }
  return conflict;
}

}  // namespace

void resolve_pairs(const std::vector<UsablePair>& pairs, const std::vector<ImageF>& images,
                   const std::vector<Mask>& clipped, PixelLights& lights, const Mask& mask,
                   const PhotometricStereoParams& params, PhotometricStereoResult& result) {
  ImageF pair_albedo = params.albedo_map.size() > 0 ? params.albedo_map
                       : params.albedo > 0.0 ? ImageF(ImageF::Constant(mask.rows(), mask.cols(), float(params.albedo)))
                                             : nearest_fitted_albedo(result, mask);
  const double uniform = uniform_pair_albedo(pairs, lights, pair_albedo);
  for (std::size_t p = 0; p < pairs.size(); ++p) {
    const UsablePair& pair = pairs[p];
    if (pair.a < 0) continue;
    const double rho = pair_albedo.data()[p] > 0.0f ? double(pair_albedo.data()[p]) : uniform;
    lights.at(int(p) / int(mask.cols()), int(p) % int(mask.cols()));
    const Eigen::Vector3d& a = lights.directions()[std::size_t(pair.a)];
    const Eigen::Vector3d& b = lights.directions()[std::size_t(pair.b)];
    const Eigen::Vector3d in_plane = in_plane_part(a, b, pair.intensity_a / rho, pair.intensity_b / rho);
    const double out_of_plane_squared = 1.0 - in_plane.squaredNorm();
    // Across the lights' plane toward the viewer: `first` faces the viewer more than `second`.
    Eigen::Vector3d across = a.cross(b).normalized();
    if (across.z() < 0.0) across = -across;
    Eigen::Vector3d first = in_plane.normalized(), second = first;
    if (out_of_plane_squared > 0.0) {
      first = in_plane + std::sqrt(out_of_plane_squared) * across;
      second = in_plane - std::sqrt(out_of_plane_squared) * across;
    }
    first.normalize();
    second.normalize();
    result.first_candidate.xyz.row(Eigen::Index(p)) = first.cast<float>().transpose();
    result.second_candidate.xyz.row(Eigen::Index(p)) = second.cast<float>().transpose();
    result.first_shadow_conflict.data()[p] = float(shadow_conflict(first, pair, rho, p, images, clipped, lights));
    result.second_shadow_conflict.data()[p] = float(shadow_conflict(second, pair, rho, p, images, clipped, lights));
    result.albedo.data()[p] = float(rho);
  }
}

}  // namespace shadecut::detail
