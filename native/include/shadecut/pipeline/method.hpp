// The reconstruction methods: their names and the defaults each uses for the options left unset.
#pragma once

#include <string>
#include <vector>

namespace shadecut {

enum class Method {
  GraphCut,     ///< "graphcut": the paper's eq. (15) energy, minimized by alpha-expansion
  GraphCutTwo,  ///< "graphcut_two": the paper's eq. (10), every pixel restricted to its two candidates
  LeeRosenfeld, ///< "lee_rosenfeld": the local method under the convex assumption (no global step)
  BrooksHorn,   ///< "brooks_horn": Brooks & Horn's variational iteration (brooks_horn.hpp), normals integrated
  TsaiShah,     ///< "tsai_shah": Tsai & Shah's linearized depth iteration (tsai_shah.hpp), normals from its depth
  Upwind,       ///< "upwind": the viscosity solution by upwind fast sweeping (upwind.hpp), normals from its depth
  Pentland,     ///< "pentland": Pentland's linear shape from shading for reliefs (pentland.hpp), normals from its depth
};

/// Every method's name, in the order of the enum (the method registry's).
const std::vector<std::string>& method_names();

/// Parses one of method_names(); throws InvalidArgument otherwise.
Method parse_method(const std::string& name);
std::string to_string(Method method);

/// Per-method defaults chosen by scripts/tune_parameters.py on training surfaces (docs/parameters.md):
/// what reconstruct() uses for an option left unset. A field a method does not use is 0.
struct MethodDefaults {
  double min_curvature = 0.0;     ///< graph-cut methods, lee_rosenfeld (ReconstructOptions::min_curvature)
  double undefined_weight = 0.0;  ///< graph-cut methods (ReconstructOptions::undefined_weight)
  double tolerance = 0.0;         ///< graph-cut methods: share of the energy; brooks_horn: mean |dn| per sweep
  int iterations = 0;             ///< brooks_horn, tsai_shah sweeps; upwind: most rounds of sweeps; pentland solves
  double smoothness = 0.0;        ///< brooks_horn, pentland (ReconstructOptions::smoothness)
};
MethodDefaults method_defaults(Method method);

}  // namespace shadecut
