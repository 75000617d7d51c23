#include <shadecut/pipeline/reconstruct_options.hpp>

#include "support/enum_names.hpp"

namespace shadecut {

double highlight_threshold_used(const ReconstructOptions& options) {
  if (options.highlight_threshold) return *options.highlight_threshold;
  return options.albedo_method == AlbedoMethod::Retinex ? kRetinexHighlightThreshold : kHighlightThreshold;
}

LightMethod light_method_used(const ReconstructOptions& options) {
  if (options.light_method) return *options.light_method;
  return options.scene == SceneKind::Relief ? LightMethod::Relief : LightMethod::ZhengChellappa;
}

const std::vector<std::string>& scene_kind_names() {
  static const std::vector<std::string> names{"object", "relief"};
  return names;
}

SceneKind parse_scene_kind(const std::string& name) { return parse_enum<SceneKind>(scene_kind_names(), name, "scene kind"); }

std::string to_string(SceneKind kind) { return scene_kind_names().at(std::size_t(kind)); }

}  // namespace shadecut
