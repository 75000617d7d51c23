// Input checks shared by every entry point, so that every layer rejects bad input with one message.
#pragma once

#include <shadecut/support/types.hpp>

#include <cstddef>
#include <string>

namespace shadecut {

/// Throws InvalidArgument unless `image` is at least 2 x 2 and every pixel is finite.
void check_image(const ImageF& image, const std::string& what = "image");

/// Throws InvalidArgument unless `mask` has the shape of `image` and selects at least one pixel.
void check_mask(const Mask& mask, const ImageF& image);

/// Throws InvalidArgument, naming the mask first, unless `mask` has the shape of `normals`, and when a
/// normal inside the mask is NaN or infinite.
void check_mask_fits(const Mask& mask, const NormalMap& normals);

/// Throws InvalidArgument unless `normals` is rows x cols.
void check_normals(const NormalMap& normals, int rows, int cols);

/// `value` for a message: six significant digits ("1e+300", "0.001"), not std::to_string's fixed
/// notation, which prints 1e300 in 301 digits and 1e-9 as 0.000000.
std::string number_text(double value);

/// How a message names the photograph at `index` of a list: "photograph 3" for index 2, counted from
/// 1 as a user counts the images they gave.
std::string photograph_name(std::size_t index);

/// Throws InvalidArgument unless `photograph`, at `index` of a list of photographs of one view, has the
/// size of the list's `first`; the message names it as photograph_name does.
void check_same_size(const ImageF& photograph, std::size_t index, const ImageF& first);

/// Throws InvalidArgument unless the albedo is finite and > 0.
void check_albedo(double albedo);

/// Throws InvalidArgument unless an iterative method is given at least one iteration.
void check_iterations(int iterations);

/// The checks of an iterative method that reads an image under a mask with an albedo (tsai_shah, upwind).
void check_iterative_input(const ImageF& image, const Mask& mask, double albedo, int iterations);

}  // namespace shadecut
