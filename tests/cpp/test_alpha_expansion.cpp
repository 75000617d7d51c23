#include "test_support.hpp"

#include <shadecut/alpha_expansion.hpp>
#include <shadecut/convexity_cut.hpp>
#include <shadecut/errors.hpp>
#include <shadecut/local_shape.hpp>
#include <shadecut/tilt_energy.hpp>

#include <reference_maxflow.hpp>

#include <gtest/gtest.h>

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
  TiltEnergyParams params;
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

TEST(TiltEnergy, RejectsTooFewLabels) {
  const testing::Scene scene = testing::sphere_scene(16, 0.45, {1, 0, 1});
  const LightFrame frame = LightFrame::from_direction({1, 0, 1});
  const LocalShape local = local_shape(scene.image, scene.mask, frame, 1.0, 1e-3);
  TiltEnergyParams params;
  params.labels = 3;
  EXPECT_THROW(TiltEnergy(local, frame, scene.mask, params), InvalidArgument);
}

}  // namespace
}  // namespace shadecut
