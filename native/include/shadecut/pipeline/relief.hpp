// Reliefs: surfaces that fill the frame (a wall, a coin, bark) and on average face the viewer. That
// one fact fixes what an image of them cannot: the albedo and the lowest frequencies of the depth.
#pragma once

#include <shadecut/estimate/relief_albedo.hpp>
#include <shadecut/support/types.hpp>

#include <Eigen/Core>

namespace shadecut {

/// Removes the least-squares plane of the masked depth, so that the relief sits on a flat carrier
/// facing the viewer (no ramp); then every 4-connected component's minimum is 0 again. A relief's
/// normals are its finished depth's (reconstruct), so they are not tilted here.
///
/// @param[in,out] depth H x W, pixel units (x = column, y = -row).
/// @param[in] mask      H x W.
void flatten_relief(ImageF& depth, const Mask& mask);

/// A relief's own scale, in pixels: the typical wavelength of its shading, 2 pi sqrt(var L / var grad L)
/// of the log-intensity L (floored at 1/1000 of the median, blurred over about a pixel against
/// noise), over the masked pixels: a single sinusoid of wavelength w gives w (skimage's brick
/// photograph reads 18 px, its coins 36 px).
/// @throws InvalidArgument for an empty mask or a relief dark in most of its pixels.
double relief_scale(const ImageF& image, const Mask& mask);

/// The pixels of a relief's thin bright lines, which shading does not draw: paint such as a brick
/// wall's mortar. A pixel is on one when, across a row or down a column, the darkest pixel on each
/// side within width / 2 is darker than it by more than the factor `contrast`: a line narrower than
/// `width` standing above both its sides. Shading draws a bright bevel beside a shadow, but a lit
/// bevel stands above one side only (its flat top is nearly as bright), so it is not marked.
/// No pixel is marked when the lines cover more than a quarter of the masked pixels (they are the
/// relief's own texture, every crest of a field of ridges, not paint on it), nor when with the black
/// pixels (shadows) they would cover half (the relief's median pixel, its albedo, would be black).
///
/// @param[in] image    H x W linear intensity.
/// @param[in] mask     H x W.
/// @param[in] width    pixels, >= 2 (< 2: no pixel).
/// @param[in] contrast > 1.
/// @return H x W, only masked pixels marked.
Mask bright_lines(const ImageF& image, const Mask& mask, int width, double contrast);

/// Damps the forms larger than `detail_size` pixels out of a relief's depth: subtracts its local
/// plane, at every pixel the masked least-squares plane through the depth around it weighted by a
/// Gaussian of standard deviation 0.187 detail_size (first-order normalized convolution). Inside the
/// frame and the mask that is the Gaussian blur, a high-pass that keeps half of a sinusoid of
/// wavelength detail_size, a sixth of one twice as long and a twentieth at four times; at their
/// edges, where the window is one-sided, the plane follows a slope that a mean would lag (and leave
/// as a band of tilted normals along the edge). Then every 4-connected component's minimum is 0
/// again. A drift of the integration (slopes read slightly wrong over a large area) is such a form;
/// the detail is not.
///
/// @param[in,out] depth   H x W, pixel units (x = column, y = -row).
/// @param[in] mask        H x W.
/// @param[in] detail_size pixels, > 0.
void damp_large_forms(ImageF& depth, const Mask& mask, double detail_size);

}  // namespace shadecut
