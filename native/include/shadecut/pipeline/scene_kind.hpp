// What the image shows, which fixes what shading alone cannot.
#pragma once

#include <string>
#include <vector>

namespace shadecut {

enum class SceneKind {
  Object,  ///< "object": an object seen whole against a background; the mask's edge is its outline
  Relief,  ///< "relief": a surface that fills the frame and on average faces the viewer (relief.hpp):
           ///< the albedo is mean intensity / S_z and the depth sits on a flat carrier, no ramp
};

const std::vector<std::string>& scene_kind_names();
SceneKind parse_scene_kind(const std::string& name);
std::string to_string(SceneKind kind);

}  // namespace shadecut
