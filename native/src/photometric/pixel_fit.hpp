// Internal to photometric_stereo: the fit of one pixel, and the two candidate normals of the pixels
// where only two photographs are usable. Not part of the public API.
#pragma once

#include <shadecut/photometric/photometric_stereo.hpp>

#include "photometric/pixel_lights.hpp"

#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <unordered_map>
#include <vector>

namespace shadecut::detail {

/// The two photographs usable at a pixel, a < b, and their intensities; a = -1 where there are not two.
struct UsablePair {
  std::int32_t a = -1, b = -1;
  float intensity_a = 0.0f, intensity_b = 0.0f;
};

struct PixelFit {
  int usable = 0;                                       ///< photographs used
  Eigen::Vector3d scaled_normal = Eigen::Vector3d::Zero();  ///< albedo * n (usable >= 3)
  double rms = 0.0;                                     ///< RMS residual of the fit (usable >= 3)
  UsablePair pair;                                      ///< usable == 2
  bool has_four_fits = false;                           ///< the outlier was one of four
  FourFits four_fits;                                   ///< has_four_fits (its pixel not set)
};

/// Fits pixels one at a time, reusing its buffers; one per thread.
class PixelFitter {
 public:
  /// @param[in] lights the lights of each pixel, one per photograph; moved to every pixel fitted.
  PixelFitter(PixelLights& lights, double shadow_fraction, double outlier_tolerance);

  /// The fit at pixel (r, c) of `images` (clipped: empty or one mask per photograph), the intensities
  /// read at the lights' strengths there.
  PixelFit fit(const std::vector<ImageF>& images, const std::vector<Mask>& clipped, int r, int c);

 private:
  // (sum over the set of S S^T)^-1, and whether the set's lights fix a normal; cached per set while
  // the lights are the same at every pixel. For each photograph k of a solvable set, indexed by k:
  // spread[k] = A^-1 S_k and free[k] = 1 - S_k . A^-1 S_k (one minus its leverage), which the
  // leave-one-out identities read at every pixel of the set.
  struct SetInverse {
    bool solvable = false;
    double determinant = 0.0;
    Eigen::Matrix3d inverse = Eigen::Matrix3d::Zero();
    std::vector<Eigen::Vector3d> spread;
    std::vector<double> free;
  };
  const SetInverse& set_inverse(const std::vector<int>& set);

  bool solve(const std::vector<int>& set, Eigen::Vector3d& scaled_normal);
  double rms(const std::vector<int>& set, const Eigen::Vector3d& scaled_normal) const;
  void select_lit(double threshold);
  double largest_deviation(const Eigen::Vector3d& scaled_normal);
  void drop_outliers(Eigen::Vector3d& scaled_normal);
  int outlier(const Eigen::Vector3d& scaled_normal);
  int best_left_out(const Eigen::Vector3d& scaled_normal);
  double outlier_cost(int i, const Eigen::Vector3d& scaled) const;

  const Eigen::Vector3d& light(int k) const { return lights_.directions()[std::size_t(k)]; }

  PixelLights& lights_;
  double shadow_fraction_, outlier_tolerance_;
  std::vector<double> intensity_;
  std::vector<int> available_, used_, previous_, trial_;
  // outlier()'s four three-photograph fits, kept when it chose among four.
  FourFits four_fits_;
  bool has_four_fits_ = false;
  // The sets met so far, by their bits (photographs 0..63); more photographs are not cached.
  std::unordered_map<std::uint64_t, SetInverse> inverses_;
  // The last set looked up: the next pixel's is mostly the same (the map's nodes never move).
  std::uint64_t last_bits_ = 0;
  const SetInverse* last_ = nullptr;
  SetInverse uncached_;
};

/// photometric_stereo's checks of its photographs, lights and masks; returns the unit lights.
std::vector<Eigen::Vector3d> checked_photometric_input(const std::vector<ImageF>& images, const LightDirections& lights,
                                                       const Mask& mask, const std::vector<Mask>& clipped);

/// Fills result.first_candidate, second_candidate, their shadow conflicts and the albedo at the pixels
/// where pairs[p].a >= 0, with the albedo PhotometricStereoParams::albedo_map or albedo describe.
void resolve_pairs(const std::vector<UsablePair>& pairs, const std::vector<ImageF>& images,
                   const std::vector<Mask>& clipped, PixelLights& lights, const Mask& mask,
                   const PhotometricStereoParams& params, PhotometricStereoResult& result);

}  // namespace shadecut::detail
