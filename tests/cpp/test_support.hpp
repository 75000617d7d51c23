// Synthetic scenes with exact ground truth, shared by the C++ tests.
#pragma once

#include <shadecut/graphcut/global_step.hpp>
#include <shadecut/graphcut/tilt_energy.hpp>
#include <shadecut/support/types.hpp>

#include <Eigen/Core>

#include <string>
#include <utility>

namespace shadecut::testing {

/// A rendered surface and its truth.
struct Scene {
  ImageF image;      ///< Lambertian render, albedo 1
  NormalMap normals; ///< exact camera-frame normals
  ImageF depth;      ///< exact depth, pixel units
  Mask mask;
};

/// The energy the tests build by hand: eq. (15) with lambda 1 over reconstruct()'s default label
/// count, no undefined pull, outline term or reference (the fields a test changes it sets itself).
TiltEnergyParams paper_energy_params();

/// global_step on one level (the exact alpha-expansion) with reconstruct()'s defaults for graphcut
/// otherwise, without the outline term and the viscosity pull.
GlobalStepParams one_level_params();

/// Sphere of radius radius_fraction * size centred in a size x size image, rendered under `light`
/// with its analytic normals. `bowl` turns it upside down: the concave inside of the sphere.
Scene sphere_scene(int size, double radius_fraction, const Eigen::Vector3d& light, bool bowl = false);

/// The Gaussian bumps and dents of the Python tests (shadecut.synthetic.bumps with its BUMPS layout:
/// three bumps and three dents on a 3 x 2 grid, over the whole image), analytic normals, rendered
/// under `light`.
Scene bumps_scene(int size, const Eigen::Vector3d& light);

/// The largest step of `depth` between neighbours across the image's wrap-around edges (left column
/// to right, top row to bottom), and the largest between neighbours inside it.
std::pair<double, double> seam_and_inner_steps(const ImageF& depth);

/// The Mozart depth map of data/mozart (256 x 256, mask = depth > 0), normals by central differences,
/// rendered under `light`.
Scene mozart_scene(const Eigen::Vector3d& light);

}  // namespace shadecut::testing
