// The global step of the graph-cut methods: local estimates, tilt energy, convexity cut and
// alpha-expansion, optionally coarse to fine.
#pragma once

#include <shadecut/graphcut/alpha_expansion.hpp>
#include <shadecut/support/light.hpp>
#include <shadecut/local/local_shape.hpp>
#include <shadecut/graphcut/maxflow.hpp>
#include <shadecut/support/progress.hpp>
#include <shadecut/graphcut/tilt_energy.hpp>
#include <shadecut/support/types.hpp>

#include <map>
#include <string>
#include <vector>

namespace shadecut {

/// Built from ReconstructOptions by global_step_params (reconstruct.hpp), which holds the defaults:
/// the fields that mirror an option have none here; the two no option sets keep theirs.
struct GlobalStepParams {
  /// The energy. data_weight and undefined_weight are those of an object of kReferenceObjectSize
  /// pixels (reconstruct.hpp); each level scales them by its own unary_scale.
  TiltEnergyParams energy;
  double min_curvature{};      ///< local_shape's threshold of the undefined tilt
  int max_cycles{};            ///< alpha_expansion's
  double tolerance{};          ///< alpha_expansion's
  /// Coarse to fine: while the object is at least twice `coarsest_object_size` pixels across
  /// (object_size), the problem is first solved at half resolution; a pixel then only keeps the labels
  /// within `band` label steps of its coarse label. < 0: one level, every label (the exact
  /// alpha-expansion of the full-resolution energy).
  int band{};
  /// Coarse to fine, banded (Lombaert et al. 2005): at a finer level only pixels within this many
  /// pixels of a jump of the upsampled coarse labelling (neighbours more than one label step apart,
  /// or without a coarse label) keep the band; the others keep their coarse label. < 0: the band
  /// everywhere.
  int band_radius{};
  double coarsest_object_size = 48.0;
  bool refine{};  ///< labelling_normals' refine
  /// > 0: the coarsest level labels twice, with the paper's energy and with the energy pulled toward
  /// the normals of the level's viscosity solution (upwind.hpp; TiltEnergyParams::reference_weight =
  /// this for an object of kReferenceObjectSize pixels, scaled like data_weight); it integrates both
  /// labellings (Poisson, after filling the unreliable pixels) and keeps the one whose depth renders
  /// closer to the level's image (brightness_residual over its reliable pixels). When that is the
  /// pulled one, both are refined with the paper's energy up to the finest level whose object is at
  /// most `choice_object_size` pixels across (or the finest level, when it is smaller) and chosen
  /// between again there; the finer levels refine the one kept. 0 = the paper's energy alone.
  double viscosity_weight{};
  double choice_object_size = 256.0;
  int viscosity_rounds = 100;        ///< upwind's iterations
  double shadow_threshold{};         ///< unreliable_pixels' thresholds for that choice (< 0: no shadows)
  double highlight_threshold{};
  bool occluding_contour{};          ///< fill_normals' outline rule for that choice
  double max_slope{};                ///< the integrator's gradient clamp for that choice
};

struct GlobalStepResult {
  NormalMap normals;               ///< the labelling's normals (labelling_normals)
  std::vector<int> labelling;      ///< one label per pixel (meaningful inside the mask)
  AlphaExpansionStats expansion;   ///< the finest level's; moves and maxflow_seconds summed over levels
  double allowed_label_fraction = 0.0;  ///< share of (pixel, label) pairs left at the finest level
  int levels = 1;                  ///< resolutions solved, the finest included
  /// viscosity_weight: the mean squared brightness residual, at the level where they were chosen
  /// between (GlobalStepParams::viscosity_weight), of the paper's labelling and of the pulled one,
  /// and whether the pulled one was kept; 0, 0, false otherwise.
  double paper_residual = 0.0;
  double pulled_residual = 0.0;
  bool pulled_kept = false;
  /// The coarsest level's labelling judged by the energy (the paper's, with the outline's and the
  /// undefined tilts' terms, without dead-end elimination and without the viscosity pull), and its
  /// inversion judged likewise: every label turned by pi (the other local candidate, the normal turned
  /// by pi about the light; under a frontal light z -> -z), or the allowed label nearest that. Their
  /// difference is what the priors and the image say for the orientation chosen.
  double orientation_energy = 0.0;
  double inverted_energy = 0.0;
  std::map<std::string, double> seconds;  ///< "local", "energy", "graphcut" (cuts), "upwind", summed over levels
};

/// Labels every masked pixel of `image` with a tilt label of the energy built from it (see
/// TiltEnergy): local_shape, then for DataTerm::Soft and TwoCandidates alike the convexity cut and
/// alpha-expansion from the convex labelling; coarse to fine when params.band >= 0 (see
/// GlobalStepParams): the coarse labelling, upsampled, is the start and the band's centre, and the
/// fine level skips the convexity cut (the coarse level made that choice). With a viscosity_weight
/// the coarsest level chooses between two labellings, and a pulled one that leads is confirmed at a
/// level of at most choice_object_size pixels (see GlobalStepParams::viscosity_weight).
///
/// @param[in] image     H x W linear intensity.
/// @param[in] mask      H x W.
/// @param[in] light     light frame.
/// @param[in] albedo    > 0.
/// @param[in] params    see GlobalStepParams.
/// @param[in] solver    the max-flow solver, reused by every level.
/// @param[in] progress  told the fraction of the step done, stages "local", "energy", "graphcut"
///                      ("upwind" with a viscosity_weight); may throw Cancelled.
GlobalStepResult global_step(const ImageF& image, const Mask& mask, const LightFrame& light, double albedo,
                             const GlobalStepParams& params, MaxFlowSolver& solver, const Progress& progress = {});

}  // namespace shadecut
