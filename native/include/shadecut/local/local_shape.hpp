// The local shape-from-shading step of Lee & Rosenfeld (1985): per-pixel slant and the two tilt
// candidates, in light-source coordinates.
#pragma once

#include <shadecut/support/light.hpp>
#include <shadecut/support/types.hpp>

namespace shadecut {

/// Per-pixel local estimates. All angles in radians, in the light-source frame of LightFrame.
struct LocalShape {
  ImageF slant;        ///< s = acos(clamp(I / albedo, 0, 1)), in [0, pi/2]
  ImageF tilt;         ///< the concave candidate t (paper eq. 9), in (-pi, pi]; t + pi is the convex one
  Mask tilt_defined;   ///< false where the surface reads as flat (see local_shape) or outside the mask
};

/// The object's size in pixels, sqrt(mask area): the length that makes the thresholds and weights
/// that compare a pixel with its surroundings the same at every resolution of the same surface.
double object_size(const Mask& mask);

/// The object size at which the energy's weights (data_weight, undefined_weight) and brooks_horn's
/// smoothness are given.
constexpr double kReferenceObjectSize = 128.0;

/// The factor that turns those per-object weights into per-pixel ones: kReferenceObjectSize /
/// object_size(mask). The data term is summed over the area (object_size^2 pixels) and the pairwise
/// term along label boundaries and over tilt gradients (object_size times its per-object value), so
/// without it doubling the resolution would double the data term against the smoothness and change
/// the minimum; with it the energy of the same surface is the same up to one factor at every
/// resolution.
double unary_scale(const Mask& mask);

/// Computes the local estimates of every masked pixel.
///
/// The tilt is t = atan2(Iy cos tS - Ix sin tS, cos sS (Ix cos tS + Iy sin tS)), with the intensity
/// derivatives Ix (along +x, right) and Iy (along +y, up) taken by central differences between masked
/// pixels (one-sided at the mask's edge).
///
/// The tilt is *undefined* where the surface reads as flat. Lee & Rosenfeld's model is a locally
/// spherical patch: a sphere of radius R (pixels) gives a pixel of slant s a gradient of about
/// albedo sin(s) / R (more toward its silhouette), so kappa = |grad I| L / (albedo sin s), with L the
/// object_size, is the curvature the model reads in units of the object: about L / R on a sphere at
/// every slant, 0 on a plane. It is the same at every resolution of the same surface, where
/// |grad I| / albedo alone halves when the resolution doubles. The tilt is undefined where
/// kappa < min_curvature, and where the gradient is exactly zero.
///
/// @param[in] image        H x W linear intensity.
/// @param[in] mask         H x W.
/// @param[in] light        light frame (LightFrame::from_direction).
/// @param[in] albedo       > 0; the intensity of a pixel facing the light.
/// @param[in] min_curvature >= 0; the tilt is undefined where kappa is below this.
LocalShape local_shape(const ImageF& image, const Mask& mask, const LightFrame& light, double albedo,
                       double min_curvature);

/// Camera-frame normals of the convex candidate (tilt t + pi) everywhere: the local method of
/// Lee & Rosenfeld under the convex assumption. Where the tilt is undefined the tilt is taken as pi
/// (the normal turned from the light toward the viewer), which matters only where the slant is large.
NormalMap convex_normals(const LocalShape& local, const LightFrame& light, const Mask& mask);

}  // namespace shadecut
