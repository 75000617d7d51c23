#include "test_support.hpp"

#include <shadecut/support/angular_error.hpp>
#include <shadecut/graphcut/global_step.hpp>
#include <shadecut/local/local_shape.hpp>
#include <shadecut/pipeline/reconstruct.hpp>
#include <shadecut/graphcut/tilt_energy.hpp>

#include <reference_maxflow.hpp>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <vector>

namespace shadecut {
namespace {

int circular_steps(int a, int b, int labels) {
  const int d = ((a - b) % labels + labels) % labels;
  return std::min(d, labels - d);
}

// A sphere under (1, 0, 1) with its local shape: the energies of the band tests are built from it.
struct BandScene {
  testing::Scene scene = testing::sphere_scene(64, 0.45, Eigen::Vector3d(1, 0, 1));
  LightFrame frame = LightFrame::from_direction(Eigen::Vector3d(1, 0, 1));
  LocalShape local = local_shape(scene.image, scene.mask, frame, 1.0, 1.0);

  TiltEnergy energy(const TiltEnergyParams& params) const { return TiltEnergy(local, frame, scene.mask, params); }
};

TEST(GlobalStep, BandKeepsOnlyLabelsNearTheCentreUnlessNoneIsAllowed) {
  const BandScene band;
  const testing::Scene& scene = band.scene;
  TiltEnergyParams params = testing::paper_energy_params();
  const TiltEnergy full = band.energy(params);
  const int n = int(scene.mask.size()), labels = params.labels;
  std::vector<int> centre(std::size_t(n), -1);
  for (int p = 0; p < n; ++p) centre[std::size_t(p)] = p % 3 == 0 ? -1 : p % labels;
  params.band_centre = &centre;
  params.band = 2;
  const TiltEnergy banded = band.energy(params);
  int kept_all = 0;
  for (int p = 0; p < n; ++p) {
    if (!scene.mask.data()[p]) continue;
    bool any_in_band = false;
    for (int k = 0; k < labels; ++k)
      any_in_band = any_in_band || (full.allowed(p, k) && circular_steps(k, centre[std::size_t(p)], labels) <= 2);
    const bool unrestricted = centre[std::size_t(p)] < 0 || !any_in_band;
    kept_all += unrestricted && centre[std::size_t(p)] >= 0;
    for (int k = 0; k < labels; ++k) {
      if (unrestricted) {
        EXPECT_EQ(banded.allowed(p, k), full.allowed(p, k)) << p << " " << k;
      } else if (circular_steps(k, centre[std::size_t(p)], labels) > 2) {
        EXPECT_FALSE(banded.allowed(p, k)) << p << " " << k;
      } else if (!full.allowed(p, k)) {
        EXPECT_FALSE(banded.allowed(p, k)) << p << " " << k;
      }
    }
  }
  // The scene has pixels whose band holds only labels facing away: they keep every label.
  EXPECT_GT(kept_all, 0);
}

TEST(GlobalStep, FrozenPixelsKeepOnlyTheirCentreWhereItIsAllowed) {
  const BandScene band;
  const testing::Scene& scene = band.scene;
  TiltEnergyParams params = testing::paper_energy_params();
  const TiltEnergy full = band.energy(params);
  const int n = int(scene.mask.size()), labels = params.labels;
  std::vector<int> centre(std::size_t(n), 0);
  std::vector<std::uint8_t> frozen(std::size_t(n), 0);
  for (int p = 0; p < n; ++p) centre[std::size_t(p)] = p % labels, frozen[std::size_t(p)] = p % 2;
  params.band_centre = &centre;
  params.band = 1;
  params.band_frozen = &frozen;
  const TiltEnergy banded = band.energy(params);
  int single = 0;
  for (int p = 0; p < n; ++p) {
    if (!scene.mask.data()[p] || !frozen[std::size_t(p)]) continue;
    const int c = centre[std::size_t(p)];
    int kept = 0;
    for (int k = 0; k < labels; ++k) kept += banded.allowed(p, k);
    if (full.allowed(p, c)) {
      EXPECT_EQ(kept, 1) << p;
      EXPECT_TRUE(banded.allowed(p, c)) << p;
      ++single;
    } else {
      // The centre faces away: the pixel keeps its band, or every label when none of it is allowed.
      EXPECT_GT(kept, 0) << p;
      EXPECT_FALSE(banded.allowed(p, c)) << p;
    }
  }
  EXPECT_GT(single, 0);
}

// The OpenCV and Boost solvers are test oracles, not user options: each gives the same quality.
TEST(GlobalStep, EveryMaxFlowSolverGivesTheSameQuality) {
  const Eigen::Vector3d light(1, 0, 1);
  const testing::Scene scene = testing::sphere_scene(64, 0.45, light);
  const LightFrame frame = LightFrame::from_direction(light);
  GlobalStepParams params = testing::one_level_params();
  params.energy.data_weight = 0.2 * unary_scale(scene.mask);
  params.energy.undefined_weight = 0.5 * unary_scale(scene.mask);
  std::vector<double> errors;
  for (MaxFlowKind kind : {MaxFlowKind::Grid, MaxFlowKind::OpenCV, MaxFlowKind::Boost}) {
    const auto solver = make_maxflow_solver(kind);
    const GlobalStepResult found = global_step(scene.image, scene.mask, frame, 1.0, params, *solver);
    errors.push_back(mean_angular_error(found.normals, scene.normals, scene.mask));
  }
  EXPECT_LT(*std::max_element(errors.begin(), errors.end()) - *std::min_element(errors.begin(), errors.end()), 0.5);
}

TEST(GlobalStep, CoarseToFineReachesNearlyTheExactEnergyAndAccuracy) {
  const Eigen::Vector3d light(1.5, 0.866, 1);
  const testing::Scene scene = testing::sphere_scene(256, 0.45, light);
  const LightFrame frame = LightFrame::from_direction(light);
  GlobalStepParams params = testing::one_level_params();
  params.energy.data_weight = 0.2;
  params.energy.undefined_weight = 0.5;
  const auto solver = make_maxflow_solver();
  const GlobalStepResult exact = global_step(scene.image, scene.mask, frame, 1.0, params, *solver);
  params.band = 1;
  const GlobalStepResult fast = global_step(scene.image, scene.mask, frame, 1.0, params, *solver);
  EXPECT_EQ(exact.levels, 1);
  EXPECT_EQ(fast.levels, 3);  // object 203 px -> 101 -> 50 (below twice the coarsest size, 96)
  EXPECT_LT(fast.allowed_label_fraction, 0.5 * exact.allowed_label_fraction);
  const double exact_energy = exact.expansion.energy_per_cycle.back();
  const double fast_energy = fast.expansion.energy_per_cycle.back();
  // A local minimum of the banded moves, measured 2.4% above the exact run's (README, "Speed").
  EXPECT_LE(fast_energy, 1.03 * exact_energy);
  const Mask inner = erode_mask(scene.mask, 2);
  EXPECT_NEAR(mean_angular_error(fast.normals, scene.normals, inner),
              mean_angular_error(exact.normals, scene.normals, inner), 0.25);

  // Banded (the default radius): only pixels near a jump of the coarse labels keep the band. Its
  // energy is measured 4.3% above the exact one: where the coarse labels vary smoothly it keeps
  // their one-step quantisation, which the pairwise term charges but the snapping to the local
  // candidates removes from the normals; hence the same accuracy.
  params.band_radius = ReconstructOptions{}.coarse_to_fine_radius;
  const GlobalStepResult banded = global_step(scene.image, scene.mask, frame, 1.0, params, *solver);
  EXPECT_LT(banded.allowed_label_fraction, 0.5 * fast.allowed_label_fraction);
  EXPECT_LE(banded.expansion.energy_per_cycle.back(), 1.05 * exact_energy);
  EXPECT_NEAR(mean_angular_error(banded.normals, scene.normals, inner),
              mean_angular_error(exact.normals, scene.normals, inner), 0.25);
}


// Why graphcut misses issue 2's bound on the bumps under light (1, 0, 1) (a strict expected failure in
// tests/python/test_reconstruct.py): there the energy itself prefers a wrong surface. The labelling
// nearest the truth costs far more than the one alpha-expansion finds, and alpha-expansion started
// from the better local candidate at every pixel comes back to the found energy. A better search
// cannot help; the energy (with the parameters chosen on the training surfaces) would have to change.
TEST(GlobalStep, OnTheTestBumpsTheTruthCostsMoreThanTheLabellingFound) {
  const Eigen::Vector3d light(1, 0, 1);
  const testing::Scene scene = testing::bumps_scene(128, light);
  const LightFrame frame = LightFrame::from_direction(light);
  // graphcut's defaults, on one level: the exact alpha-expansion.
  const MethodDefaults defaults = method_defaults(Method::GraphCut);
  GlobalStepParams params = testing::one_level_params();
  params.energy.data_weight = ReconstructOptions().data_weight;
  params.energy.undefined_weight = defaults.undefined_weight;
  params.min_curvature = defaults.min_curvature;
  const auto solver = make_maxflow_solver();
  const GlobalStepResult found = global_step(scene.image, scene.mask, frame, 1.0, params, *solver);

  const LocalShape local = local_shape(scene.image, scene.mask, frame, 1.0, params.min_curvature);
  TiltEnergyParams energy_params = params.energy;
  energy_params.data_weight *= unary_scale(scene.mask);
  energy_params.undefined_weight *= unary_scale(scene.mask);
  const TiltEnergy energy(local, frame, scene.mask, energy_params);
  const int n = int(scene.mask.size());
  // Per pixel: the allowed label nearest the truth, and the label of the local candidate nearer it.
  std::vector<int> nearest_truth(static_cast<std::size_t>(n)), better_candidate(static_cast<std::size_t>(n));
  for (int p = 0; p < n; ++p) {
    const Eigen::Vector3d truth = scene.normals.xyz.row(p).cast<double>();
    const double slant = local.slant.data()[p];
    double best = -2.0;
    for (int k = 0; k < energy.labels(); ++k) {
      const double agreement = frame.normal(slant, energy.label_tilt(k)).dot(truth);
      if (energy.allowed(p, k) && agreement > best) best = agreement, nearest_truth[std::size_t(p)] = k;
    }
    better_candidate[std::size_t(p)] = nearest_truth[std::size_t(p)];
    if (local.tilt_defined.data()[p]) {
      const double t = local.tilt.data()[p];
      const double tilt = frame.normal(slant, t).dot(truth) > frame.normal(slant, t + M_PI).dot(truth) ? t : t + M_PI;
      better_candidate[std::size_t(p)] = energy.nearest_allowed_label(p, tilt);
    }
  }
  const Mask inner = erode_mask(scene.mask, 2);
  auto error = [&](const std::vector<int>& labelling) {
    return mean_angular_error(labelling_normals(labelling, energy, local, frame, params.refine), scene.normals, inner);
  };
  std::vector<int> from_candidates = better_candidate;
  alpha_expansion(energy, from_candidates, *solver, params.max_cycles);
  std::printf("bumps, light (1, 0, 1): energy / mean error: found %.1f / %.2f deg, nearest the truth %.1f / %.2f deg, "
              "better candidates %.1f / %.2f deg, alpha-expansion from them %.1f / %.2f deg\n",
              energy.energy(found.labelling), error(found.labelling), energy.energy(nearest_truth), error(nearest_truth),
              energy.energy(better_candidate), error(better_candidate), energy.energy(from_candidates),
              error(from_candidates));
  EXPECT_GT(error(found.labelling), 30.0);
  EXPECT_LT(error(nearest_truth), 2.0);
  EXPECT_GT(energy.energy(nearest_truth), 1.3 * energy.energy(found.labelling));
  EXPECT_GT(error(from_candidates), 30.0);
  EXPECT_LE(energy.energy(from_candidates), 1.01 * energy.energy(found.labelling));
}

// The mean angle between 4-neighbours' normals across the rows and columns at multiples of 8 pixels
// (coarse to fine's blocks from three levels down), over the mean across all the others:
// shadecut.evaluation.grid_step_ratio with its default periods.
double grid_step_ratio(const NormalMap& normals, const Mask& mask) {
  double on = 0.0, off = 0.0;
  long on_count = 0, off_count = 0;
  auto add = [&](Eigen::Index a, Eigen::Index b, bool grid) {
    const Eigen::Vector3d u = normals.xyz.row(a).cast<double>().normalized(), v = normals.xyz.row(b).cast<double>().normalized();
    const double angle = std::atan2(u.cross(v).norm(), u.dot(v));
    (grid ? on : off) += angle;
    ++(grid ? on_count : off_count);
  };
  const Eigen::Index rows = mask.rows(), cols = mask.cols();
  for (Eigen::Index r = 0; r < rows; ++r) {
    for (Eigen::Index c = 0; c < cols; ++c) {
      if (!mask(r, c)) continue;
      if (c + 1 < cols && mask(r, c + 1)) add(r * cols + c, r * cols + c + 1, (c + 1) % 8 == 0);
      if (r + 1 < rows && mask(r + 1, c)) add(r * cols + c, (r + 1) * cols + c, (r + 1) % 8 == 0);
    }
  }
  return (on / double(on_count)) / (off / double(off_count));
}

// Issue 29: the normals of coarse to fine (the defaults: four levels at 512 px, three at 256) step no
// more across the coarse blocks' edges than elsewhere. The pixels that keep their coarse label take
// the coarse level's tilts interpolated, not the block's label tilt, and a jump's pixels can take
// either side's label, so that its boundary is not pinned to the coarse pixels' edges. Before, the
// blocks' edges stepped up to twice as much (measured with this test before: bumps 1.98, sphere 1.44;
// now 1.07 and 1.07).
TEST(GlobalStep, CoarseToFineLeavesNoBlockGridInTheNormals) {
  const Eigen::Vector3d light(1, 0, 1);
  const LightFrame frame = LightFrame::from_direction(light);
  const GlobalStepParams params = global_step_params(ReconstructOptions{});
  const auto solver = make_maxflow_solver();
  for (const testing::Scene& scene : {testing::bumps_scene(256, light), testing::sphere_scene(256, 0.45, light)}) {
    const GlobalStepResult result = global_step(scene.image, scene.mask, frame, 1.0, params, *solver);
    EXPECT_GE(result.levels, 3);
    const double ratio = grid_step_ratio(result.normals, scene.mask);
    std::printf("grid step ratio %.3f (truth %.3f)\n", ratio, grid_step_ratio(scene.normals, scene.mask));
    EXPECT_LE(ratio, 1.1);
  }
}

}  // namespace
}  // namespace shadecut
