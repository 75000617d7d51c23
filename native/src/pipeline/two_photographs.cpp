#include "pipeline/two_photographs.hpp"

#include "photometric/pixel_lights.hpp"
#include "pipeline/paint.hpp"

#include <shadecut/support/errors.hpp>
#include <shadecut/support/validate.hpp>

#include <algorithm>
#include <cmath>
#include <string>

namespace shadecut::detail {

namespace {

// The unit axis of pixel (r, c)'s circle of normals, I_2 S_1 - I_1 S_2 (`lights` moved to the pixel).
Eigen::Vector3d circle_axis(const std::vector<ImageF>& images, const PixelLights& lights, int r, int c) {
  const std::vector<Eigen::Vector3d>& toward = lights.directions();
  const double first = images[0](r, c) / lights.strength(0), second = images[1](r, c) / lights.strength(1);
  return (second * toward[0] - first * toward[1]).normalized();
}

}  // namespace

std::vector<NormalMap> photographs_read_alone(const std::vector<Observation>& photographs, const Mask& mask,
                                              const ReconstructOptions& options, const Progress& progress) {
  std::vector<NormalMap> alone;
  for (std::size_t k = 0; k < photographs.size(); ++k) {
    const Observation& photograph = photographs[k];
    ReconstructOptions own = options;
    const Progress part = progress.range(double(k) / double(photographs.size()), double(k + 1) / double(photographs.size()));
    own.progress = [part](double fraction, const std::string& stage) {
      part.report(fraction, stage);
      return true;
    };
    const ColourImage* colour = photograph.has_colour() ? &photograph.colour : nullptr;
    try {
      alone.push_back(reconstruct_painted(photograph.image, colour, photograph.light, &mask, std::nullopt, own).normals);
    } catch (const InvalidArgument& error) {  // say which photograph, and that it was read alone
      throw InvalidArgument("shadecut: " + photograph_name(k) + ", read alone to anchor the other: " +
                            std::string(error.what()).substr(std::string("shadecut: ").size()));
    }
  }
  return alone;
}

NormalMap mean_normals(const NormalMap& first, const NormalMap& second, const Mask& mask) {
  NormalMap mean(first.rows, first.cols);
  for (Eigen::Index i = 0; i < mask.size(); ++i) {
    const Eigen::Vector3f sum = (first.xyz.row(i) + second.xyz.row(i)).transpose();
    if (mask.data()[i] && sum.norm() > 0.0f) mean.xyz.row(i) = sum.normalized().transpose();
  }
  return mean;
}

const NormalMap& nearest_to_circles(const std::vector<NormalMap>& anchors, const std::vector<ImageF>& images,
                                    const std::vector<Eigen::Vector3d>& lights, const NearLamps& lamps,
                                    const Mask& both_lit) {
  std::vector<double> off(anchors.size(), 0.0);
  PixelLights here(lights, lamps);
  const int cols = int(both_lit.cols());
  for (Eigen::Index i = 0; i < both_lit.size(); ++i) {
    if (!both_lit.data()[i]) continue;
    here.at(int(i / cols), int(i % cols));
    const Eigen::Vector3d across = circle_axis(images, here, int(i / cols), int(i % cols));
    for (std::size_t k = 0; k < anchors.size(); ++k)
      off[k] += std::asin(std::min(1.0, std::abs(across.dot(anchors[k].xyz.row(i).transpose().cast<double>()))));
  }
  return anchors[std::size_t(std::min_element(off.begin(), off.end()) - off.begin())];
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
    const Eigen::Vector3d across = circle_axis(images, here, r, c);
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
