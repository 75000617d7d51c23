#include <shadecut/graphcut/global_step.hpp>

#include <shadecut/graphcut/convexity_cut.hpp>
#include <shadecut/support/downsample.hpp>
#include <shadecut/support/render.hpp>
#include <shadecut/integrate/shadow_fill.hpp>
#include <shadecut/integrate/surface_from_normals.hpp>
#include <shadecut/baselines/upwind.hpp>

#include "support/parallel.hpp"
#include "support/stopwatch.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <string>
#include <tuple>
#include <utility>

namespace shadecut {

namespace {

// The brightest shade of the pull's viscosity solution: the image's own, unclamped below 1. Clamped
// like the upwind method's (kUpwindBrightestShade), the solution settles where the image reaches the
// albedo, and the pulled labellings read DiLiGenT worse (docs/method.md, "The viscosity pull"): the
// pull was tuned with, and relies on, the bulge the unsettled sweeps raise there.
constexpr double kPullBrightestShade = 1.0;

// Share of a level's progress range spent on the levels below it (they have a quarter of its pixels
// each, and every label open to them).
constexpr double kCoarseShare = 0.25;

// Fine-resolution centres of a coarse labelling: each fine pixel takes its block's coarse label, -1
// where the block is outside the coarse mask.
std::vector<int> upsample_labels(const std::vector<int>& coarse, const Mask& coarse_mask, int rows, int cols) {
  const int coarse_rows = int(coarse_mask.rows()), coarse_cols = int(coarse_mask.cols());
  std::vector<int> centre(std::size_t(rows) * cols, -1);
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) {
      const int cr = r / 2, cc = c / 2;
      if (cr < coarse_rows && cc < coarse_cols && coarse_mask(cr, cc))
        centre[std::size_t(r) * cols + c] = coarse[std::size_t(cr) * coarse_cols + cc];
    }
  }
  return centre;
}

// The pixels at a jump of the upsampled coarse labelling: both of a pair of 4-neighbours more than one
// label step apart, and a masked pixel next to one without a coarse label (or without one itself).
std::vector<std::uint8_t> jump_pixels(const std::vector<int>& centre, const Mask& mask, int labels) {
  const int rows = int(mask.rows()), cols = int(mask.cols());
  std::vector<std::uint8_t> at_jump(centre.size(), 0);
  auto jump = [&](std::size_t a, std::size_t b) {
    if (centre[a] < 0 || centre[b] < 0) return centre[a] != centre[b];
    const int steps = std::abs(centre[a] - centre[b]);
    return std::min(steps, labels - steps) > 1;
  };
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) {
      const std::size_t a = std::size_t(r) * cols + c;
      if (!mask.data()[a]) continue;
      if (c + 1 < cols && mask.data()[a + 1] && jump(a, a + 1)) at_jump[a] = at_jump[a + 1] = 1;
      if (r + 1 < rows && mask.data()[a + cols] && jump(a, a + cols)) at_jump[a] = at_jump[a + cols] = 1;
      if (centre[a] < 0) at_jump[a] = 1;
    }
  }
  return at_jump;
}

// The windows of the pixels at a jump (at_jump): the shortest circular run of labels holding the
// pixel's coarse label and its masked 4-neighbours', as (first label, further steps) in the form of
// TiltEnergyParams::band_centre and band_span; every other pixel keeps its centre and a span of 0.
std::pair<std::vector<int>, std::vector<std::int16_t>> jump_windows(const std::vector<int>& centre,
                                                                    const std::vector<std::uint8_t>& at_jump,
                                                                    const Mask& mask, int labels) {
  const int rows = int(mask.rows()), cols = int(mask.cols());
  std::vector<int> first = centre;
  std::vector<std::int16_t> span(centre.size(), 0);
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) {
      const std::size_t p = std::size_t(r) * cols + c;
      if (!at_jump[p] || centre[p] < 0) continue;
      std::array<int, 5> held{centre[p]};
      int count = 1;
      auto hold = [&](int rr, int cc) {
        if (rr < 0 || cc < 0 || rr >= rows || cc >= cols || !mask(rr, cc)) return;
        const int label = centre[std::size_t(rr) * cols + cc];
        if (label >= 0) held[std::size_t(count++)] = label;
      };
      hold(r - 1, c), hold(r + 1, c), hold(r, c - 1), hold(r, c + 1);
      // The run starting at each held label and reaching every other one upward; the shortest wins.
      int best_start = centre[p], best_length = labels;
      for (int i = 0; i < count; ++i) {
        int length = 0;
        for (int j = 0; j < count; ++j) length = std::max(length, (held[std::size_t(j)] - held[std::size_t(i)] + labels) % labels);
        if (length < best_length) best_start = held[std::size_t(i)], best_length = length;
      }
      first[p] = best_start;
      span[p] = std::int16_t(best_length);
    }
  }
  return {std::move(first), std::move(span)};
}

// The pixels that keep only their coarse label: those farther than `radius` (Chebyshev distance)
// from every pixel at a jump (jump_pixels). Where the coarse labels vary smoothly the fine level has
// nothing to decide that the snapping to the local candidates (labelling_normals) and the coarse
// level's interpolated tilts (upsampled_tilts) do not; where they jump, the convex/concave boundary
// is only known to a coarse pixel.
std::vector<std::uint8_t> frozen_pixels(const std::vector<std::uint8_t>& at_jump, int rows, int cols, int radius) {
  radius = std::min(radius, std::max(rows, cols));  // farther reaches nothing more
  // Dilation by a (2 radius + 1)^2 square, separably: rows, then columns. Along a line, a target
  // is covered when the last jump seen, `radius` cells ahead of it, lies within 2 radius.
  auto dilate_line = [radius](const std::uint8_t* in, std::uint8_t* out, int length, std::size_t stride,
                              std::uint8_t covered) {
    int last = -radius - 1;
    for (int i = 0; i < length + radius; ++i) {
      if (i < length && in[std::size_t(i) * stride]) last = i;
      const int target = i - radius;
      if (target >= 0 && i - last <= 2 * radius) out[std::size_t(target) * stride] = covered;
    }
  };
  std::vector<std::uint8_t> across(at_jump.size(), 0), frozen(at_jump.size(), 1);
  for (int r = 0; r < rows; ++r)
    dilate_line(&at_jump[std::size_t(r) * cols], &across[std::size_t(r) * cols], cols, 1, 1);
  for (int c = 0; c < cols; ++c) dilate_line(&across[std::size_t(c)], &frozen[std::size_t(c)], rows, std::size_t(cols), 0);
  return frozen;
}

// The tilts (light frame, radians; NaN elsewhere) that stand for the coarse label at the fine pixels
// that keep it (`frozen`): the coarse level's own tilts (those of its normals) interpolated bilinearly
// between coarse pixel centres, over the coarse neighbours whose label is within one step of the
// pixel's own coarse label (the smoothly turning part of the labelling, which is where pixels are
// frozen; a convex/concave jump is never averaged across). Taking the block's label instead made every
// coarse block a plateau of one tilt, and the normal maps a grid of steps on the blocks' edges (issue
// 29) wherever no local candidate snaps the label: flat-looking areas, gentle slopes, textures.
std::vector<float> upsampled_tilts(const GlobalStepResult& coarse, const Mask& coarse_mask, const std::vector<int>& centre,
                                   const std::vector<std::uint8_t>& frozen, const LightFrame& light, int labels, int rows,
                                   int cols) {
  const int coarse_rows = int(coarse_mask.rows()), coarse_cols = int(coarse_mask.cols());
  // Each coarse pixel's tilt as a unit vector in the light frame; a normal along the light has none,
  // and takes its label's.
  std::vector<Eigen::Vector2d> direction(std::size_t(coarse_rows) * coarse_cols, Eigen::Vector2d::Zero());
  for (std::size_t q = 0; q < direction.size(); ++q) {
    if (!coarse_mask.data()[q]) continue;
    const Eigen::Vector3d in_light = light.to_camera.transpose() * coarse.normals.xyz.row(Eigen::Index(q)).transpose().cast<double>();
    const double length = in_light.head<2>().norm();
    const double label_tilt = 2.0 * M_PI * coarse.labelling[q] / labels;
    direction[q] = length > 1e-6 ? Eigen::Vector2d(in_light.head<2>() / length)
                                 : Eigen::Vector2d(std::cos(label_tilt), std::sin(label_tilt));
  }
  std::vector<float> tilts(std::size_t(rows) * cols, std::numeric_limits<float>::quiet_NaN());
  detail::parallel_for(rows, 8, detail::default_thread_count(), [&](int r) {
    for (int c = 0; c < cols; ++c) {
      const std::size_t p = std::size_t(r) * cols + c;
      if (!frozen[p] || centre[p] < 0) continue;
      // The fine pixel's centre in coarse pixel coordinates (coarse centres at integers).
      const double y = 0.5 * r - 0.25, x = 0.5 * c - 0.25;
      const int r0 = int(std::floor(y)), c0 = int(std::floor(x));
      const double fy = y - r0, fx = x - c0;
      Eigen::Vector2d sum = Eigen::Vector2d::Zero();
      for (int dr = 0; dr <= 1; ++dr) {
        for (int dc = 0; dc <= 1; ++dc) {
          const int cr = r0 + dr, cc = c0 + dc;
          if (cr < 0 || cc < 0 || cr >= coarse_rows || cc >= coarse_cols || !coarse_mask(cr, cc)) continue;
          const std::size_t q = std::size_t(cr) * coarse_cols + cc;
          const int steps = std::abs(coarse.labelling[q] - centre[p]);
          if (std::min(steps, labels - steps) > 1) continue;
          sum += (dr ? fy : 1.0 - fy) * (dc ? fx : 1.0 - fx) * direction[q];
        }
      }
      // The pixel's own block always counts (weight >= 9/16), so the sum vanishes only when its
      // neighbours' tilts cancel it, which one label step apart they cannot.
      if (sum.norm() > 1e-9) tilts[p] = float(std::atan2(sum.y(), sum.x()));
    }
  });
  return tilts;
}

// The start of a fine level: the allowed label nearest the centre; the convex labelling where there
// is no centre.
std::vector<int> start_from_centres(const TiltEnergy& energy, const std::vector<int>& centre) {
  std::vector<int> labelling(centre.size(), 0);
  for (std::size_t p = 0; p < labelling.size(); ++p) {
    if (!energy.mask().data()[p]) continue;
    const int nearest = centre[p] < 0 ? -1 : energy.nearest_allowed_label(int(p), energy.label_tilt(centre[p]));
    labelling[p] = nearest >= 0 ? nearest : energy.convex_label(int(p));
  }
  return labelling;
}

// The mean squared brightness residual of the depth integrated from a labelling's normals, over the
// pixels not `unreliable`: how well the labelling, made integrable, explains the image.
double integrated_residual(NormalMap normals, const ImageF& image, const Mask& mask, const Mask& unreliable,
                           const LightFrame& light, double albedo, const GlobalStepParams& params) {
  const Surface surface =
      surface_from_normals(std::move(normals), mask, unreliable, params.occluding_contour, Integrator::Poisson, false,
                           params.max_slope);
  return mean_brightness_residual(surface.depth, image, mask, mask && !unreliable, light.direction, albedo);
}

// The energy of a labelling and of its inversion (each label turned by pi, or the allowed label nearest
// that) under `params` without dead-end elimination and without a reference:
// GlobalStepResult::orientation_energy and inverted_energy.
std::pair<double, double> orientation_energies(const LocalShape& local, const LightFrame& light, const Mask& mask,
                                               TiltEnergyParams params, const std::vector<int>& labelling) {
  params.prune = false;
  params.reference = nullptr;
  params.reference_weight = 0.0;
  params.band_centre = nullptr;
  params.band_frozen = nullptr;
  params.band_span = nullptr;
  const TiltEnergy judge(local, light, mask, params);
  std::vector<int> inverted = labelling;
  for (std::size_t p = 0; p < inverted.size(); ++p) {
    if (!mask.data()[p]) continue;
    const int turned = judge.nearest_allowed_label(int(p), judge.label_tilt(labelling[p]) + M_PI);
    if (turned >= 0) inverted[p] = turned;
  }
  return {judge.energy(labelling), judge.energy(inverted)};
}

// The labellings carried up the levels: the paper's alone, or with a viscosity_weight the paper's
// and the pulled one (in that order) while the pulled one leads but is not yet confirmed.
using Lineages = std::vector<GlobalStepResult>;

// Integrates both lineages and keeps the one whose depth renders closer to this level's image, with
// both residuals; with `confirm_later`, a pulled lineage that leads keeps the paper's beside it. Its
// time counts as the graph cut's.
void choose_lineage(const ImageF& image, const Mask& mask, const LightFrame& light, double albedo,
                    const GlobalStepParams& params, bool confirm_later, std::map<std::string, double>& seconds,
                    Lineages& lineages) {
  const Stopwatch stage;
  const Mask unreliable = unreliable_pixels(image, mask, albedo, params.shadow_threshold, params.highlight_threshold);
  auto residual = [&](const GlobalStepResult& lineage) {
    return integrated_residual(lineage.normals, image, mask, unreliable, light, albedo, params);
  };
  const double paper_residual = residual(lineages[0]);
  const double pulled_residual = residual(lineages[1]);
  seconds["graphcut"] += stage.seconds();
  const bool pulled_kept = pulled_residual < paper_residual;
  for (GlobalStepResult& lineage : lineages) {
    lineage.paper_residual = paper_residual;
    lineage.pulled_residual = pulled_residual;
    lineage.pulled_kept = pulled_kept;
  }
  if (pulled_kept && confirm_later) return;
  GlobalStepResult kept = std::move(lineages[pulled_kept ? 1 : 0]);
  lineages.assign(1, std::move(kept));
}

// What every lineage of one level reads: the level's image and local shape, and the call's settings.
struct Level {
  const ImageF& image;
  const Mask& mask;
  const LightFrame& light;
  double albedo;
  const GlobalStepParams& params;
  MaxFlowSolver& solver;
  const Progress& progress;
  std::map<std::string, double>& seconds;
  const LocalShape& local;
  const TiltEnergyParams& base_params;  // the energy's weights scaled to this level's object
  double scale;                         // unary_scale of the level's mask
  const Mask& coarse_mask;              // the coarser level's mask (empty at the coarsest level)
};

// Where a lineage's coarse labelling lets each pixel's labels go, held while its energy is built.
// At a jump the band reaches the neighbours' coarse labels: a band around either side's own label
// holds no label of the other side, so the boundary could never leave the coarse pixels' edges,
// and every convex/concave boundary ended on the coarsest level's grid (issue 29). Reaching them, a
// level can move it by a pixel, and the levels together anywhere in a coarsest pixel.
struct CoarseBand {
  std::vector<int> centre;
  std::vector<int> band_centre;
  std::vector<std::int16_t> band_span;
  std::vector<std::uint8_t> at_jump, frozen;
  std::vector<float> frozen_tilts;
};

// The band of `from` at this level, pointed to by `energy_params`.
void restrict_to_band(const Level& level, const GlobalStepResult& from, CoarseBand& band, TiltEnergyParams& energy_params) {
  const int rows = int(level.image.rows()), cols = int(level.image.cols());
  const int labels = level.params.energy.labels;
  band.centre = upsample_labels(from.labelling, level.coarse_mask, rows, cols);
  band.at_jump = jump_pixels(band.centre, level.mask, labels);
  std::tie(band.band_centre, band.band_span) = jump_windows(band.centre, band.at_jump, level.mask, labels);
  energy_params.band_centre = &band.band_centre;
  energy_params.band_span = &band.band_span;
  if (level.params.band_radius >= 0) {
    band.frozen = frozen_pixels(band.at_jump, rows, cols, level.params.band_radius);
    energy_params.band_frozen = &band.frozen;
    band.frozen_tilts = upsampled_tilts(from, level.coarse_mask, band.centre, band.frozen, level.light, labels, rows, cols);
  }
}

// The counts and choices a lineage carries from its coarser level.
void carry_from_coarser(const GlobalStepResult& from, GlobalStepResult& result) {
  result.expansion.moves += from.expansion.moves;
  result.expansion.accepted_moves += from.expansion.accepted_moves;
  result.expansion.repaired_moves += from.expansion.repaired_moves;
  result.expansion.maxflow_seconds += from.expansion.maxflow_seconds;
  result.levels = from.levels + 1;
  result.orientation_energy = from.orientation_energy;
  result.inverted_energy = from.inverted_energy;
  result.paper_residual = from.paper_residual;
  result.pulled_residual = from.pulled_residual;
  result.pulled_kept = from.pulled_kept;
}

// One lineage's labelling at this level, from its coarse labelling (none at the coarsest level),
// with `reference` pulling the energy when given; its progress in [begin, end] of the level.
GlobalStepResult solve_lineage(const Level& level, const GlobalStepResult* from, const NormalMap* reference, double begin,
                               double end) {
  GlobalStepResult result;
  level.progress.report(begin, "energy");
  Stopwatch stage;
  TiltEnergyParams energy_params = level.base_params;
  energy_params.band = level.params.band;
  CoarseBand band;
  if (from) restrict_to_band(level, *from, band, energy_params);
  if (reference) {
    energy_params.reference = reference;
    energy_params.reference_weight = level.params.viscosity_weight * level.scale;
  }
  const TiltEnergy energy(level.local, level.light, level.mask, energy_params);
  level.seconds["energy"] += stage.seconds();
  level.progress.report(begin + 0.05 * (end - begin), "graphcut");
  stage.restart();
  if (from) {
    result.labelling = start_from_centres(energy, band.centre);
  } else {
    result.labelling = energy.convex_labelling();
    convexity_cut(energy, level.local, result.labelling, level.solver);
  }
  result.expansion = alpha_expansion(energy, result.labelling, level.solver, level.params.max_cycles, level.params.tolerance,
                                     level.progress.range(begin + 0.05 * (end - begin), end));
  result.allowed_label_fraction = double(energy.allowed_count()) / (double(level.mask.count()) * energy.labels());
  level.seconds["graphcut"] += stage.seconds();
  result.normals = labelling_normals(result.labelling, energy, level.local, level.light, level.params.refine,
                                     band.frozen_tilts.empty() ? nullptr : &band.frozen_tilts);
  if (from) {
    carry_from_coarser(*from, result);
  } else {
    std::tie(result.orientation_energy, result.inverted_energy) =
        orientation_energies(level.local, level.light, level.mask, level.base_params, result.labelling);
  }
  return result;
}

void solve_level(const ImageF& image, const Mask& mask, const LightFrame& light, double albedo,
                 const GlobalStepParams& params, MaxFlowSolver& solver, Progress progress, bool finest,
                 std::map<std::string, double>& seconds, Lineages& lineages);

// The coarser levels solved into `coarse` (half resolution, and below it recursively) when coarse to
// fine applies; returns their mask (empty when it does not) and narrows `progress` to this level's share.
Mask solve_coarser(const ImageF& image, const Mask& mask, const LightFrame& light, double albedo, const GlobalStepParams& params,
                   MaxFlowSolver& solver, Progress& progress, std::map<std::string, double>& seconds, Lineages& coarse) {
  if (params.band < 0 || object_size(mask) < 2.0 * params.coarsest_object_size) return {};
  // A coarse pixel lies in the mask only when its whole block does.
  auto [half_image, half_mask] = downsample(image, mask, 2, 1.0);
  if (!half_mask.any()) return {};
  solve_level(half_image, half_mask, light, albedo, params, solver, progress.range(0.0, kCoarseShare), false, seconds, coarse);
  // Chosen at the finest level no larger than choice_object_size: finer levels rarely change
  // which labelling explains the image better, and cost each lineage four times as much.
  if (coarse.size() == 2 && object_size(mask) > params.choice_object_size)
    choose_lineage(half_image, half_mask, light, albedo, params, false, seconds, coarse);
  progress = progress.range(kCoarseShare, 1.0);
  return std::move(half_mask);
}

// Solves one level (after the coarser ones, when there are any) into `lineages`, reporting progress
// in [begin, end] of the whole step and adding each stage's seconds to `seconds`. `finest` is the
// level the caller asked for: lineages still both alive there are chosen between there.
void solve_level(const ImageF& image, const Mask& mask, const LightFrame& light, double albedo,
                 const GlobalStepParams& params, MaxFlowSolver& solver, Progress progress, bool finest,
                 std::map<std::string, double>& seconds, Lineages& lineages) {
  Lineages coarse;
  const Mask coarse_mask = solve_coarser(image, mask, light, albedo, params, solver, progress, seconds, coarse);
  progress.report(0.0, "local");
  Stopwatch stage;
  const LocalShape local = local_shape(image, mask, light, albedo, params.min_curvature);
  seconds["local"] += stage.seconds();
  TiltEnergyParams base_params = params.energy;
  const double scale = unary_scale(mask);
  base_params.data_weight *= scale;
  base_params.undefined_weight *= scale;
  const Level level{image, mask, light, albedo, params, solver, progress, seconds, local, base_params, scale, coarse_mask};

  lineages.clear();
  if (!coarse.empty()) {
    const double share = 1.0 / double(coarse.size());
    for (std::size_t i = 0; i < coarse.size(); ++i)
      lineages.push_back(solve_lineage(level, &coarse[i], nullptr, double(i) * share, double(i + 1) * share));
  } else if (params.viscosity_weight > 0.0) {
    lineages.push_back(solve_lineage(level, nullptr, nullptr, 0.0, 0.5));
    progress.report(0.5, "upwind");
    stage.restart();
    const NormalMap reference = normals_from_depth(upwind(image, mask, light, albedo, params.viscosity_rounds, {}, kPullBrightestShade).depth, mask);
    seconds["upwind"] += stage.seconds();
    lineages.push_back(solve_lineage(level, nullptr, &reference, 0.5, 1.0));
    // The coarsest level's residuals can be within its coarse discretization's own error: a pulled
    // labelling that leads here is confirmed at a finer level, the paper's carried beside it.
    choose_lineage(image, mask, light, albedo, params, !finest, seconds, lineages);
  } else {
    lineages.push_back(solve_lineage(level, nullptr, nullptr, 0.0, 1.0));
  }
  if (finest && lineages.size() == 2) choose_lineage(image, mask, light, albedo, params, false, seconds, lineages);
}

}  // namespace

GlobalStepResult global_step(const ImageF& image, const Mask& mask, const LightFrame& light, double albedo,
                             const GlobalStepParams& params, MaxFlowSolver& solver, const Progress& progress) {
  std::map<std::string, double> seconds;
  Lineages lineages;
  solve_level(image, mask, light, albedo, params, solver, progress, true, seconds, lineages);
  GlobalStepResult result = std::move(lineages.front());
  result.seconds = std::move(seconds);
  return result;
}

}  // namespace shadecut
