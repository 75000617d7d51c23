// One photograph of the scene with the light that shaded it: the input of a reconstruction is a list
// of these (one photograph is a list of one).
#pragma once

#include <shadecut/support/types.hpp>

#include <Eigen/Core>

#include <optional>

namespace shadecut {

struct Observation {
  /// H x W linear intensity (>= 2 x 2, finite, >= 0): the luminance of `colour` when that is given.
  ImageF image;
  /// H x W x 3 linear RGB under one white light, or empty (0 x 0 channels) for a grey photograph.
  ColourImage colour;
  /// Direction toward the light, camera frame, S_z > 0 (normalized by reconstruct()), or
  /// std::nullopt: estimated from the image.
  std::optional<Eigen::Vector3d> light;

  bool has_colour() const { return colour.channel[0].size() > 0; }
};

/// A grey photograph.
Observation grey_observation(ImageF image, const std::optional<Eigen::Vector3d>& light);

/// A colour photograph: its intensity is its Rec. 709 luminance. Throws InvalidArgument when the
/// channels differ in shape or hold negative or non-finite values.
Observation colour_observation(ColourImage colour, const std::optional<Eigen::Vector3d>& light);

/// Rec. 709 luminance of a colour image (kLuminanceWeights): the intensity the shape is read from.
ImageF luminance(const ColourImage& colour);

}  // namespace shadecut
