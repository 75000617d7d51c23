// A labelling's normals made into a surface: the finishing every reconstruction, and every
// comparison of two labellings, shares.
#pragma once

#include <shadecut/integrate/integrate.hpp>
#include <shadecut/support/progress.hpp>
#include <shadecut/support/types.hpp>

namespace shadecut {

struct Surface {
  NormalMap normals;      ///< H x W: filled and folded; with `periodic`, the tiling depth's own
  ImageF depth;           ///< H x W, pixel units, larger = closer
  int filled_pixels = 0;  ///< normals fill_normals interpolated
};

/// fill_normals over the `unreliable` pixels, fold_back_facing, then the depth: integrate_periodic
/// when `periodic` (the normals then become that depth's, normals_from_periodic_depth; a tiling
/// surface has no ramp to flatten), integrate_normals with `integrator` otherwise.
///
/// @param[in] normals           H x W camera-frame unit normals.
/// @param[in] mask              H x W pixels of the surface.
/// @param[in] unreliable        H x W pixels whose normals are interpolated (unreliable_pixels).
/// @param[in] occluding_contour fill_normals' outline rule.
/// @param[in] integrator        used unless `periodic`.
/// @param[in] periodic          the surface fills the image and tiles.
/// @param[in] max_slope         the integrators' gradient clamp.
/// @param[in] progress          integrate_normals' progress.
Surface surface_from_normals(NormalMap normals, const Mask& mask, const Mask& unreliable, bool occluding_contour,
                             Integrator integrator, bool periodic, double max_slope, const Progress& progress = {});

}  // namespace shadecut
