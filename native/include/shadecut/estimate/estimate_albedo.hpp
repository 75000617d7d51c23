// The albedo of a uniformly coloured object when none is given: the brightness of a pixel facing the
// light, read robustly from the image.
#pragma once

#include <shadecut/support/types.hpp>

#include <string>
#include <vector>

namespace shadecut {

enum class AlbedoMethod {
  /// "brightest": the largest value of the 3 x 3 median-filtered image. Exact on a clean Lambertian
  /// image with a pixel facing the light; a highlight or a saturated spot larger than a pixel
  /// becomes the albedo.
  Brightest,
  /// "top_fit": around the normal that faces the light, the share A of a smooth object brighter than
  /// t = albedo cos(theta) grows like sin^2(theta) (exactly so on a sphere, to second order on any
  /// smooth surface whose Gauss map is regular there), so t^2 falls linearly with A and reaches
  /// albedo^2 at A = 0. A line fitted to the squared sorted intensities against their share of the
  /// mask, within TopFitWindow, gives the albedo. Highlights and saturated pixels brighter than the
  /// window's start do not move it. Under an oblique light the cap reaches the limb within the window
  /// and the fit falls short (docs/method.md#albedo), so where the brightest value
  /// exceeds the fit by no more than TopFitWindow::agreement (the image shows no highlight), the
  /// brightest value is taken: exact on a clean image.
  TopFit,
  /// "retinex": paint separated from shading, a reflectance per pixel (estimate_reflectance.hpp);
  /// reconstruct() reads the albedo of the shading image that leaves by top_fit. Not a single value:
  /// estimate_albedo() refuses it.
  Retinex,
};

/// The window of top_fit, as shares of the mask's area (brightest first). The defaults were chosen
/// by scripts/tune_parameters.py --albedo on training renders with highlights (docs/parameters.md).
struct TopFitWindow {
  double from = 0.2;
  double to = 0.6;
  double agreement = 0.3;  ///< relative excess of the brightest value over the fit still taken as clean
};

/// Every method's name, in the order of the enum.
const std::vector<std::string>& albedo_method_names();
AlbedoMethod parse_albedo_method(const std::string& name);
std::string to_string(AlbedoMethod method);

/// Estimates the albedo from the masked pixels.
///
/// @param[in] image  H x W linear intensity (>= 2 x 2, finite).
/// @param[in] mask   H x W pixels of the object.
/// @param[in] method see AlbedoMethod. top_fit falls back to brightest when the window holds fewer
///                   than 3 pixels.
/// @param[in] window top_fit's window, 0 <= from < to <= 1, agreement >= 0.
/// @throws InvalidArgument for bad input, a bad window or an image dark everywhere in the mask.
double estimate_albedo(const ImageF& image, const Mask& mask, AlbedoMethod method = AlbedoMethod::TopFit,
                       const TopFitWindow& window = {});

}  // namespace shadecut
