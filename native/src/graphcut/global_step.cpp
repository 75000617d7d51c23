#include <shadecut/graphcut/global_step.hpp>

#include <shadecut/graphcut/convexity_cut.hpp>
#include <shadecut/support/downsample.hpp>
#include <shadecut/support/render.hpp>
#include <shadecut/pipeline/shadow_fill.hpp>
#include <shadecut/integrate/surface_from_normals.hpp>
#include <shadecut/baselines/upwind.hpp>

#include "support/parallel.hpp"
#include "support/stopwatch.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <tuple>
#include <utility>

namespace shadecut {

namespace {

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
// reliable pixels: how well the labelling, made integrable, explains the image.
double integrated_residual(NormalMap normals, const ImageF& image, const Mask& mask, const LightFrame& light, double albedo,
                           const GlobalStepParams& params) {
  const Mask unreliable = unreliable_pixels(image, mask, albedo, params.shadow_threshold, params.highlight_threshold);
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

// Solves one level (after the coarser ones, when there are any) into `result`, reporting progress in
// [begin, end] of the whole step.
void solve_level(const ImageF& image, const Mask& mask, const LightFrame& light, double albedo,
                 const GlobalStepParams& params, MaxFlowSolver& solver, Progress progress, GlobalStepResult& result) {
  std::vector<int> centre;
  GlobalStepResult coarse;
  Mask coarse_mask;
  int coarse_moves = 0, coarse_accepted = 0, coarse_repaired = 0, coarse_levels = 0;
  double coarse_seconds = 0.0;
  if (params.band >= 0 && object_size(mask) >= 2.0 * params.coarsest_object_size) {
    // A coarse pixel lies in the mask only when its whole block does.
    auto [half_image, half_mask] = downsample(image, mask, 2, 1.0);
    if (half_mask.any()) {
      solve_level(half_image, half_mask, light, albedo, params, solver, progress.range(0.0, kCoarseShare), coarse);
      centre = upsample_labels(coarse.labelling, half_mask, int(image.rows()), int(image.cols()));
      coarse_mask = std::move(half_mask);
      coarse_moves = coarse.expansion.moves;
      coarse_accepted = coarse.expansion.accepted_moves;
      coarse_repaired = coarse.expansion.repaired_moves;
      coarse_seconds = coarse.expansion.maxflow_seconds;
      coarse_levels = coarse.levels;
      result.seconds = coarse.seconds;
      result.paper_residual = coarse.paper_residual;
      result.pulled_residual = coarse.pulled_residual;
      result.pulled_kept = coarse.pulled_kept;
      result.orientation_energy = coarse.orientation_energy;
      result.inverted_energy = coarse.inverted_energy;
      progress = progress.range(kCoarseShare, 1.0);
    }
  }

  progress.report(0.0, "local");
  Stopwatch stage;
  const LocalShape local = local_shape(image, mask, light, albedo, params.min_curvature);
  result.seconds["local"] += stage.seconds();
  progress.report(0.02, "energy");
  stage.restart();
  TiltEnergyParams energy_params = params.energy;
  const double scale = unary_scale(mask);
  energy_params.data_weight *= scale;
  energy_params.undefined_weight *= scale;
  // At a jump the band reaches the neighbours' coarse labels: a band around either side's own label
  // holds no label of the other side, so the boundary could never leave the coarse pixels' edges,
  // and every convex/concave boundary ended on the coarsest level's grid (issue 29). Reaching them, a
  // level can move it by a pixel, and the levels together anywhere in a coarsest pixel.
  std::vector<int> band_centre;
  std::vector<std::int16_t> band_span;
  std::vector<std::uint8_t> at_jump;
  if (!centre.empty()) {
    at_jump = jump_pixels(centre, mask, params.energy.labels);
    std::tie(band_centre, band_span) = jump_windows(centre, at_jump, mask, params.energy.labels);
    energy_params.band_centre = &band_centre;
    energy_params.band_span = &band_span;
  }
  energy_params.band = params.band;
  std::vector<std::uint8_t> frozen;
  std::vector<float> frozen_tilts;
  if (!centre.empty() && params.band_radius >= 0) {
    frozen = frozen_pixels(at_jump, int(image.rows()), int(image.cols()), params.band_radius);
    energy_params.band_frozen = &frozen;
    frozen_tilts = upsampled_tilts(coarse, coarse_mask, centre, frozen, light, params.energy.labels, int(image.rows()),
                                   int(image.cols()));
  }
  const TiltEnergy energy(local, light, mask, energy_params);
  result.seconds["energy"] += stage.seconds();
  const bool choose = centre.empty() && params.viscosity_weight > 0.0;
  // Each labelling's share of the level's cuts: both when the coarsest level chooses.
  const double cuts_end = choose ? 0.5 : 1.0;
  progress.report(0.05, "graphcut");
  stage.restart();
  auto label = [&](const TiltEnergy& labelled, double begin, double end, AlphaExpansionStats& expansion) {
    std::vector<int> labelling;
    if (centre.empty()) {
      labelling = labelled.convex_labelling();
      convexity_cut(labelled, local, labelling, solver);
    } else {
      labelling = start_from_centres(labelled, centre);
    }
    expansion = alpha_expansion(labelled, labelling, solver, params.max_cycles, params.tolerance, progress.range(begin, end));
    return labelling;
  };
  std::vector<int> labelling = label(energy, 0.05, cuts_end, result.expansion);
  result.allowed_label_fraction = double(energy.allowed_count()) / (double(mask.count()) * energy.labels());
  result.seconds["graphcut"] += stage.seconds();
  result.normals = labelling_normals(labelling, energy, local, light, params.refine,
                                     frozen_tilts.empty() ? nullptr : &frozen_tilts);
  if (choose) {
    progress.report(cuts_end, "upwind");
    stage.restart();
    const NormalMap reference = normals_from_depth(upwind(image, mask, light, albedo, params.viscosity_rounds).depth, mask);
    result.seconds["upwind"] += stage.seconds();
    progress.report(cuts_end, "energy");
    stage.restart();
    energy_params.reference = &reference;
    energy_params.reference_weight = params.viscosity_weight * scale;
    const TiltEnergy pulled_energy(local, light, mask, energy_params);
    result.seconds["energy"] += stage.seconds();
    progress.report(cuts_end, "graphcut");
    stage.restart();
    AlphaExpansionStats pulled_expansion;
    std::vector<int> pulled = label(pulled_energy, cuts_end, 1.0, pulled_expansion);
    NormalMap pulled_normals = labelling_normals(pulled, pulled_energy, local, light, params.refine);
    result.paper_residual = integrated_residual(result.normals, image, mask, light, albedo, params);
    result.pulled_residual = integrated_residual(pulled_normals, image, mask, light, albedo, params);
    result.seconds["graphcut"] += stage.seconds();
    if (result.pulled_residual < result.paper_residual) {
      result.pulled_kept = true;
      labelling = std::move(pulled);
      result.normals = std::move(pulled_normals);
      result.expansion = std::move(pulled_expansion);
      result.allowed_label_fraction = double(pulled_energy.allowed_count()) / (double(mask.count()) * energy.labels());
    }
  }
  if (centre.empty()) {
    TiltEnergyParams judged = params.energy;
    judged.data_weight *= scale;
    judged.undefined_weight *= scale;
    std::tie(result.orientation_energy, result.inverted_energy) =
        orientation_energies(local, light, mask, judged, labelling);
  }
  result.expansion.moves += coarse_moves;
  result.expansion.accepted_moves += coarse_accepted;
  result.expansion.repaired_moves += coarse_repaired;
  result.expansion.maxflow_seconds += coarse_seconds;
  result.levels = coarse_levels + 1;
  result.labelling = std::move(labelling);
}

}  // namespace

GlobalStepResult global_step(const ImageF& image, const Mask& mask, const LightFrame& light, double albedo,
                             const GlobalStepParams& params, MaxFlowSolver& solver, const Progress& progress) {
  GlobalStepResult result;
  solve_level(image, mask, light, albedo, params, solver, progress, result);
  return result;
}

}  // namespace shadecut
