#include "pipeline/option_checks.hpp"

#include <shadecut/pipeline/option_table.hpp>
#include <shadecut/support/errors.hpp>
#include <shadecut/support/memory.hpp>
#include <shadecut/support/validate.hpp>

#include <string>

namespace shadecut::detail {

namespace {

// A call's peak memory per pixel and per label and pixel with every label kept (docs/benchmarks.md,
// "Memory", measures both).
constexpr double kPeakBytesPerPixel = 180.0;
constexpr double kPeakBytesPerLabelPixel = 20.0;

// The finest detail size the damping resolves: below it its blur (three boxes, damp_large_forms) has
// a radius of 0 and would take every form away, leaving a depth of 0.
constexpr double kMinDetailSize = 5.0;

void check_memory(const ReconstructOptions& options, const Mask& mask) {
  const std::uint64_t needed = estimated_peak_memory(options, std::int64_t(mask.size()));
  const std::uint64_t available = available_memory();
  if (needed > available)
    throw InvalidArgument("shadecut: this call needs about " + memory_text(needed) + " for " + std::to_string(mask.rows()) +
                          " x " + std::to_string(mask.cols()) + " pixels, but only " + memory_text(available) +
                          " can be allocated; give a smaller image (max_pixels, or the add-on's Max size)");
}

}  // namespace

std::uint64_t estimated_peak_memory(const ReconstructOptions& options, std::int64_t pixels) {
  const bool graph_cut = options.method == Method::GraphCut || options.method == Method::GraphCutTwo;
  const bool every_label = graph_cut && options.coarse_to_fine_band < 0;
  return std::uint64_t(double(pixels) * (kPeakBytesPerPixel + (every_label ? options.labels * kPeakBytesPerLabelPixel : 0.0)));
}

void check_options(const ReconstructOptions& options, const Mask& mask) {
  check_memory(options, mask);
  check_option_ranges(options);
  if (options.detail_size > 0.0 && options.detail_size < kMinDetailSize)
    throw InvalidArgument("shadecut: detail_size must be 0 (read from the image), < 0 (keep every form) or at least " +
                          std::to_string(int(kMinDetailSize)) + " pixels (finer forms are the detail itself); got " +
                          number_text(options.detail_size));
  // No Lambertian pixel is brighter than its albedo: a threshold below 1 would call lit pixels highlights.
  if (options.highlight_threshold && *options.highlight_threshold > 0.0 && *options.highlight_threshold < 1.0)
    throw InvalidArgument("shadecut: highlight_threshold must be <= 0 (never) or at least 1 (no Lambertian surface is "
                          "brighter than its albedo); got " + number_text(*options.highlight_threshold));
  if (options.seamless && options.scene != SceneKind::Relief)
    throw InvalidArgument("shadecut: seamless output is for reliefs that fill the image; set scene to relief");
  if (options.seamless && !mask.all())
    throw InvalidArgument("shadecut: seamless output tiles the whole image, but the mask leaves " +
                          std::to_string(mask.size() - mask.count()) + " pixels out; give no mask");
}

}  // namespace shadecut::detail
