// What reconstruct() hands each stage: its parameters filled from the options (and method_defaults
// where an option is unset), the one translation from options to a stage's parameters.
#pragma once

#include <shadecut/estimate/estimate_reflectance.hpp>
#include <shadecut/graphcut/global_step.hpp>
#include <shadecut/pipeline/reconstruct_options.hpp>
#include <shadecut/refine/fit_shading.hpp>

namespace shadecut {

/// For the graph-cut methods (graphcut, graphcut_two), with the thread count of the reconstruct()
/// in progress (every core outside one).
GlobalStepParams global_step_params(const ReconstructOptions& options);

/// For fit_shading when options.fit_shading is on: options.fit_smoothness.
FitShadingParams fit_shading_params(const ReconstructOptions& options);

/// For estimate_reflectance with albedo_method retinex: the options' retinex_* values (the rim for
/// objects only).
ReflectanceParams reflectance_params(const ReconstructOptions& options);

}  // namespace shadecut
