// Conversions between numpy arrays and the core's images, masks and normal maps, with the shape
// checks every bound function shares.
#pragma once

#include <shadecut/support/types.hpp>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <optional>
#include <vector>

namespace shadecut::python {

using FloatArray = pybind11::array_t<float, pybind11::array::c_style | pybind11::array::forcecast>;
using BoolArray = pybind11::array_t<bool, pybind11::array::c_style | pybind11::array::forcecast>;

ImageF to_image(const FloatArray& array, const char* what);
/// An (H, W, 3) array as a colour image.
ColourImage to_colour(const FloatArray& array, const char* what);
/// Refuses an image that is neither (H, W) intensity nor (H, W, 3) RGB by its dimensions, before
/// the caller reads it as one or the other.
void require_grey_or_colour(const FloatArray& array);
std::optional<Mask> to_mask(const std::optional<BoolArray>& array);
/// The mask, or every pixel of a rows x cols image when there is none.
Mask mask_or_all(const std::optional<BoolArray>& array, Eigen::Index rows, Eigen::Index cols);
NormalMap to_normals(const FloatArray& array);
Eigen::Vector3d to_vector3(const std::vector<double>& values, const char* what);

pybind11::array_t<float> from_image(const ImageF& image);
pybind11::array_t<bool> from_mask(const Mask& mask);
pybind11::array_t<float> from_normals(const NormalMap& normals);
/// (H, W, 3); None for a colour image without channels.
pybind11::object from_colour(const ColourImage& colour);

}  // namespace shadecut::python
