// Internal to photometric stereo: the lights one pixel sees, distant or near. Not part of the public API.
#pragma once

#include <shadecut/photometric/photometric_stereo.hpp>

#include <Eigen/Core>

#include <vector>

namespace shadecut::detail {

/// The unit directions toward the lights at a pixel and their strengths there: the distant lights'
/// (strength 1) everywhere, or those of near lamps (NearLamps), which at() moves to a pixel.
class PixelLights {
 public:
  /// @param[in] distant unit directions, one per photograph; the lamps' directions from their centre.
  /// @param[in] lamps   distance 0 for distant lights; depth empty or the photographs' size.
  PixelLights(const std::vector<Eigen::Vector3d>& distant, const NearLamps& lamps);

  bool near() const { return lamps_.distance > 0.0; }
  /// Moves to pixel (r, c): a no-op for distant lights.
  void at(int r, int c);
  const std::vector<Eigen::Vector3d>& directions() const { return near() ? directions_ : distant_; }
  /// Lamp k's strength at the pixel over its strength at `distance`.
  double strength(std::size_t k) const { return near() ? strengths_[k] : 1.0; }

 private:
  const std::vector<Eigen::Vector3d>& distant_;
  const NearLamps& lamps_;
  std::vector<Eigen::Vector3d> directions_;
  std::vector<double> strengths_;
};

/// NearLamps' checks against photographs of `rows` x `cols`.
void check_lamps(const NearLamps& lamps, int rows, int cols);

}  // namespace shadecut::detail
