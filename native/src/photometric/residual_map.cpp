#include <shadecut/photometric/residual_map.hpp>

#include "photometric/pixel_lights.hpp"
#include "support/parallel.hpp"

#include <algorithm>
#include <cmath>

namespace shadecut {

ImageF residual_map(const std::vector<ImageF>& images, const std::vector<Eigen::Vector3d>& lights, const NearLamps& lamps,
                    const NormalMap& normals, const ImageF& albedo_map, const Mask& mask) {
  ImageF residual = ImageF::Zero(mask.rows(), mask.cols());
  const int cols = int(mask.cols());
  detail::parallel_ranges(int(mask.rows()), 8, 0, [&](int begin, int end) {
    detail::PixelLights lights_here(lights, lamps);
    for (int r = begin; r < end; ++r)
      for (int c = 0; c < cols; ++c) {
        const Eigen::Index i = Eigen::Index(r) * cols + c;
        if (!mask.data()[i]) continue;
        lights_here.at(r, c);
        const Eigen::Vector3d n = normals.xyz.row(i).transpose().cast<double>();
        double misfit = 0.0;
        for (std::size_t k = 0; k < images.size(); ++k) {
          const double shading = std::max(0.0, n.dot(lights_here.directions()[k])) * lights_here.strength(k);
          misfit += std::pow(images[k].data()[i] - albedo_map.data()[i] * shading, 2);
        }
        residual.data()[i] = float(std::sqrt(misfit / double(images.size())));
      }
  });
  return residual;
}

}  // namespace shadecut
