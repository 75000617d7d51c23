// Internal: the methods behind one interface. A method is its own file under pipeline/methods/ with
// a solve function, and one line of method_registry.cpp that names it and gives its defaults.
#pragma once

#include <shadecut/pipeline/method.hpp>
#include <shadecut/pipeline/reconstruct_options.hpp>
#include <shadecut/pipeline/reconstruction.hpp>
#include <shadecut/support/light.hpp>
#include <shadecut/support/progress.hpp>

#include <vector>

namespace shadecut::detail {

/// What every method reads: the image (H x W linear intensity), the mask, the pixels the call marked
/// as shadow or highlight (unreliable_pixels; filled after the method), the light, the albedo, the
/// options and the progress of its share.
struct MethodInput {
  const ImageF& image;
  const Mask& mask;
  const Mask& unreliable;
  const LightFrame& frame;
  double albedo;
  const ReconstructOptions& options;
  const Progress& progress;
};

/// The method's normals (H x W, unit inside the mask); its stages' seconds and its counts go into `stats`.
using SolveNormals = NormalMap (*)(const MethodInput& input, ReconstructStats& stats);

struct MethodEntry {
  const char* name;         ///< the method's name (method_names())
  MethodDefaults defaults;  ///< tuned (docs/parameters.md)
  SolveNormals solve;
};

/// Every method, in the order of the Method enum.
const std::vector<MethodEntry>& method_registry();

/// The registry's entry of `method`.
const MethodEntry& method_entry(Method method);

// The methods, each in its own file of pipeline/methods/.
NormalMap solve_graph_cut(const MethodInput& input, ReconstructStats& stats);      // graphcut, graphcut_two
NormalMap solve_lee_rosenfeld(const MethodInput& input, ReconstructStats& stats);
NormalMap solve_brooks_horn(const MethodInput& input, ReconstructStats& stats);
NormalMap solve_tsai_shah(const MethodInput& input, ReconstructStats& stats);
NormalMap solve_upwind(const MethodInput& input, ReconstructStats& stats);
NormalMap solve_pentland(const MethodInput& input, ReconstructStats& stats);

}  // namespace shadecut::detail
