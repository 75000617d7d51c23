#include <shadecut/pipeline/stage_params.hpp>

#include "pipeline/surface_rules.hpp"
#include "support/parallel.hpp"

namespace shadecut {

GlobalStepParams global_step_params(const ReconstructOptions& options) {
  const MethodDefaults defaults = method_defaults(options.method);
  GlobalStepParams params;
  params.energy.labels = options.labels;
  params.energy.data_weight = options.data_weight;
  params.energy.undefined_weight = options.undefined_weight.value_or(defaults.undefined_weight);
  params.energy.contour_weight = detail::edge_is_outline(options) ? options.contour_weight : 0.0;
  params.energy.data_term = options.method == Method::GraphCut ? DataTerm::Soft : DataTerm::TwoCandidates;
  params.energy.threads = detail::default_thread_count();
  params.min_curvature = options.min_curvature.value_or(defaults.min_curvature);
  params.max_cycles = options.max_cycles;
  params.tolerance = options.tolerance.value_or(defaults.tolerance);
  params.band = options.coarse_to_fine_band;
  params.band_radius = options.coarse_to_fine_radius;
  params.refine = options.refine;
  // Tuned for graphcut only (docs/parameters.md).
  params.viscosity_weight = options.method == Method::GraphCut ? options.viscosity_weight : 0.0;
  params.shadow_threshold = detail::shadow_threshold_used(options);
  params.highlight_threshold = highlight_threshold_used(options);
  params.occluding_contour = detail::edge_is_outline(options);
  params.max_slope = options.max_slope;
  return params;
}

FitShadingParams fit_shading_params(const ReconstructOptions& options) {
  FitShadingParams params;
  params.smoothness = options.fit_smoothness;
  params.max_slant = options.fit_max_slant;
  return params;
}

ReflectanceParams reflectance_params(const ReconstructOptions& options) {
  ReflectanceParams params;
  params.chroma_edge = options.retinex_chroma_edge;
  params.intensity_edge = options.retinex_intensity_edge;
  params.rim = options.scene == SceneKind::Object ? options.retinex_rim : 0;
  params.highlight = options.retinex_highlight;
  params.shadow = options.retinex_shadow;
  return params;
}

}  // namespace shadecut
