// The global energy over discretized tilt labels of Chang, Lee & Lee (2008), eqs. (10), (15), (20).
#pragma once

#include <shadecut/support/light.hpp>
#include <shadecut/local/local_shape.hpp>
#include <shadecut/support/types.hpp>

#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

namespace shadecut {

/// Which data term R_p the energy uses.
enum class DataTerm {
  /// Eq. (15): R_p is 0 at the two local candidates t and t + pi and grows with the angular distance
  /// to the nearer one: R_p(theta) = data_weight * |n(s_p, theta) - n(s_p, nearer candidate)|
  /// = data_weight * 2 sin(s_p) sin(d / 2), d the tilt distance.
  Soft,
  /// Eq. (10): only the labels nearest t and t + pi are allowed (cost 0), every other is prohibited.
  TwoCandidates,
};

namespace detail {
class LabelCostModel;
}

/// The largest number of tilt labels; one degree per label is finer than any image supports.
constexpr int kMaxLabels = 360;

/// The slant (radians, 20 degrees) of the weakest light under which an outline is read as a rim.
/// An outline's rim vote is the mean, over its pixels, of brightness / albedo times outward . S_xy:
/// a silhouette's (horizontal normals pointing out) is +sin^2(slant) / 4, a rim's (pointing in)
/// -sin^2(slant) / 4, and an object whose edge is not everywhere an occluding contour adds a vote of
/// its own that grows like sin(slant) (a bust cut off at its base). Under a light near the viewer
/// the image cannot tell a surface from its inversion, so the outline must not turn on a vote that
/// small: it reads as a rim only where the vote is below a rim's under this slant,
/// -sin^2(20 deg) / 4 = -0.029. Then the choice does not change as the light nears the viewer: a
/// bowl lit from 20 degrees or more keeps its rim; under lights nearer the viewer it is read as a
/// dome, the outline's choice, and ReconstructStats::orientation_ambiguous says the image could not
/// tell (docs/method.md, "Occluding contour").
constexpr double kRimSlant = 20.0 * M_PI / 180.0;

/// The tuned values come from ReconstructOptions (global_step_params, reconstruct.hpp): the weights
/// and the label count hold none of their own here.
struct TiltEnergyParams {
  int labels{};                ///< K; label k is the tilt 2 pi k / K in the light frame. K >= 4.
  double data_weight{};        ///< lambda of the soft data term (unused by TwoCandidates)
  /// Where the tilt is undefined R_p is nearly flat, so the neighbours decide; a pull of this weight
  /// toward tilt pi (the normal turned from the light toward the viewer, the local method's own choice
  /// there) settles what the neighbours leave open: R_p(theta) = w 2 sin(s_p) sin(|theta - pi| / 2).
  double undefined_weight{};
  /// On the mask's edge, where it is the object's outline (an occluding contour: the surface turns
  /// away there, its normal pointing outward), label theta costs contour_weight (1 - cos d) / 2 more,
  /// d the angle between the outward direction of the edge and the image-plane direction of the
  /// label's normal: an object seen whole is convex at its outline. On every part of the mask
  /// except those whose edge reads as a rim (kRimSlant: a bowl's rim lit from aside, brighter where
  /// it faces away from the light, gets no term); under a light near the viewer the edge reads as
  /// nothing and the term holds: the outline decides what the image cannot. 0 = no such term (reliefs).
  double contour_weight{};
  /// A pull toward given normals (one per pixel of the mask's grid, row-major; the viscosity
  /// solution's, GlobalStepParams::viscosity_weight): label theta costs reference_weight
  /// |n(s_p, theta) - m_p| more, a chord like the soft data term's. Null or 0 = none.
  const NormalMap* reference = nullptr;
  double reference_weight = 0.0;
  DataTerm data_term = DataTerm::Soft;
  /// Dead-end elimination (see TiltEnergy). Off, every label that faces the viewer (and, for
  /// TwoCandidates, is a candidate) keeps its cost: for judging labellings a minimum would not use.
  bool prune = true;
  int threads = 0;             ///< threads for building the tables; 0 = all cores
  /// Coarse to fine: with band >= 0, a masked pixel p with (*band_centre)[p] >= 0 (a label, one per
  /// pixel, row-major) keeps only the labels within `band` label steps of it (circularly), unless none
  /// of them is allowed there: then it keeps them all. Null or band < 0: every label.
  const std::vector<int>* band_centre = nullptr;
  int band = -1;
  /// With a band: pixels where band_frozen[p] != 0 keep only their centre label (a band of 0), or
  /// the band when the centre is not allowed there. Null: the band everywhere.
  const std::vector<std::uint8_t>* band_frozen = nullptr;
  /// With a band: per pixel (row-major; null = 0 everywhere), how many label steps the window reaches
  /// beyond the band above its centre: the labels from centre - band to centre + band_span[p] + band.
  /// Coarse to fine widens the pixels at a jump of the coarse labelling this way to their neighbours'
  /// labels (global_step).
  const std::vector<std::int16_t>* band_span = nullptr;
};

/// E(labels) = sum_p R_p(theta_p) + sum over 4-neighbours (p, q) of
///   V_pq = |n(s_min, theta_p) - n(s_min, theta_q)| = 2 sin(s_min) |sin((theta_p - theta_q) / 2)|,
/// s_min = min(s_p, s_q) (eq. 20, a metric). Labels whose normal faces away from the viewer (n_z <= 0)
/// are prohibited (infinite cost), and so are labels that cannot be part of any minimum: label a is
/// dropped at p when another label b has R_p(a) - R_p(b) > sum_q w_pq |n(a) - n(b)|, since then
/// switching p from a to b lowers the energy whatever its neighbours are (dead-end elimination).
class TiltEnergy {
 public:
  TiltEnergy(const LocalShape& local, const LightFrame& light, const Mask& mask, const TiltEnergyParams& params);

  int rows() const { return rows_; }
  int cols() const { return cols_; }
  int labels() const { return labels_; }
  const Mask& mask() const { return mask_; }

  /// Tilt of label k, radians, light frame.
  double label_tilt(int k) const;

  /// The label whose tilt is nearest `tilt` (radians, any value).
  int nearest_label(double tilt) const;

  /// Where the pair (pixel, label k) is stored: per-(pixel, label) data of any size-slot_count()
  /// array goes at this index. Without a band every pixel keeps all K labels, in one plane per label;
  /// with a band every masked pixel keeps a circular window of consecutive labels (its band, or all K).
  /// -1 when k lies outside the pixel's window (k is then prohibited there; a label inside it may be
  /// prohibited too).
  std::int64_t slot(int pixel, int k) const {
    if (planes_) return std::int64_t(k) * (rows_ * cols_) + pixel;
    const std::int64_t begin = window_begin_[std::size_t(pixel)];
    int steps = k - window_first_[std::size_t(pixel)];
    if (steps < 0) steps += labels_;
    return steps < window_begin_[std::size_t(pixel) + 1] - begin ? begin + steps : -1;
  }
  /// Number of labels in the pixel's window (K without a band); some of them may be prohibited.
  int window_width(int pixel) const {
    return planes_ ? labels_ : int(window_begin_[std::size_t(pixel) + 1] - window_begin_[std::size_t(pixel)]);
  }
  /// Number of slots.
  std::int64_t slot_count() const { return std::int64_t(data_cost_.size()); }

  /// R_p(k); +infinity where label k is prohibited at pixel p (p inside the mask).
  float data_cost(int pixel, int k) const {
    const std::int64_t s = slot(pixel, k);
    return s < 0 ? std::numeric_limits<float>::infinity() : data_cost_[std::size_t(s)];
  }
  bool allowed(int pixel, int k) const { return std::isfinite(data_cost(pixel, k)); }

  /// w_pq = sin(min(s_p, s_q)) of the edge from p to its right / lower neighbour; 0 when either pixel
  /// is outside the mask or the neighbour is outside the image.
  float weight_right(int pixel) const { return weight_right_[pixel]; }
  float weight_down(int pixel) const { return weight_down_[pixel]; }

  /// 2 |sin((theta_a - theta_b) / 2)|.
  float label_distance(int a, int b) const { return chord_[std::size_t((a - b + labels_) % labels_)]; }

  /// Total energy of a labelling (one label per pixel; pixels outside the mask are ignored).
  double energy(const std::vector<int>& labelling) const;

  /// The Lee-Rosenfeld convex labelling: each pixel takes the allowed label nearest t + pi (pi where
  /// the tilt is undefined).
  std::vector<int> convex_labelling() const;
  /// The convex labelling's label at one masked pixel.
  int convex_label(int pixel) const;

  /// The allowed label at `pixel` nearest the tilt `tilt` (radians), -1 if none.
  int nearest_allowed_label(int pixel, double tilt) const;

  /// Number of (pixel, label) pairs still allowed, summed over the mask.
  std::int64_t allowed_count() const;

 private:
  // The constructor's steps: w_pq and the chords, the band's windows, R_p after dead-end elimination.
  void build_pairwise_terms(const LocalShape& local, int threads);
  void build_windows(const detail::LabelCostModel& model, const TiltEnergyParams& params, int threads);
  void build_data_costs(const detail::LabelCostModel& model, bool prune, int threads);
  void eliminate_dead_ends(int pixel, int first, int width, float* cost) const;

  int rows_ = 0, cols_ = 0, labels_ = 0;
  Mask mask_;
  // Without a band, label-major planes: an expansion move reads one of them in order (its reads
  // strided by K per pixel slowed the exact alpha-expansion). With a band, pixel p's window
  // holds the labels window_first_[p], window_first_[p] + 1, ... (mod K), at the slots
  // window_begin_[p] up to window_begin_[p + 1]; a band of 3 labels needs a twelfth of the memory of
  // all 36, which at 512 x 512 saves more time (in page faults) than building the costs takes.
  bool planes_ = true;
  std::vector<std::int64_t> window_begin_;
  std::vector<std::int16_t> window_first_;
  std::vector<float> data_cost_;  // per slot
  std::vector<float> weight_right_, weight_down_;
  std::vector<float> chord_;
  std::vector<float> convex_tilt_;  // t + pi per pixel, NaN where undefined
};

/// Camera-frame normals of a labelling. With `refine`, a pixel whose label lies within one label step
/// of a local candidate takes that candidate's exact tilt (the labels decide convex or concave, the
/// local step keeps its sub-label precision); otherwise, and without `refine`, the label's tilt.
///
/// `label_tilts` (with `refine`; null = none): one light-frame tilt per pixel (radians, row-major,
/// NaN = none) that stands for the label in place of its own tilt, both in the snapping and where
/// nothing snaps: coarse to fine gives the pixels that keep their coarse label the coarse level's
/// tilts interpolated smoothly (global_step), so that its blocks leave no steps in the normals.
NormalMap labelling_normals(const std::vector<int>& labelling, const TiltEnergy& energy, const LocalShape& local,
                            const LightFrame& light, bool refine, const std::vector<float>* label_tilts = nullptr);

}  // namespace shadecut
