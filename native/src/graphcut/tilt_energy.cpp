#include <shadecut/graphcut/tilt_energy.hpp>

#include <shadecut/support/errors.hpp>
#include <shadecut/support/mask_components.hpp>

#include "support/contour.hpp"
#include "support/parallel.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>

namespace shadecut {

namespace {

constexpr float kProhibited = std::numeric_limits<float>::infinity();
// Normals this close to the image plane are treated as facing away from the viewer.
constexpr double kMinFrontFacing = 1e-6;
// Slack of the dead-end test, so that float rounding never drops a label that could tie.
constexpr float kDominanceSlack = 1e-5f;

// Which connected parts of the mask are outlined by a silhouette (the surface turning away, normals
// pointing out) rather than a rim (a bowl's edge, normals pointing in). At a silhouette the lit side
// of the outline is the one facing the light, at a rim the one facing away: the brightness cos(s_p)
// of the edge pixels, correlated with outward . S_xy, says which, once the light is far enough from
// the viewer for that correlation to be the light's (kRimSlant). Empty when the term is off.
struct Outline {
  MaskComponents components;
  std::vector<char> silhouette;  // per component
};

Outline read_outline(const LocalShape& local, const LightFrame& light, const Mask& mask, double contour_weight) {
  Outline outline;
  if (!(contour_weight > 0.0)) return outline;
  outline.components = mask_components(mask);
  std::vector<double> vote(std::size_t(outline.components.count), 0.0), edge(vote.size(), 0.0);
  const Eigen::Vector2d light_across = light.direction.head<2>();
  for (int r = 0; r < mask.rows(); ++r) {
    for (int c = 0; c < mask.cols(); ++c) {
      if (!mask(r, c)) continue;
      const Eigen::Vector2d outward = detail::contour_outward(mask, r, c);
      if (outward.isZero()) continue;
      const double brightness = std::cos(double(local.slant(r, c)));
      const std::size_t component = std::size_t(outline.components.labels(r, c));
      vote[component] += brightness * outward.dot(light_across);
      edge[component] += 1.0;
    }
  }
  const double rim_vote = -0.25 * std::pow(std::sin(kRimSlant), 2);
  for (std::size_t i = 0; i < vote.size(); ++i)
    outline.silhouette.push_back(!(edge[i] > 0.0 && vote[i] / edge[i] < rim_vote));
  return outline;
}

// Circular distance between two angles, in [0, pi].
double angle_distance(double a, double b) {
  const double d = std::fmod(std::abs(a - b), 2.0 * M_PI);
  return d > M_PI ? 2.0 * M_PI - d : d;
}

}  // namespace

double TiltEnergy::label_tilt(int k) const { return 2.0 * M_PI * k / labels_; }

int TiltEnergy::nearest_label(double tilt) const {
  const long k = std::lround(tilt / (2.0 * M_PI / labels_));
  return int(((k % labels_) + labels_) % labels_);
}

namespace detail {

// R_p(k) before dead-end elimination, for one pixel at a time: +infinity where the normal faces
// away, or where eq. (10) allows only the candidates.
class LabelCostModel {
 public:
  // What R_p needs of one pixel.
  struct PixelTerms {
    double s = 0.0, sin_s = 0.0, nz_base = 0.0, nz_step = 0.0, t = 0.0, cos_t = 1.0, sin_t = 0.0;
    bool defined = false;
    int concave_label = 0, convex_label = 0;  // the two-candidate term's
    Eigen::Vector3d reference = Eigen::Vector3d::Zero();  // zero without a reference
    Eigen::Vector2d outward = Eigen::Vector2d::Zero();    // zero off the outline
  };

  LabelCostModel(const TiltEnergy& energy, const LocalShape& local, const LightFrame& light, const Mask& mask,
                 const TiltEnergyParams& params)
      : energy_(energy), local_(local), light_(light), mask_(mask), params_(params),
        referenced_(params.reference && params.reference_weight > 0.0),
        cos_ls_(std::cos(light.slant)), sin_ls_(std::sin(light.slant)),
        outline_(read_outline(local, light, mask, params.contour_weight)) {
    const int k_count = energy.labels();
    cos_label_.resize(std::size_t(k_count));
    sin_label_.resize(std::size_t(k_count));
    undefined_chord_.resize(std::size_t(k_count));
    label_angle_.resize(std::size_t(k_count));
    for (int k = 0; k < k_count; ++k) {
      label_angle_[std::size_t(k)] = energy.label_tilt(k);
      cos_label_[std::size_t(k)] = std::cos(label_angle_[std::size_t(k)]);
      sin_label_[std::size_t(k)] = std::sin(label_angle_[std::size_t(k)]);
      // From the label's tilt to pi (the convex tilt of an undefined pixel).
      undefined_chord_[std::size_t(k)] = std::hypot(cos_label_[std::size_t(k)] + 1.0, sin_label_[std::size_t(k)]);
    }
  }

  // What R_p needs of pixel p; with `admissibility_only`, what admissible() needs (the windows ask
  // at every pixel, and the costs' terms would cost as much again).
  PixelTerms pixel_terms(int p, bool admissibility_only = false) const {
    PixelTerms terms;
    const double s = local_.slant.data()[p];
    terms.s = s;
    const int component = outline_.silhouette.empty() || admissibility_only ? -1 : outline_.components.labels.data()[p];
    if (component >= 0 && outline_.silhouette[std::size_t(component)])
      terms.outward = contour_outward(mask_, p / mask_.cols(), p % mask_.cols());
    terms.sin_s = std::sin(s);
    // z of Rz(tS) Ry(sS) n'(s, theta) = nz_base - nz_step cos(theta): the rotation about z leaves it unchanged.
    terms.nz_base = cos_ls_ * std::cos(s);
    terms.nz_step = sin_ls_ * terms.sin_s;
    terms.defined = local_.tilt_defined.data()[p];
    terms.t = local_.tilt.data()[p];
    if (terms.defined && !admissibility_only) terms.cos_t = std::cos(terms.t), terms.sin_t = std::sin(terms.t);
    // The candidates matter to the two-candidate term alone.
    if (terms.defined && params_.data_term == DataTerm::TwoCandidates) {
      terms.concave_label = energy_.nearest_label(terms.t);
      terms.convex_label = energy_.nearest_label(terms.t + M_PI);
    }
    if (referenced_ && !admissibility_only) terms.reference = params_.reference->xyz.row(p).transpose().cast<double>();
    return terms;
  }

  double label_nz(const PixelTerms& terms, int k) const { return terms.nz_base - terms.nz_step * cos_label_[std::size_t(k)]; }

  float label_cost(const PixelTerms& terms, int k) const {
    if (!admissible(terms, k)) return kProhibited;
    return float(with_normal_terms(terms, k, data_cost_of(terms, k)));
  }

  // Whether label_cost(terms, k) is finite: the label's normal faces the viewer and, with the
  // two-candidate term, the label is a candidate (an undefined pixel takes any).
  bool admissible(const PixelTerms& terms, int k) const {
    if (label_nz(terms, k) <= kMinFrontFacing) return false;
    return !terms.defined || params_.data_term == DataTerm::Soft || k == terms.concave_label || k == terms.convex_label;
  }

 private:
  // `cost` plus the terms that look at the label's whole normal n, which is computed once for both:
  // the occluding contour's (TiltEnergyParams::contour_weight, 0 off the outline) and the reference's.
  double with_normal_terms(const PixelTerms& terms, int k, double cost) const {
    const bool on_outline = !terms.outward.isZero();
    if (!on_outline && !referenced_) return cost;
    const Eigen::Vector3d n = light_.normal(terms.s, label_angle_[std::size_t(k)]);
    if (on_outline) {
      const double across = n.head<2>().norm();
      const double cos_d = across > 1e-9 ? n.head<2>().dot(terms.outward) / across : 0.0;
      cost += params_.contour_weight * 0.5 * (1.0 - cos_d);
    }
    if (referenced_) cost += params_.reference_weight * (n - terms.reference).norm();
    return cost;
  }

  // Eq. (15)'s R_p: 2 sin(d / 2) for an angle d between tilts is the chord between their unit vectors,
  // which the label's cosine and sine give without an angle's sine (and its fmods) per label.
  double data_cost_of(const PixelTerms& terms, int k) const {
    if (!terms.defined) return params_.undefined_weight * terms.sin_s * undefined_chord_[std::size_t(k)];
    if (params_.data_term == DataTerm::Soft) {
      // d runs to the nearer end of the tilt axis: t or t + pi.
      const double c = cos_label_[std::size_t(k)], s = sin_label_[std::size_t(k)];
      const double end = c * terms.cos_t + s * terms.sin_t >= 0.0 ? 1.0 : -1.0;
      const double dx = c - end * terms.cos_t, dy = s - end * terms.sin_t;
      return params_.data_weight * terms.sin_s * std::sqrt(dx * dx + dy * dy);
    }
    return k == terms.concave_label || k == terms.convex_label ? 0.0 : double(kProhibited);
  }

  const TiltEnergy& energy_;
  const LocalShape& local_;
  const LightFrame& light_;
  const Mask& mask_;
  const TiltEnergyParams& params_;
  const bool referenced_;
  const double cos_ls_, sin_ls_;
  const Outline outline_;
  std::vector<double> cos_label_, sin_label_, undefined_chord_, label_angle_;
};

}  // namespace detail

namespace {

void check_params(const TiltEnergyParams& params, int rows, int cols) {
  if (params.labels < 4 || params.labels > kMaxLabels)
    throw InvalidArgument("shadecut: labels must be between 4 and " + std::to_string(kMaxLabels) + " (got " + std::to_string(params.labels) + ")");
  if (!(params.data_weight >= 0.0) || !std::isfinite(params.data_weight))
    throw InvalidArgument("shadecut: data_weight must be finite and >= 0");
  if (!(params.undefined_weight >= 0.0) || !std::isfinite(params.undefined_weight))
    throw InvalidArgument("shadecut: undefined_weight must be finite and >= 0");
  if (!(params.contour_weight >= 0.0) || !std::isfinite(params.contour_weight))
    throw InvalidArgument("shadecut: contour_weight must be finite and >= 0");
  if (!(params.reference_weight >= 0.0) || !std::isfinite(params.reference_weight))
    throw InvalidArgument("shadecut: the weight of the reference normals must be finite and >= 0");
  const bool referenced = params.reference && params.reference_weight > 0.0;
  if (referenced && (params.reference->rows != rows || params.reference->cols != cols))
    throw InvalidArgument("shadecut: the reference normals are not the mask's shape");
}

}  // namespace

TiltEnergy::TiltEnergy(const LocalShape& local, const LightFrame& light, const Mask& mask,
                       const TiltEnergyParams& params)
    : rows_(int(mask.rows())), cols_(int(mask.cols())), labels_(params.labels), mask_(mask) {
  check_params(params, rows_, cols_);
  const int threads = params.threads > 0 ? params.threads : detail::default_thread_count();
  build_pairwise_terms(local, threads);
  const detail::LabelCostModel model(*this, local, light, mask, params);
  build_windows(model, params, threads);
  build_data_costs(model, params.prune, threads);
}

void TiltEnergy::build_pairwise_terms(const LocalShape& local, int threads) {
  const int n = rows_ * cols_, k_count = labels_;
  chord_.resize(std::size_t(k_count));
  for (int d = 0; d < k_count; ++d) chord_[std::size_t(d)] = float(2.0 * std::abs(std::sin(M_PI * d / k_count)));

  weight_right_.assign(std::size_t(n), 0.0f);
  weight_down_.assign(std::size_t(n), 0.0f);
  detail::parallel_for(rows_, 16, threads, [&](int r) {
    for (int c = 0; c < cols_; ++c) {
      if (!mask_(r, c)) continue;
      const int p = r * cols_ + c;
      if (c + 1 < cols_ && mask_(r, c + 1))
        weight_right_[std::size_t(p)] = std::sin(std::min(local.slant(r, c), local.slant(r, c + 1)));
      if (r + 1 < rows_ && mask_(r + 1, c))
        weight_down_[std::size_t(p)] = std::sin(std::min(local.slant(r, c), local.slant(r + 1, c)));
    }
  });
}

// The windows: a pixel with a band centre keeps the band (or only its centre, when frozen), unless
// no label in it is allowed; then it tries the band, and then, like every other masked pixel, keeps
// all labels.
void TiltEnergy::build_windows(const detail::LabelCostModel& model, const TiltEnergyParams& params, int threads) {
  const int n = rows_ * cols_, k_count = labels_;
  const bool banded = params.band >= 0 && params.band_centre;
  planes_ = !banded || (2 * params.band + 1 >= k_count && !params.band_frozen);
  if (planes_) return;
  window_first_.assign(std::size_t(n), 0);
  window_begin_.assign(std::size_t(n) + 1, 0);
  detail::parallel_for(n, 256, threads, [&](int p) {
    if (!mask_.data()[p]) return;
    int width = k_count;
    const int centre = (*params.band_centre)[std::size_t(p)];
    if (centre >= 0) {
      const detail::LabelCostModel::PixelTerms terms = model.pixel_terms(p, true);
      const bool frozen = params.band_frozen && (*params.band_frozen)[std::size_t(p)];
      const int span = params.band_span ? (*params.band_span)[std::size_t(p)] : 0;
      for (int half = frozen ? 0 : params.band; half <= params.band && width == k_count; half += std::max(1, params.band)) {
        const int first = (centre - half + k_count) % k_count;
        const int band_width = std::min(2 * half + 1 + span, k_count);
        for (int j = 0; j < band_width && width == k_count; ++j)
          if (model.admissible(terms, (first + j) % k_count)) width = band_width, window_first_[std::size_t(p)] = std::int16_t(first);
      }
    }
    window_begin_[std::size_t(p) + 1] = width;
  });
  for (int p = 0; p < n; ++p) window_begin_[std::size_t(p) + 1] += window_begin_[std::size_t(p)];
}

void TiltEnergy::build_data_costs(const detail::LabelCostModel& model, bool prune, int threads) {
  const int n = rows_ * cols_, k_count = labels_;
  convex_tilt_.assign(std::size_t(n), std::numeric_limits<float>::quiet_NaN());
  data_cost_.assign(planes_ ? std::size_t(n) * k_count : std::size_t(window_begin_.back()), kProhibited);
  detail::parallel_for(n, 256, threads, [&](int p) {
    if (!mask_.data()[p]) return;
    const detail::LabelCostModel::PixelTerms terms = model.pixel_terms(p);
    if (terms.defined) convex_tilt_[std::size_t(p)] = float(terms.t + M_PI);
    const int first = planes_ ? 0 : window_first_[std::size_t(p)];
    const int width = window_width(p);
    std::array<float, kMaxLabels> cost_buffer;
    float* cost = cost_buffer.data();
    auto label_at = [&](int j) { return (first + j) % k_count; };
    int most_frontal = 0;
    for (int j = 0; j < width; ++j) {
      cost[j] = model.label_cost(terms, label_at(j));
      if (model.label_nz(terms, label_at(j)) > model.label_nz(terms, label_at(most_frontal))) most_frontal = j;
    }
    // Eq. (10) can leave no label when both candidates face away after discretization.
    if (std::none_of(cost, cost + width, [](float v) { return std::isfinite(v); })) cost[most_frontal] = 0.0f;
    if (prune) eliminate_dead_ends(p, first, width, cost);
    for (int j = 0; j < width; ++j) data_cost_[std::size_t(slot(p, label_at(j)))] = cost[j];
  });
}

// Dead-end elimination at pixel p (its window's costs, `width` labels from `first`) against the
// cheapest label and the cheapest one of the other convexity.
void TiltEnergy::eliminate_dead_ends(int p, int first, int width, float* cost) const {
  auto label_at = [&](int j) { return (first + j) % labels_; };
  int best = -1;
  for (int j = 0; j < width; ++j)
    if (std::isfinite(cost[j]) && (best < 0 || cost[j] < cost[best])) best = j;
  int rival = -1;
  for (int j = 0; j < width; ++j)
    if (std::isfinite(cost[j]) && label_distance(label_at(j), label_at(best)) > float(M_SQRT2) &&
        (rival < 0 || cost[j] < cost[rival]))
      rival = j;
  const int r = p / cols_, c = p % cols_;
  const float neighbour_weight = weight_right_[std::size_t(p)] + weight_down_[std::size_t(p)] +
                                 (c > 0 ? weight_right_[std::size_t(p - 1)] : 0.0f) +
                                 (r > 0 ? weight_down_[std::size_t(p - cols_)] : 0.0f);
  for (int j = 0; j < width; ++j) {
    if (!std::isfinite(cost[j]) || j == best || j == rival) continue;
    for (int b : {best, rival}) {
      if (b >= 0 && cost[j] - cost[b] > neighbour_weight * label_distance(label_at(j), label_at(b)) + kDominanceSlack) {
        cost[j] = kProhibited;
        break;
      }
    }
  }
}

double TiltEnergy::energy(const std::vector<int>& labelling) const {
  double total = 0.0;
  for (int p = 0; p < rows_ * cols_; ++p) {
    if (!mask_.data()[p]) continue;
    const int lp = labelling[std::size_t(p)];
    total += data_cost(p, lp);
    if (weight_right_[std::size_t(p)] > 0.0f)
      total += double(weight_right_[std::size_t(p)]) * label_distance(lp, labelling[std::size_t(p + 1)]);
    if (weight_down_[std::size_t(p)] > 0.0f)
      total += double(weight_down_[std::size_t(p)]) * label_distance(lp, labelling[std::size_t(p + cols_)]);
  }
  return total;
}

std::vector<int> TiltEnergy::convex_labelling() const {
  std::vector<int> labelling(std::size_t(rows_) * cols_, 0);
  for (int p = 0; p < rows_ * cols_; ++p)
    if (mask_.data()[p]) labelling[std::size_t(p)] = convex_label(p);
  return labelling;
}

int TiltEnergy::convex_label(int pixel) const {
  const float convex = convex_tilt_[std::size_t(pixel)];
  return nearest_allowed_label(pixel, std::isnan(convex) ? M_PI : double(convex));
}

int TiltEnergy::nearest_allowed_label(int pixel, double tilt) const {
  // Labels in order of their distance to the tilt: the nearest, then alternately one step further
  // on the tilt's side of it and on the other.
  const double position = tilt / (2.0 * M_PI / labels_);
  const long nearest = std::lround(position);
  const int toward = position >= double(nearest) ? 1 : -1;
  for (int step = 0; step < labels_; ++step) {
    const long offset = step == 0 ? 0 : (step % 2 ? toward : -toward) * long((step + 1) / 2);
    const int k = int((((nearest + offset) % labels_) + labels_) % labels_);
    if (allowed(pixel, k)) return k;
  }
  return -1;
}

std::int64_t TiltEnergy::allowed_count() const {
  // Slots outside the mask hold +infinity.
  return std::count_if(data_cost_.begin(), data_cost_.end(), [](float v) { return std::isfinite(v); });
}

NormalMap labelling_normals(const std::vector<int>& labelling, const TiltEnergy& energy, const LocalShape& local,
                            const LightFrame& light, bool refine, const std::vector<float>* label_tilts) {
  const Mask& mask = energy.mask();
  NormalMap normals(energy.rows(), energy.cols());
  const double step = 2.0 * M_PI / energy.labels();
  // Rows in parallel: two sines and cosines per pixel are a visible share of a megapixel call on one core.
  detail::parallel_ranges(energy.rows(), 16, 0, [&](int begin, int end) {
    for (Eigen::Index i = Eigen::Index(begin) * energy.cols(); i < Eigen::Index(end) * energy.cols(); ++i) {
      if (!mask.data()[i]) continue;
      double tilt = energy.label_tilt(labelling[std::size_t(i)]);
      if (refine && label_tilts && std::isfinite((*label_tilts)[std::size_t(i)])) tilt = (*label_tilts)[std::size_t(i)];
      if (refine && local.tilt_defined.data()[i]) {
        const double concave = local.tilt.data()[i], convex = concave + M_PI;
        const double nearer = angle_distance(tilt, concave) < angle_distance(tilt, convex) ? concave : convex;
        if (angle_distance(tilt, nearer) <= step + 1e-9) tilt = nearer;
      }
      normals.xyz.row(i) = light.normal(local.slant.data()[i], tilt).cast<float>();
    }
  });
  return normals;
}

}  // namespace shadecut
