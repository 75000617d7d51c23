#include <shadecut/integrate/surface_from_normals.hpp>

#include <shadecut/support/render.hpp>
#include <shadecut/integrate/shadow_fill.hpp>

#include <utility>

namespace shadecut {

Surface surface_from_normals(NormalMap normals, const Mask& mask, const Mask& unreliable, bool occluding_contour,
                             Integrator integrator, bool periodic, double max_slope, const Progress& progress) {
  Surface surface;
  surface.filled_pixels = fill_normals(normals, unreliable, mask, occluding_contour);
  fold_back_facing(normals, mask);
  if (periodic) {
    surface.depth = integrate_periodic(normals, max_slope);
    surface.normals = normals_from_periodic_depth(surface.depth);
  } else {
    surface.depth = integrate_normals(normals, mask, integrator, max_slope, progress);
    surface.normals = std::move(normals);
  }
  return surface;
}

}  // namespace shadecut
