// What reconstruct() returns: the surface, the albedo and light used, and what the call did.
#pragma once

#include <shadecut/pipeline/cut_out.hpp>
#include <shadecut/support/types.hpp>

#include <Eigen/Core>

#include <cstdint>
#include <limits>
#include <map>
#include <string>
#include <vector>

namespace shadecut {

struct ReconstructStats {
  std::map<std::string, double> seconds;    ///< per stage run ("light", "local", "energy", "graphcut",
                                            ///< "brooks_horn", "tsai_shah", "upwind", "pentland", "integration", "fit_shading", "orientation": the
                                            ///< inverted surface judged, judge_orientation) and "total"; with retinex
                                            ///< summed over its passes, beside "albedo" (the paint)
  std::vector<double> energy_per_cycle;     ///< initial energy, then after every alpha-expansion cycle
  int cycles = 0;
  int iterations = 0;                       ///< alpha-expansion cycles, brooks_horn or tsai_shah sweeps, upwind rounds, pentland solves; 0 for lee_rosenfeld
  bool light_estimated = false;             ///< whether the light (and, without a given albedo, the albedo) was estimated
  /// degrees: how far the estimated light may be off (LightEstimate::uncertainty), NaN
  /// when the light was given or its estimator does not know it
  double light_uncertainty = std::numeric_limits<double>::quiet_NaN();
  int moves = 0;                            ///< expansion moves, summed over the levels
  int accepted_moves = 0;
  int levels = 0;                           ///< graphcut, graphcut_two: resolutions solved (coarse to fine)
  double maxflow_seconds = 0.0;
  double allowed_label_fraction = 0.0;      ///< share of (pixel, label) pairs left after pruning
  int shadow_pixels = 0;                    ///< pixels whose normals were filled from their neighbours
                                            ///< (attached shadows and highlights: fill_normals)
  /// reliefs: the detail size used (pixels; options.detail_size or the one read from the image);
  /// NaN for objects and when every form is kept
  double detail_size = std::numeric_limits<double>::quiet_NaN();
  /// viscosity_weight: the mean squared brightness residuals of the paper's labelling's integrated
  /// depth and of the pulled one's on which the choice was made (the coarsest level's when the paper's
  /// led there, else those of the finest level of at most GlobalStepParams::choice_object_size
  /// pixels), and whether the pulled one was kept (the graph-cut statistics above are the kept
  /// one's); 0, 0, false when it did not run.
  double paper_residual = 0.0;
  double pulled_residual = 0.0;
  bool pulled_kept = false;
  /// The orientation: how much the result beats its inversion, every normal turned by pi about the
  /// light (n -> 2 (n . S) S - n: the other normal of the same brightness, the local step's other
  /// candidate; under a frontal light (nx, ny, nz) -> (-nx, -ny, nz), flip_surface's inversion).
  /// graphcut, graphcut_two: the energy of the coarsest level's labelling and of its inversion
  /// (GlobalStepResult::orientation_energy, inverted_energy); 0 for the other methods.
  double orientation_energy = 0.0;
  double inverted_energy = 0.0;
  /// Every method: the mean squared brightness residual (mean_brightness_residual) of the returned
  /// depth and of the inversion's (its normals made a surface as the result's were: filled,
  /// integrated, flattened for a relief), over the mask without shadows and highlights; for an object
  /// 512 pixels across or more, both on means of blocks that bring it to 256-511 pixels (a block with
  /// a shadow or a highlight not counted).
  double orientation_residual = 0.0;
  double inverted_residual = 0.0;
  /// inverted_residual < kAmbiguousResidualRatio * orientation_residual: the image explains the
  /// inversion nearly as well as the result, so the priors (the outline, the relief rule) chose the
  /// orientation, not the image; flip_surface gives the other one.
  bool orientation_ambiguous = false;
  /// fit_shading: the brightness residual before and after (FitShadingStats) and the steps taken;
  /// all 0 when it did not run.
  double shading_residual_before = 0.0;
  double shading_residual_after = 0.0;
  int fit_steps = 0;
  /// ReconstructOptions::cut_out: how the cut-out ended (not_tried when it did not run; the mask is
  /// the cut-out's only when found), its CutOut::outline_contrast and its sentence for the user.
  CutOutOutcome cut_out = CutOutOutcome::NotTried;
  double cut_out_contrast = 0.0;
  std::string cut_out_message;
  /// One photograph: the share of the mask's pixels brighter than the albedo used, which a
  /// Lambertian surface of that albedo cannot be (they are read as facing the light). A given albedo
  /// with more than kBrighterThanAlbedoShare of them is likely wrong, and albedo_message says so for
  /// the user; empty otherwise (an estimated albedo may leave highlights above it by design).
  double brighter_than_albedo = 0.0;
  std::string albedo_message;
  /// How many photographs the call read; with several, the masked pixels where two were usable (the
  /// graph cut chose between their two normals), one, and none (both filled from their neighbours),
  /// and of those fitted from three or more, the ones where four were usable and one missed the
  /// others' fit (the graph cut chose which of the four to leave out: PhotometricStereoResult::four_fits).
  int photographs = 1;
  std::int64_t pair_pixels = 0;
  std::int64_t four_fit_pixels = 0;
  std::int64_t single_pixels = 0;
  std::int64_t dark_pixels = 0;
  /// Several photographs, lights estimated, an object: its outline turned the lights the hint's first
  /// tilt gave by half a circle (the surface's inversion, which the photographs leave open).
  bool lights_turned_by_outline = false;
};

struct Reconstruction {
  NormalMap normals;       ///< H x W camera-frame unit normals, 0 outside the mask; a relief's are its depth's
  ImageF depth;            ///< H x W, pixel units, larger = closer; each mask component's minimum is 0
  Mask mask;               ///< H x W, the pixels reconstructed
  double albedo = 0.0;     ///< the albedo used (given or estimated): of the brightest paint with retinex
  ImageF albedo_map;       ///< H x W albedo per pixel (albedo everywhere unless retinex), 0 outside the mask
  /// H x W x 3 for a colour image: the de-lit colour, albedo_map times the image's chromaticity; empty
  /// (0 x 0 channels) for a grey image.
  ColourImage albedo_colour;
  Eigen::Vector3d light;   ///< unit light direction used, camera frame (the first photograph's)
  /// Several photographs: the unit light of each, as used; one photograph: its light alone.
  std::vector<Eigen::Vector3d> lights;
  /// H x W, how far the photographs are from the result (residual_map): the RMS over them of
  /// intensity - albedo_map max(0, n . S_k), for one photograph |intensity - albedo_map max(0, n . S)|
  /// (their intensity units, 0 outside the mask). Where the result does not explain the image stands
  /// out: cast shadows, highlights, paint the surface does not account for.
  ImageF residual;
  ReconstructStats stats;
};

/// ReconstructStats::albedo_message: the share of the mask above which a given albedo below the
/// image's brightness is named (a few noisy or specular pixels are not).
constexpr double kBrighterThanAlbedoShare = 0.01;

/// A result is ambiguous in its orientation (ReconstructStats::orientation_ambiguous) when its
/// inversion renders less than this many times as far from the image (mean squared residual) as the
/// result: under a frontal light both render alike (ratio 1), and the ratio grows as the light leaves
/// the viewer (docs/method.md, "10. Orientation", has the measured ratios).
constexpr double kAmbiguousResidualRatio = 2.0;

}  // namespace shadecut
