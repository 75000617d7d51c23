#include "test_support.hpp"

#include <shadecut/pipeline/reconstruct.hpp>
#include <shadecut/support/render.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace shadecut::testing {

TiltEnergyParams paper_energy_params() {
  TiltEnergyParams params;
  params.labels = ReconstructOptions().labels;
  params.data_weight = 1.0;
  return params;
}

GlobalStepParams one_level_params() {
  ReconstructOptions options;
  options.coarse_to_fine_band = -1;
  options.coarse_to_fine_radius = -1;
  options.contour_weight = 0.0;
  options.viscosity_weight = 0.0;
  return global_step_params(options);
}

Scene sphere_scene(int size, double radius_fraction, const Eigen::Vector3d& light, bool bowl) {
  const double radius = radius_fraction * size, centre = 0.5 * (size - 1);
  Scene scene{ImageF::Zero(size, size), NormalMap(size, size), ImageF::Zero(size, size), Mask::Constant(size, size, false)};
  for (int r = 0; r < size; ++r) {
    for (int c = 0; c < size; ++c) {
      const double x = c - centre, y = centre - r, h2 = radius * radius - x * x - y * y;
      if (h2 <= 0.0) continue;
      const double h = std::sqrt(h2);
      scene.mask(r, c) = true;
      scene.depth(r, c) = float(bowl ? radius - h : h);
      // The bowl is the sphere's inside: its surface slopes the other way.
      const Eigen::Vector3d n = bowl ? Eigen::Vector3d(-x, -y, h) / radius : Eigen::Vector3d(x, y, h) / radius;
      scene.normals.xyz.row(Eigen::Index(r) * size + c) = n.cast<float>();
    }
  }
  scene.image = render_lambertian(scene.normals, light, 1.0, scene.mask);
  return scene;
}

namespace {

// synthetic.BUMPS, read from the file it is held in: (centre x, centre y, sigma, amplitude) in units
// of the image size.
std::vector<std::array<double, 4>> bump_features() {
  const std::string path = std::string(SHADECUT_ADDON_DIR) + "/shadecut/synthetic_bumps.csv";
  std::ifstream file(path);
  std::string line;
  if (!std::getline(file, line)) throw std::runtime_error("cannot read " + path);
  std::vector<std::array<double, 4>> features;
  while (std::getline(file, line)) {
    std::array<double, 4> row{};
    std::istringstream fields(line);
    for (double& value : row) {
      std::string field;
      std::getline(fields, field, ',');
      value = std::stod(field);
    }
    features.push_back(row);
  }
  return features;
}

}  // namespace

Scene bumps_scene(int size, const Eigen::Vector3d& light) {
  const std::vector<std::array<double, 4>> features = bump_features();
  const double centre = 0.5 * (size - 1);
  Scene scene{ImageF::Zero(size, size), NormalMap(size, size), ImageF::Zero(size, size), Mask::Constant(size, size, true)};
  for (int r = 0; r < size; ++r) {
    for (int c = 0; c < size; ++c) {
      const double x = c - centre, y = centre - r;
      double z = 0.0, dz_dx = 0.0, dz_dy = 0.0;
      for (const auto& f : features) {
        const double cx = f[0] * size, cy = f[1] * size, sigma = f[2] * size, amplitude = f[3] * size;
        const double g = amplitude * std::exp(-((x - cx) * (x - cx) + (y - cy) * (y - cy)) / (2.0 * sigma * sigma));
        z += g;
        dz_dx -= g * (x - cx) / (sigma * sigma);
        dz_dy -= g * (y - cy) / (sigma * sigma);
      }
      scene.depth(r, c) = float(z);
      scene.normals.xyz.row(Eigen::Index(r) * size + c) = Eigen::Vector3d(-dz_dx, -dz_dy, 1.0).normalized().cast<float>();
    }
  }
  scene.depth.array() -= scene.depth.minCoeff();
  scene.image = render_lambertian(scene.normals, light, 1.0, scene.mask);
  return scene;
}

Scene mozart_scene(const Eigen::Vector3d& light) {
  const std::string path = std::string(SHADECUT_DATA_DIR) + "/mozart/moz256.depth";
  std::ifstream file(path);
  if (!file) throw std::runtime_error("cannot open " + path);
  constexpr int kSize = 256;
  Scene scene;
  scene.depth = ImageF::Zero(kSize, kSize);
  for (Eigen::Index i = 0; i < scene.depth.size(); ++i)
    if (!(file >> scene.depth.data()[i])) throw std::runtime_error("short depth file " + path);
  scene.mask = scene.depth > 0.0f;
  scene.normals = normals_from_depth(scene.depth, scene.mask);
  scene.image = render_lambertian(scene.normals, light, 1.0, scene.mask);
  return scene;
}

std::pair<double, double> seam_and_inner_steps(const ImageF& depth) {
  const Eigen::Index rows = depth.rows(), cols = depth.cols();
  const double seam = std::max((depth.col(0) - depth.col(cols - 1)).abs().maxCoeff(),
                               (depth.row(0) - depth.row(rows - 1)).abs().maxCoeff());
  const double inner = std::max((depth.rightCols(cols - 1) - depth.leftCols(cols - 1)).abs().maxCoeff(),
                                (depth.bottomRows(rows - 1) - depth.topRows(rows - 1)).abs().maxCoeff());
  return {seam, inner};
}

}  // namespace shadecut::testing
