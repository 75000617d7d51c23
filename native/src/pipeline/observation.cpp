#include <shadecut/pipeline/observation.hpp>

#include <shadecut/support/errors.hpp>
#include <shadecut/support/validate.hpp>

#include <utility>

namespace shadecut {

ImageF luminance(const ColourImage& colour) {
  for (const ImageF& channel : colour.channel)
    if (channel.rows() != colour.rows() || channel.cols() != colour.cols())
      throw InvalidArgument("shadecut: the colour image's channels differ in shape");
  return (colour.channel[0].cast<double>() * kLuminanceWeights[0] + colour.channel[1].cast<double>() * kLuminanceWeights[1] +
          colour.channel[2].cast<double>() * kLuminanceWeights[2])
      .cast<float>();
}

Observation grey_observation(ImageF image, const std::optional<Eigen::Vector3d>& light) {
  Observation observation;
  observation.image = std::move(image);
  observation.light = light;
  return observation;
}

Observation colour_observation(ColourImage colour, const std::optional<Eigen::Vector3d>& light) {
  Observation observation;
  observation.image = luminance(colour);
  for (const ImageF& channel : colour.channel) {
    check_image(channel);
    if (channel.minCoeff() < 0.0f) throw InvalidArgument("shadecut: the image has negative values; linear RGB is >= 0");
  }
  observation.colour = std::move(colour);
  observation.light = light;
  return observation;
}

}  // namespace shadecut
