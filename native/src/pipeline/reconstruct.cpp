// The entry point: photographs in, a surface out. An object given without a mask is cut out of its
// background first (ReconstructOptions::cut_out).
#include <shadecut/pipeline/reconstruct.hpp>

#include <shadecut/pipeline/cut_out.hpp>
#include <shadecut/support/errors.hpp>

#include "pipeline/option_checks.hpp"
#include "pipeline/paint.hpp"
#include "pipeline/photographs.hpp"
#include "support/stopwatch.hpp"

namespace shadecut {

namespace {

Reconstruction reconstruct_cut_out(const ImageF& image, const ColourImage* colour, const std::optional<Eigen::Vector3d>& light,
                                   std::optional<double> albedo, const ReconstructOptions& options) {
  // The options and the memory first: a call refused for its size is refused at once, not after the cut.
  detail::check_options(options, Mask::Constant(image.rows(), image.cols(), true));
  const Stopwatch stopwatch;
  // The cut-out reports as the call's start, so that a cancel reaches it too.
  const CutOut cut = cut_out(image, colour, CutOutOptions{}, Progress(options.progress).range(0.0, 0.0));
  const double seconds = stopwatch.seconds();
  Reconstruction result = detail::reconstruct_painted(image, colour, light, cut.outcome == CutOutOutcome::Found ? &cut.mask : nullptr,
                                                      albedo, options);
  result.stats.cut_out = cut.outcome;
  result.stats.cut_out_contrast = cut.outline_contrast;
  result.stats.cut_out_message = cut.message;
  result.stats.seconds["cut_out"] = seconds;
  result.stats.seconds["total"] += seconds;
  return result;
}

Reconstruction reconstruct_one(const Observation& photograph, const Mask* mask, std::optional<double> albedo,
                               const ReconstructOptions& options) {
  check_option_ranges(options);
  const ColourImage* colour = photograph.has_colour() ? &photograph.colour : nullptr;
  if (mask || options.scene != SceneKind::Object || !options.cut_out)
    return detail::reconstruct_painted(photograph.image, colour, photograph.light, mask, albedo, options);
  return reconstruct_cut_out(photograph.image, colour, photograph.light, albedo, options);
}

}  // namespace

Reconstruction reconstruct(const std::vector<Observation>& observations, const Mask* mask, std::optional<double> albedo,
                           const ReconstructOptions& options) {
  if (observations.empty()) throw InvalidArgument("shadecut: no photograph given");
  check_option_ranges(options);
  if (observations.size() > 1) return detail::reconstruct_photographs(observations, mask, albedo, options);
  return reconstruct_one(observations.front(), mask, albedo, options);
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
