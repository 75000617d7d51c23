// graphcut and graphcut_two: the paper's global step (graphcut/global_step.hpp).
#include <shadecut/graphcut/global_step.hpp>
#include <shadecut/graphcut/maxflow.hpp>
#include <shadecut/pipeline/stage_params.hpp>

#include "pipeline/method_registry.hpp"

namespace shadecut::detail {

NormalMap solve_graph_cut(const MethodInput& input, ReconstructStats& stats) {
  const auto solver = make_maxflow_solver();
  GlobalStepResult solved =
      global_step(input.image, input.mask, input.frame, input.albedo, global_step_params(input.options), *solver, input.progress);
  for (const auto& [stage, seconds] : solved.seconds) stats.seconds[stage] = seconds;
  stats.allowed_label_fraction = solved.allowed_label_fraction;
  stats.energy_per_cycle = solved.expansion.energy_per_cycle;
  stats.cycles = solved.expansion.cycles;
  stats.iterations = solved.expansion.cycles;
  stats.moves = solved.expansion.moves;
  stats.accepted_moves = solved.expansion.accepted_moves;
  stats.maxflow_seconds = solved.expansion.maxflow_seconds;
  stats.levels = solved.levels;
  stats.paper_residual = solved.paper_residual;
  stats.pulled_residual = solved.pulled_residual;
  stats.pulled_kept = solved.pulled_kept;
  stats.orientation_energy = solved.orientation_energy;
  stats.inverted_energy = solved.inverted_energy;
  return std::move(solved.normals);
}

}  // namespace shadecut::detail
