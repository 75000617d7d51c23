#include "pipeline/surface_rules.hpp"

#include <shadecut/pipeline/relief.hpp>

#include <cmath>
#include <limits>

namespace shadecut::detail {

double shadow_threshold_used(const ReconstructOptions& options) {
  return options.fill_shadows ? options.shadow_threshold : -1.0;
}

bool edge_is_outline(const ReconstructOptions& options) {
  return options.occluding_contour && options.scene == SceneKind::Object;
}

double detail_size_used(const ImageF& image, const Mask& mask, const ReconstructOptions& options) {
  const double none = std::numeric_limits<double>::quiet_NaN();
  if (options.scene != SceneKind::Relief || options.seamless || options.detail_size < 0.0) return none;
  if (options.detail_size > 0.0) return options.detail_size;
  // The damping takes out the integration's drift; pentland's depth is one least-squares solve, whose large
  // forms are the image's (docs/comparison_methods.md, pentland).
  if (options.method == Method::Pentland) return none;
  const double size = options.detail_scale_factor * relief_scale(image, mask);
  return std::isfinite(size) ? size : none;
}

void finish_relief(ImageF& depth, const Mask& mask, const ReconstructOptions& options, double detail_size) {
  if (options.seamless || options.scene != SceneKind::Relief) return;
  flatten_relief(depth, mask);
  if (std::isfinite(detail_size)) damp_large_forms(depth, mask, detail_size);
}

}  // namespace shadecut::detail
