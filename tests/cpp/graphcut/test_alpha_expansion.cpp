#include "test_support.hpp"

#include <shadecut/graphcut/alpha_expansion.hpp>
#include <shadecut/graphcut/convexity_cut.hpp>
#include <shadecut/support/errors.hpp>
#include <shadecut/local/local_shape.hpp>
#include <shadecut/graphcut/tilt_energy.hpp>

#include <reference_maxflow.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

namespace shadecut {
namespace {

struct Problem {
  LightFrame frame;
  LocalShape local;
  TiltEnergy energy;
};

Problem make_problem(const testing::Scene& scene, const Eigen::Vector3d& light, DataTerm term,
                     double undefined_weight = 0.0) {
  const LightFrame frame = LightFrame::from_direction(light);
  LocalShape local = local_shape(scene.image, scene.mask, frame, 1.0, 1e-3);
  TiltEnergyParams params = testing::paper_energy_params();
  params.data_term = term;
  params.undefined_weight = undefined_weight;
  TiltEnergy energy(local, frame, scene.mask, params);
  return {frame, std::move(local), std::move(energy)};
}

TEST(AlphaExpansion, EnergyNeverRisesWithAnySolver) {
  const Eigen::Vector3d light(1, 0, 1);
  const testing::Scene scene = testing::mozart_scene(light);
  for (DataTerm term : {DataTerm::Soft, DataTerm::TwoCandidates}) {
    const Problem problem = make_problem(scene, light, term);
    std::vector<double> finals;
    for (MaxFlowKind kind : {MaxFlowKind::Grid, MaxFlowKind::OpenCV, MaxFlowKind::Boost}) {
      std::vector<int> labelling = problem.energy.convex_labelling();
      const auto solver = make_maxflow_solver(kind);
      const AlphaExpansionStats stats = alpha_expansion(problem.energy, labelling, *solver, 5);
      ASSERT_GE(stats.energy_per_cycle.size(), 2u);
      for (std::size_t i = 1; i < stats.energy_per_cycle.size(); ++i)
        EXPECT_LE(stats.energy_per_cycle[i], stats.energy_per_cycle[i - 1] + 1e-9) << to_string(kind);
      EXPECT_LT(stats.energy_per_cycle.back(), stats.energy_per_cycle.front()) << to_string(kind);
      EXPECT_NEAR(stats.energy_per_cycle.back(), problem.energy.energy(labelling), 1e-6 * stats.energy_per_cycle.back());
      finals.push_back(stats.energy_per_cycle.back());
    }
    // Different minimum cuts lead to different local minima, but of nearly the same energy.
    EXPECT_NEAR(finals[0], finals[2], 0.01 * finals[2]);
  }
}

// The grid solver, without the promise that lets alpha-expansion keep flows: every move is a full,
// cold cut.
class ColdGridSolver final : public MaxFlowSolver {
 public:
  double solve(GridGraph& graph, std::vector<std::uint8_t>& sink_side) override { return grid_->solve(graph, sink_side); }

 private:
  std::unique_ptr<MaxFlowSolver> grid_ = make_maxflow_solver();
};

// Kept flows, warm starts and sparse repairs find the same minimum cut as a cold cut of every move
// (the grid solver reports the smallest sink side, which every maximum flow determines), so the whole
// run follows the same path, up to float rounding in near ties. Without the pull of undefined tilts
// whole regions tie exactly, and which of two equal cuts rounding picks differs from run to run.
TEST(AlphaExpansion, KeptFlowsFindTheSameMovesAsColdCuts) {
  const Eigen::Vector3d light(1, 0, 1);
  const testing::Scene scenes[] = {testing::mozart_scene(light), testing::sphere_scene(96, 0.45, light, /*bowl=*/true)};
  for (const testing::Scene& scene : scenes) {
    const Problem problem = make_problem(scene, light, DataTerm::Soft, 0.2);
    std::vector<int> warm_labelling = problem.energy.convex_labelling();
    std::vector<int> cold_labelling = warm_labelling;
    const auto grid = make_maxflow_solver();
    ColdGridSolver cold;
    const AlphaExpansionStats warm_stats = alpha_expansion(problem.energy, warm_labelling, *grid, 20);
    const AlphaExpansionStats cold_stats = alpha_expansion(problem.energy, cold_labelling, cold, 20);
    EXPECT_GT(warm_stats.repaired_moves, 0);
    EXPECT_EQ(cold_stats.repaired_moves, 0);
    EXPECT_EQ(warm_stats.cycles, cold_stats.cycles);
    EXPECT_EQ(warm_stats.moves, cold_stats.moves);
    ASSERT_EQ(warm_stats.energy_per_cycle.size(), cold_stats.energy_per_cycle.size());
    for (std::size_t i = 0; i < warm_stats.energy_per_cycle.size(); ++i)
      EXPECT_NEAR(warm_stats.energy_per_cycle[i], cold_stats.energy_per_cycle[i], 1e-6 * cold_stats.energy_per_cycle[i]);
    int differ = 0;
    for (std::size_t p = 0; p < warm_labelling.size(); ++p) differ += warm_labelling[p] != cold_labelling[p];
    EXPECT_LE(differ, int(1e-3 * double(scene.mask.count())));
  }
}

TEST(ConvexityCut, TurnsTheBowlConcaveAndLowersTheEnergy) {
  const Eigen::Vector3d light(1, 0, 1);
  const testing::Scene bowl = testing::sphere_scene(96, 0.45, light, /*bowl=*/true);
  const Problem problem = make_problem(bowl, light, DataTerm::TwoCandidates);
  std::vector<int> labelling = problem.energy.convex_labelling();
  const double before = problem.energy.energy(labelling);
  const auto solver = make_maxflow_solver();
  convexity_cut(problem.energy, problem.local, labelling, *solver);
  EXPECT_LT(problem.energy.energy(labelling), before);
  int concave = 0, decided = 0;
  for (int p = 0; p < problem.energy.rows() * problem.energy.cols(); ++p) {
    if (!bowl.mask.data()[p] || !problem.local.tilt_defined.data()[p]) continue;
    const double tilt = problem.energy.label_tilt(labelling[std::size_t(p)]);
    const double d = std::abs(std::remainder(tilt - problem.local.tilt.data()[p], 2.0 * M_PI));
    concave += d < M_PI / 2;
    ++decided;
  }
  EXPECT_GT(concave, 0.99 * decided);
}

// The soft energy of a scene without the outline term and with contour_weight 2.
struct ContourEnergies {
  ContourEnergies(const testing::Scene& scene, const Eigen::Vector3d& light)
      : frame(LightFrame::from_direction(light)),
        local(local_shape(scene.image, scene.mask, frame, 1.0, 1e-3)),
        without(local, frame, scene.mask, testing::paper_energy_params()),
        with(local, frame, scene.mask, with_contour()) {}
  static TiltEnergyParams with_contour() {
    TiltEnergyParams params = testing::paper_energy_params();
    params.contour_weight = 2.0;
    return params;
  }
  LightFrame frame;
  LocalShape local;
  TiltEnergy without, with;
};

TEST(TiltEnergy, TheOutlineFavoursNormalsPointingOutOfTheSilhouette) {
  const Eigen::Vector3d light(0.5, 0.3, 1.0);
  const testing::Scene scene = testing::sphere_scene(48, 0.4, light);
  const ContourEnergies energies(scene, light);
  const LightFrame& frame = energies.frame;
  const LocalShape& local = energies.local;
  const TiltEnergy &without = energies.without, &with = energies.with;
  TiltEnergyParams params = testing::paper_energy_params();
  const double centre = 0.5 * (48 - 1);
  int outline = 0, compared = 0;
  for (int r = 1; r < 47; ++r) {
    for (int c = 1; c < 47; ++c) {
      if (!scene.mask(r, c)) continue;
      const int p = r * 48 + c;
      const bool on_edge = !scene.mask(r - 1, c) || !scene.mask(r + 1, c) || !scene.mask(r, c - 1) || !scene.mask(r, c + 1);
      outline += on_edge;
      for (int k = 0; k < with.labels(); ++k) {
        if (!with.allowed(p, k) || !without.allowed(p, k)) continue;
        const double added = double(with.data_cost(p, k)) - double(without.data_cost(p, k));
        if (!on_edge) {
          EXPECT_NEAR(added, 0.0, 1e-6);
          continue;
        }
        // Independently: the label's normal against the direction from the disc's centre.
        const Eigen::Vector3d n = frame.normal(local.slant(r, c), with.label_tilt(k));
        const Eigen::Vector2d radial = Eigen::Vector2d(c - centre, centre - r).normalized();
        const double d = std::acos(std::clamp(n.head<2>().normalized().dot(radial), -1.0, 1.0));
        // contour_outward is the 4-neighbour edge direction, within 45 degrees of the radial one.
        EXPECT_LE(added, 2.0 * 0.5 * (1.0 - std::cos(std::min(M_PI, d + M_PI / 4))) + 1e-6);
        EXPECT_GE(added, 2.0 * 0.5 * (1.0 - std::cos(std::max(0.0, d - M_PI / 4))) - 1e-6);
        ++compared;
      }
    }
  }
  EXPECT_GT(outline, 50);
  EXPECT_GT(compared, 500);
  params.contour_weight = -1.0;
  EXPECT_THROW(TiltEnergy(local, frame, scene.mask, params), InvalidArgument);
}

TEST(TiltEnergy, ABowlsRimGetsNoOutlineTerm) {
  // Brighter on the side facing away from the light: a rim, whose normals point inward.
  const Eigen::Vector3d light(0.5, 0.3, 1.0);
  const ContourEnergies energies(testing::sphere_scene(48, 0.4, light, true), light);
  for (int p = 0; p < 48 * 48; ++p)
    for (int k = 0; k < energies.with.labels(); ++k) ASSERT_EQ(energies.with.data_cost(p, k), energies.without.data_cost(p, k));
}

TEST(TiltEnergy, AReferencePullsEachLabelByItsChordToTheReferenceNormal) {
  const Eigen::Vector3d light(0.5, 0.3, 1.0);
  const testing::Scene scene = testing::sphere_scene(32, 0.4, light);
  const LightFrame frame = LightFrame::from_direction(light);
  const LocalShape local = local_shape(scene.image, scene.mask, frame, 1.0, 1e-3);
  TiltEnergyParams params = testing::paper_energy_params();
  const TiltEnergy without(local, frame, scene.mask, params);
  params.reference = &scene.normals;
  params.reference_weight = 0.5;
  const TiltEnergy with(local, frame, scene.mask, params);
  int compared = 0;
  for (int p = 0; p < 32 * 32; ++p) {
    if (!scene.mask.data()[p]) continue;
    const Eigen::Vector3d truth = scene.normals.xyz.row(p).transpose().cast<double>();
    for (int k = 0; k < with.labels(); ++k) {
      if (!with.allowed(p, k) || !without.allowed(p, k)) continue;
      const Eigen::Vector3d n = frame.normal(local.slant.data()[p], with.label_tilt(k));
      EXPECT_NEAR(double(with.data_cost(p, k)) - double(without.data_cost(p, k)), 0.5 * (n - truth).norm(), 1e-5);
      ++compared;
    }
  }
  EXPECT_GT(compared, 1000);
  const NormalMap wrong_shape(16, 16);
  params.reference = &wrong_shape;
  EXPECT_THROW(TiltEnergy(local, frame, scene.mask, params), InvalidArgument);
  params.reference = &scene.normals;
  params.reference_weight = -1.0;
  EXPECT_THROW(TiltEnergy(local, frame, scene.mask, params), InvalidArgument);
}

TEST(TiltEnergy, RejectsTooFewLabels) {
  const testing::Scene scene = testing::sphere_scene(16, 0.45, {1, 0, 1});
  const LightFrame frame = LightFrame::from_direction({1, 0, 1});
  const LocalShape local = local_shape(scene.image, scene.mask, frame, 1.0, 1e-3);
  TiltEnergyParams params = testing::paper_energy_params();
  params.labels = 3;
  EXPECT_THROW(TiltEnergy(local, frame, scene.mask, params), InvalidArgument);
}

}  // namespace
}  // namespace shadecut
