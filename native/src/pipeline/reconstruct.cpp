// The entry point: photographs in, a surface out. An object given without a mask is cut out of its
// background first (ReconstructOptions::cut_out).
#include <shadecut/pipeline/reconstruct.hpp>

#include <shadecut/pipeline/cut_out.hpp>
#include <shadecut/support/errors.hpp>

#include "pipeline/crop.hpp"
#include "pipeline/option_checks.hpp"
#include "pipeline/paint.hpp"
#include "pipeline/photographs.hpp"
#include "support/stopwatch.hpp"

namespace shadecut {

namespace {

// One photograph, or several, within the mask; an object in its window when that saves the frame (a
// relief's steps read the whole frame: its detail size, its large forms).
Reconstruction reconstruct_masked(const std::vector<Observation>& observations, const Mask& mask, std::optional<double> albedo,
                                  const ReconstructOptions& options) {
  auto solve = [&](const std::vector<Observation>& inside, const Mask& inside_mask) {
    if (inside.size() > 1) return detail::reconstruct_photographs(inside, &inside_mask, albedo, options);
    const ColourImage* colour = inside.front().has_colour() ? &inside.front().colour : nullptr;
    return detail::reconstruct_painted(inside.front().image, colour, inside.front().light, &inside_mask, albedo, options);
  };
  // Near lamps stand around the frame's centre, which a window would move.
  if (options.scene != SceneKind::Object || options.light_distance > 0.0) return solve(observations, mask);
  return detail::solve_in_object_window(observations, mask, solve);
}

// `alone` holds one photograph: passed as the list it came in, so that the cut-out's call copies none.
Reconstruction reconstruct_cut_out(const std::vector<Observation>& alone, std::optional<double> albedo,
                                   const ReconstructOptions& options) {
  const Observation& photograph = alone.front();
  const ImageF& image = photograph.image;
  const ColourImage* colour = photograph.has_colour() ? &photograph.colour : nullptr;
  // The options and the memory first: a call refused for its size is refused at once, not after the cut.
  detail::check_options(options, Mask::Constant(image.rows(), image.cols(), true));
  const Stopwatch stopwatch;
  // The cut-out reports as the call's start, so that a cancel reaches it too.
  const CutOut cut = cut_out(image, colour, CutOutOptions{}, Progress(options.progress).range(0.0, 0.0));
  const double seconds = stopwatch.seconds();
  Reconstruction result = cut.outcome == CutOutOutcome::Found
                              ? reconstruct_masked(alone, cut.mask, albedo, options)
                              : detail::reconstruct_painted(image, colour, photograph.light, nullptr, albedo, options);
  result.stats.cut_out = cut.outcome;
  result.stats.cut_out_contrast = cut.outline_contrast;
  result.stats.cut_out_message = cut.message;
  result.stats.seconds["cut_out"] = seconds;
  result.stats.seconds["total"] += seconds;
  return result;
}

Reconstruction reconstruct_one(const std::vector<Observation>& alone, std::optional<double> albedo,
                               const ReconstructOptions& options) {
  if (options.scene == SceneKind::Object && options.cut_out) return reconstruct_cut_out(alone, albedo, options);
  const Observation& photograph = alone.front();
  const ColourImage* colour = photograph.has_colour() ? &photograph.colour : nullptr;
  return detail::reconstruct_painted(photograph.image, colour, photograph.light, nullptr, albedo, options);
}

}  // namespace

Reconstruction reconstruct(const std::vector<Observation>& observations, const Mask* mask, std::optional<double> albedo,
                           const ReconstructOptions& options) {
  if (observations.empty()) throw InvalidArgument("shadecut: no photograph given");
  check_option_ranges(options);
  if (observations.size() == 1 && options.light_distance > 0.0)
    throw InvalidArgument("shadecut: light_distance places the lamps of several photographs; one photograph is read "
                          "under a distant light (leave light_distance at 0)");
  if (mask) return reconstruct_masked(observations, *mask, albedo, options);
  if (observations.size() > 1) return detail::reconstruct_photographs(observations, nullptr, albedo, options);
  return reconstruct_one(observations, albedo, options);
}

Reconstruction reconstruct(const ImageF& image, const std::optional<Eigen::Vector3d>& light, const Mask* mask,
                           std::optional<double> albedo, const ReconstructOptions& options) {
  return reconstruct({grey_observation(image, light)}, mask, albedo, options);
}

Reconstruction reconstruct(const ColourImage& image, const std::optional<Eigen::Vector3d>& light, const Mask* mask,
                           std::optional<double> albedo, const ReconstructOptions& options) {
  return reconstruct({colour_observation(image, light)}, mask, albedo, options);
}

}  // namespace shadecut
