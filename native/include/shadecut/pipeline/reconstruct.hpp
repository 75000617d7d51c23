// The whole pipeline: one shaded image in, normals and depth out.
#pragma once

#include <shadecut/estimate/estimate_albedo.hpp>
#include <shadecut/estimate/estimate_light.hpp>
#include <shadecut/estimate/estimate_reflectance.hpp>
#include <shadecut/graphcut/global_step.hpp>
#include <shadecut/integrate/integrate.hpp>
#include <shadecut/pipeline/cut_out.hpp>
#include <shadecut/refine/fit_shading.hpp>
#include <shadecut/support/progress.hpp>
#include <shadecut/support/types.hpp>

#include <Eigen/Core>

#include <limits>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace shadecut {

enum class Method {
  GraphCut,     ///< "graphcut": the paper's eq. (15) energy, minimized by alpha-expansion
  GraphCutTwo,  ///< "graphcut_two": the paper's eq. (10), every pixel restricted to its two candidates
  LeeRosenfeld, ///< "lee_rosenfeld": the local method under the convex assumption (no global step)
  BrooksHorn,   ///< "brooks_horn": Brooks & Horn's variational iteration (brooks_horn.hpp), normals integrated
  TsaiShah,     ///< "tsai_shah": Tsai & Shah's linearized depth iteration (tsai_shah.hpp), normals from its depth
  Upwind,       ///< "upwind": the viscosity solution by upwind fast sweeping (upwind.hpp), normals from its depth
};

/// What the image shows, which fixes what shading alone cannot.
enum class SceneKind {
  Object,  ///< "object": an object seen whole against a background; the mask's edge is its outline
  Relief,  ///< "relief": a surface that fills the frame and on average faces the viewer (relief.hpp):
           ///< the albedo is mean intensity / S_z and the depth sits on a flat carrier, no ramp
};

const std::vector<std::string>& scene_kind_names();
SceneKind parse_scene_kind(const std::string& name);
std::string to_string(SceneKind kind);

/// Every method's name, in the order of the enum.
const std::vector<std::string>& method_names();

/// Parses one of method_names(); throws InvalidArgument otherwise.
Method parse_method(const std::string& name);
std::string to_string(Method method);

/// Per-method defaults chosen by scripts/tune_parameters.py on training surfaces (docs/parameters.md):
/// what reconstruct() uses for an option left unset. A field a method does not use is 0.
struct MethodDefaults {
  double min_curvature = 0.0;     ///< graph-cut methods, lee_rosenfeld (ReconstructOptions::min_curvature)
  double undefined_weight = 0.0;  ///< graph-cut methods (ReconstructOptions::undefined_weight)
  double tolerance = 0.0;         ///< graph-cut methods: share of the energy; brooks_horn: mean |dn| per sweep
  int iterations = 0;             ///< brooks_horn, tsai_shah sweeps; upwind: most rounds of sweeps
  double smoothness = 0.0;        ///< brooks_horn (ReconstructOptions::smoothness)
};
MethodDefaults method_defaults(Method method);

/// highlight_threshold when unset with one albedo (top_fit, brightest): never.
constexpr double kHighlightThreshold = 0.0;
/// highlight_threshold when unset with albedo_method retinex: the shading image keeps the highlights
/// the paint step does not read, and every pixel above its albedo is one of them.
constexpr double kRetinexHighlightThreshold = 1.0;

/// The fewest tilt labels the energy can be built with.
constexpr int kMinLabels = 4;
/// The most threads a call may ask for: more than the machine has only costs memory.
constexpr int kMaxThreads = 256;

/// Every setting of reconstruct(), with its default: the one place defaults are held. The Python
/// binding, the command-line tool and the Blender add-on read them from here. Per-object weights
/// are scaled to the object's size by unary_scale (local_shape.hpp).
struct ReconstructOptions {
  SceneKind scene = SceneKind::Object;
  /// scene = Object with no mask given: cut the object out of a plain background (cut_out.hpp, its
  /// default CutOutOptions) and reconstruct it alone when one is found (CutOutOutcome::Found);
  /// otherwise, and when off, every pixel. ReconstructStats::cut_out says what happened.
  bool cut_out = true;
  Method method = Method::GraphCut;
  int labels = 36;                          ///< K tilt labels
  /// lambda of eq. (15) for an object of kReferenceObjectSize pixels, tuned (graphcut only).
  double data_weight = 0.2;
  std::optional<double> undefined_weight;   ///< TiltEnergyParams::undefined_weight at kReferenceObjectSize (unary_scale); unset = method_defaults
  Integrator integrator = Integrator::Poisson;
  int max_cycles = 20;                      ///< alpha-expansion stops earlier when a cycle gains nothing
  /// graphcut, graphcut_two: coarse to fine (GlobalStepParams::band): each pixel keeps the labels
  /// within this many steps of its label at half resolution; < 0 = one level, every label.
  int coarse_to_fine_band = 1;
  /// graphcut, graphcut_two: with a band, only pixels within this many pixels of a jump of the
  /// half-resolution labelling keep it (GlobalStepParams::band_radius; 0 = the pixels of the jump
  /// only); the others keep their coarse label; < 0 = the band everywhere. Chosen by
  /// scripts/tune_parameters.py --band-radius: the smallest radius within 0.1 deg of the band
  /// everywhere on the training surfaces.
  int coarse_to_fine_radius = 0;
  std::optional<double> tolerance;          ///< convergence tolerance (MethodDefaults::tolerance); unset = method_defaults
  std::optional<int> iterations;            ///< brooks_horn, tsai_shah sweeps, upwind rounds; unset = method_defaults
  /// brooks_horn lambda for an object of kReferenceObjectSize pixels (the per-pixel weight is this
  /// times (object_size / kReferenceObjectSize)^2, at least kStableSmoothness); unset = method_defaults
  std::optional<double> smoothness;
  /// the estimator used when no light is given; unset = by scene (light_method_used)
  std::optional<LightMethod> light_method;
  /// How the albedo is read when none is given: one value (top_fit, brightest) with a light given, or
  /// per pixel (retinex: the paint separated from the shading first, estimate_reflectance.hpp).
  AlbedoMethod albedo_method = AlbedoMethod::TopFit;
  /// retinex: ReflectanceParams' chroma_edge, intensity_edge (<= 0 off), rim (objects), highlight
  /// (<= 0 none) and shadow, tuned (docs/parameters.md).
  double retinex_chroma_edge = 0.02;
  double retinex_intensity_edge = 0.2;
  int retinex_rim = 0;
  double retinex_highlight = 0.0;
  double retinex_shadow = 0.05;
  /// retinex: how many times the paint is read (>= 1). Each pass after the first reads the shading's
  /// step across every paint edge from the surface the pass before found (its depth's normals under
  /// the light), not from the image steps beside the edge: a surface is continuous where paint is not.
  int retinex_passes = 2;
  /// Pixels brighter than this times the albedo, which no Lambertian surface of that albedo shows
  /// (highlights, saturation), are filled from their neighbours like attached shadows; <= 0 = never.
  /// Unset = by albedo method (highlight_threshold_used), both tuned (docs/parameters.md).
  std::optional<double> highlight_threshold;
  std::optional<double> min_curvature;      ///< curvature in units of the object below which the local tilt is undefined (local_shape); unset = method_defaults
  bool refine = true;                       ///< snap labels to the exact local candidate (labelling_normals)
  double max_slope = 10.0;                  ///< gradient clamp of the integrator
  bool fill_shadows = true;                 ///< interpolate normals in attached shadows (fill_normals)
  double shadow_threshold = 1e-3;           ///< relative intensity at or below which a pixel is in shadow
  bool occluding_contour = true;            ///< treat the mask's edge as an occluding contour when filling (objects)
  /// graphcut, graphcut_two, objects with occluding_contour: TiltEnergyParams::contour_weight, the
  /// pull of the outline's pixels toward normals pointing outward. Tuned (docs/parameters.md).
  double contour_weight = 10.0;
  /// graphcut: > 0 also labels the image, at the coarsest level of coarse to fine, with the energy
  /// pulled toward the normals of its viscosity solution (upwind.hpp; GlobalStepParams::viscosity_weight,
  /// this weight), integrates both labellings and keeps the one whose depth renders closer to the
  /// image (brightness_residual over the mask without shadows and highlights). When that is the
  /// pulled one, both are refined up to a level of at most 256 pixels across (the whole image when
  /// smaller) and the choice made again there; the finer levels refine the one kept. 0 = the
  /// paper's energy alone. Tuned (docs/parameters.md).
  double viscosity_weight = 0.3;
  /// graphcut: after integration, fit the depth to the image (fit_shading.hpp): the
  /// normals are then the depth's, integrable, and render closer to the image. Not with seamless.
  /// Off by default: it wins on the training surfaces (5.98 -> 2.99 deg, docs/parameters.md) for about
  /// 0.3 s at 256 px and 0.6 s at a megapixel, but loses on painted objects, reliefs and the
  /// real-photograph tests (docs/parameters.md, "Fitting the depth to the image").
  bool fit_shading = false;
  /// FitShadingParams::smoothness, tuned (docs/parameters.md).
  double fit_smoothness = 0.05;
  /// Reliefs over the whole image: depth and normals that tile, the image's opposite edges meeting
  /// (integrate_periodic, normals_from_periodic_depth), for seamless textures. Needs scene = Relief
  /// and no mask, or one that covers every pixel; the integrator setting is then not used.
  bool seamless = false;
  /// Reliefs: forms larger than this many pixels are carrier, not detail, and are damped out of the
  /// depth (damp_large_forms: half their height gone at this wavelength, nearly all at twice it);
  /// 0 = detail_scale_factor times the relief's own scale (relief_scale, read from the image);
  /// < 0 = keep every form (the least-squares plane alone is removed).
  double detail_size = 0.0;
  /// Reliefs with detail_size 0: the detail size in units of relief_scale. Tuned
  /// (scripts/tune_parameters.py --detail-size, docs/parameters.md).
  double detail_scale_factor = 1.5;
  /// Reliefs: thin bright lines (bright_lines: narrower than this many pixels, brighter than both
  /// their sides by paint_line_contrast) are paint, such as mortar, not slopes: filled from their
  /// neighbours: read as shadows by every stage. < 2 = off. Tuned (scripts/tune_parameters.py --detail-size).
  int paint_line_width = 9;
  double paint_line_contrast = 2.0;
  int threads = 0;                          ///< 0 = all cores
  /// Told the fraction of the call done and the stage: "light" (estimating it), "local", "energy",
  /// "graphcut", "brooks_horn", "tsai_shah", "upwind", "integration", "fit_shading". Returning false cancels.
  ProgressCallback progress;
};

/// The highlight threshold a call uses: options.highlight_threshold, or when unset
/// kRetinexHighlightThreshold with albedo_method retinex and kHighlightThreshold otherwise.
double highlight_threshold_used(const ReconstructOptions& options);

struct ReconstructStats {
  std::map<std::string, double> seconds;    ///< per stage run ("light", "local", "energy", "graphcut",
                                            ///< "brooks_horn", "tsai_shah", "upwind", "integration", "fit_shading", "orientation": the
                                            ///< inverted surface judged, judge_orientation) and "total"; with retinex
                                            ///< summed over its passes, beside "albedo" (the paint)
  std::vector<double> energy_per_cycle;     ///< initial energy, then after every alpha-expansion cycle
  int cycles = 0;
  int iterations = 0;                       ///< alpha-expansion cycles, brooks_horn or tsai_shah sweeps, upwind rounds; 0 for lee_rosenfeld
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
  Eigen::Vector3d light;   ///< unit light direction used, camera frame
  ReconstructStats stats;
};


/// The light estimator reconstruct() uses when given no light: options.light_method, or for the
/// scene kind: zheng_chellappa for an object, relief for a relief (whose normals are nothing like
/// the sphere's the others assume).
LightMethod light_method_used(const ReconstructOptions& options);

/// A result is ambiguous in its orientation (ReconstructStats::orientation_ambiguous) when its
/// inversion renders less than this many times as far from the image (mean squared residual) as the
/// result: under a frontal light both render alike (ratio 1); a 128-px sphere lit from 2, 5 and 10
/// degrees off the viewer gives 1.4, 5.0 and 21 (docs/method.md, "10. Orientation").
constexpr double kAmbiguousResidualRatio = 2.0;

/// What reconstruct() hands global_step for the graph-cut methods (graphcut, graphcut_two): the
/// options' values, method_defaults where they are unset, and the thread count of the reconstruct()
/// in progress (every core outside one).
GlobalStepParams global_step_params(const ReconstructOptions& options);

/// What reconstruct() hands fit_shading when options.fit_shading is on: options.fit_smoothness.
FitShadingParams fit_shading_params(const ReconstructOptions& options);

/// What reconstruct() hands estimate_reflectance with albedo_method retinex: the options' retinex_*
/// values (the rim for objects only).
ReflectanceParams reflectance_params(const ReconstructOptions& options);

/// Rec. 709 luminance of a colour image (kLuminanceWeights): the intensity the shape is read from.
ImageF luminance(const ColourImage& colour);

/// Reconstructs normals and depth from one Lambertian image.
///
/// @param[in] image   H x W linear intensity (>= 2 x 2, finite).
/// @param[in] light   direction toward the light, camera frame, S_z > 0 (normalized here), or
///                    std::nullopt to estimate it with light_method_used(options) (estimate_light.hpp).
/// @param[in] mask    H x W pixels to reconstruct, or nullptr for all.
/// @param[in] albedo  > 0, or std::nullopt: the light estimator's albedo when the light is estimated,
///                    estimate_albedo with options.albedo_method otherwise.
/// @param[in] options method and parameters.
/// Throws InvalidArgument for bad input and Cancelled when options.progress returns false.
Reconstruction reconstruct(const ImageF& image, const std::optional<Eigen::Vector3d>& light, const Mask* mask,
                           std::optional<double> albedo, const ReconstructOptions& options);

/// The same for a colour image (H x W x 3 linear RGB under one white light): the shape from its
/// luminance; with retinex the chromaticity tells paint from shading, and albedo_colour is filled.
Reconstruction reconstruct(const ColourImage& image, const std::optional<Eigen::Vector3d>& light, const Mask* mask,
                           std::optional<double> albedo, const ReconstructOptions& options);

}  // namespace shadecut
