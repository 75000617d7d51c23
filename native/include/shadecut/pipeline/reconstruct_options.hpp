// Every setting of reconstruct(), grouped by the stage that reads it. What each field means, its
// allowed range and its one line of help are in the option table (option_table.hpp), the one place
// from which the checks, the Python binding, the command line's flags and the docs' table follow.
#pragma once

#include <shadecut/estimate/estimate_albedo.hpp>
#include <shadecut/estimate/estimate_light.hpp>
#include <shadecut/integrate/integrate.hpp>
#include <shadecut/photometric/choose_candidates.hpp>
#include <shadecut/photometric/estimate_lights.hpp>
#include <shadecut/photometric/photometric_stereo.hpp>
#include <shadecut/pipeline/method.hpp>
#include <shadecut/pipeline/scene_kind.hpp>
#include <shadecut/support/progress.hpp>

#include <optional>

namespace shadecut {

/// highlight_threshold when unset with one albedo (top_fit, brightest): never.
constexpr double kHighlightThreshold = 0.0;
/// highlight_threshold when unset with albedo_method retinex: the shading image keeps the highlights
/// the paint step does not read, and every pixel above its albedo is one of them.
constexpr double kRetinexHighlightThreshold = 1.0;

/// The fewest tilt labels the energy can be built with.
constexpr int kMinLabels = 4;
/// The most threads a call may ask for: more than the machine has only costs memory.
constexpr int kMaxThreads = 256;

/// The defaults are the tuned ones (docs/parameters.md); an optional left unset takes the rule its
/// table entry names (most often method_defaults). Per-object weights are scaled to the object's
/// size by unary_scale (local_shape.hpp).
struct ReconstructOptions {
  // The scene and the method
  SceneKind scene = SceneKind::Object;
  bool cut_out = true;
  Method method = Method::GraphCut;
  std::optional<LightMethod> light_method;
  // The graph cut (graphcut, graphcut_two)
  int labels = 36;
  double data_weight = 0.2;
  std::optional<double> undefined_weight;
  std::optional<double> min_curvature;
  int max_cycles = 20;
  int coarse_to_fine_band = 1;
  int coarse_to_fine_radius = 0;
  bool refine = true;
  double contour_weight = 10.0;
  double viscosity_weight = 0.3;
  // The iterative methods (and the graph cut's stopping rule)
  std::optional<double> tolerance;
  std::optional<int> iterations;
  std::optional<double> smoothness;
  // The paint
  AlbedoMethod albedo_method = AlbedoMethod::TopFit;
  double retinex_chroma_edge = 0.02;
  double retinex_intensity_edge = 0.2;
  int retinex_rim = 0;
  double retinex_highlight = 0.0;
  double retinex_shadow = 0.05;
  int retinex_passes = 2;
  // Shadows and highlights
  bool fill_shadows = true;
  double shadow_threshold = 1e-3;
  std::optional<double> highlight_threshold;
  bool occluding_contour = true;
  // Integration
  Integrator integrator = Integrator::Poisson;
  double max_slope = 10.0;
  bool seamless = false;
  // Refinement
  bool fit_shading = false;
  double fit_smoothness = 0.05;
  double fit_max_slant = 65.0;
  // Reliefs
  double detail_size = 0.0;
  double detail_scale_factor = 1.5;
  int paint_line_width = 9;
  double paint_line_contrast = 2.0;
  // Several photographs (photometric/): the defaults are the stages' own
  double photometric_shadow_fraction = PhotometricStereoParams{}.shadow_fraction;
  double photometric_outlier_tolerance = PhotometricStereoParams{}.outlier_tolerance;
  double candidate_smoothness = CandidateCutParams{}.smoothness;
  double light_slant = LightHint{}.slant;
  double first_light_tilt = LightHint{}.first_tilt;
  double light_distance = 0.0;
  // Runtime
  int threads = 0;
  /// Told the fraction of the call done and the stage: "cut_out", "light" (estimating it), "local", "energy",
  /// "graphcut", "brooks_horn", "tsai_shah", "upwind", "pentland", "integration", "fit_shading"; with several photographs
  /// also "photometric stereo" and "candidate cut". Returning false cancels.
  ProgressCallback progress;
};

/// The highlight threshold a call uses: options.highlight_threshold, or when unset
/// kRetinexHighlightThreshold with albedo_method retinex and kHighlightThreshold otherwise.
double highlight_threshold_used(const ReconstructOptions& options);

/// The light estimator reconstruct() uses when given no light: options.light_method, or for the
/// scene kind: zheng_chellappa for an object, relief for a relief (whose normals are nothing like
/// the sphere's the others assume).
LightMethod light_method_used(const ReconstructOptions& options);

}  // namespace shadecut
