#include "pipeline/two_photographs.hpp"

#include "photometric/pixel_lights.hpp"
#include "pipeline/paint.hpp"

namespace shadecut::detail {

NormalMap single_photographs_normals(const std::vector<Observation>& photographs, const Mask& mask,
                                     const ReconstructOptions& options, const Progress& progress) {
  Eigen::MatrixXf sum = Eigen::MatrixXf::Zero(mask.size(), 3);
  for (std::size_t k = 0; k < photographs.size(); ++k) {
    const Observation& photograph = photographs[k];
    ReconstructOptions alone = options;
    const Progress part = progress.range(double(k) / double(photographs.size()), double(k + 1) / double(photographs.size()));
    alone.progress = [part](double fraction, const std::string& stage) {
      part.report(fraction, stage);
      return true;
    };
    const ColourImage* colour = photograph.has_colour() ? &photograph.colour : nullptr;
    sum += reconstruct_painted(photograph.image, colour, photograph.light, &mask, std::nullopt, alone).normals.xyz;
  }
  NormalMap mean(int(mask.rows()), int(mask.cols()));
  for (Eigen::Index i = 0; i < mask.size(); ++i)
    if (mask.data()[i] && sum.row(i).norm() > 0.0f) mean.xyz.row(i) = sum.row(i).normalized();
  return mean;
}

NormalMap nearest_on_circles(const std::vector<ImageF>& images, const std::vector<Eigen::Vector3d>& lights,
                             const NearLamps& lamps, const CountImage& usable, const NormalMap& anchor, const Mask& mask) {
  NormalMap normals = anchor;
  PixelLights here(lights, lamps);
  const int cols = int(mask.cols());
  for (Eigen::Index i = 0; i < mask.size(); ++i) {
    if (!mask.data()[i] || usable.data()[i] != 2) continue;
    const int r = int(i / cols), c = int(i % cols);
    here.at(r, c);
    const std::vector<Eigen::Vector3d>& toward = here.directions();
    const double first = images[0](r, c) / here.strength(0), second = images[1](r, c) / here.strength(1);
    const Eigen::Vector3d across = (second * toward[0] - first * toward[1]).normalized();
    const Eigen::Vector3d near = anchor.xyz.row(i).transpose().cast<double>();
    Eigen::Vector3d on_circle = near - near.dot(across) * across;
    if (!(on_circle.norm() > 1e-9)) continue;  // the anchor is the circle's axis: every point is as near
    on_circle.normalize();
    if (on_circle.dot(toward[0]) < 0.0) on_circle = -on_circle;
    normals.xyz.row(i) = on_circle.cast<float>().transpose();
  }
  return normals;
}

}  // namespace shadecut::detail
