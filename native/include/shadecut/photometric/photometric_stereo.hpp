// Calibrated photometric stereo: several photographs from one viewpoint, each under its own known
// distant light, give the normal and the albedo of every pixel lit in three or more of them.
#pragma once

#include <shadecut/support/progress.hpp>
#include <shadecut/support/types.hpp>

#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <vector>

namespace shadecut {

/// K x 3 light directions, one row per photograph, toward the light, camera frame (any length > 0).
using LightDirections = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;

/// H x W counts, row-major.
using CountImage = Eigen::Array<std::int32_t, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

/// Lights whose directions are closer than this (degrees) give the same equation to within any
/// photograph's noise: the second of the two photographs adds nothing and is refused.
constexpr double kSameLightDegrees = 0.1;

/// Lamps near the subject (a desk lamp, a flash): lamp k stands at `centre` + `distance` S_k, S_k the
/// unit light of photograph k, so the direction toward it changes across the frame, and its strength
/// falls with the squared distance, equal to a distant light's at `distance`. A distant light is a
/// lamp infinitely far (`distance` 0 here).
struct NearLamps {
  double distance = 0.0;  ///< pixel units, > 0; 0 = distant lights
  /// Camera frame, pixel units, where pixel (r, c) of the surface is (c, -r, depth(r, c)).
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  ImageF depth;  ///< H x W, pixel units: the surface's depth; empty = 0 everywhere
};

/// A pixel where four photographs are usable and one misses the others' fit (a highlight, a cast
/// shadow). Any three of the four fit exactly, so the four cannot say which one to leave out:
/// normals[i] is the unit normal of the three without the i-th of the four (in the photographs'
/// order), and cost[i] the physics' case against leaving that one out: 1 - n . H, H its half vector,
/// where it is brighter than the three predict (a highlight lies where H meets the normal);
/// max(0, n . S) where it is darker (a cast shadow, likeliest where its light grazes).
struct FourFits {
  int pixel = 0;  ///< row-major index
  std::array<Eigen::Vector3f, 4> normals;
  std::array<float, 4> cost{};
};

struct PhotometricStereoParams {
  /// A photograph is in shadow at a pixel where its intensity is below shadow_fraction times the
  /// pixel's albedo, i.e. where the light grazes the surface by less than asin(shadow_fraction)
  /// (5.7 degrees at 0.1): there noise, ambient light and bounces outweigh the Lambertian shading.
  double shadow_fraction = 0.1;
  /// With four or more usable photographs, when one of them differs from what the fit of the others
  /// predicts by more than outlier_tolerance times the albedo, the fit drops the photograph that
  /// disagrees (a highlight or a cast shadow), one at a time while three or more remain.
  double outlier_tolerance = 0.05;
  /// The albedo the two candidate normals of a pixel with exactly two usable photographs assume.
  /// 0 = the mean albedo of the nearest pixels (4-neighbour steps inside the mask) where three or more
  /// photographs are usable; where there are none, the smallest uniform albedo that is consistent
  /// with all but one percent of the two-photograph pixels (kTwoLightAlbedoQuantile).
  double albedo = 0.0;
  /// Empty, or H x W finite: per pixel, the albedo the two candidates assume, in place of `albedo`
  /// (an albedo known from elsewhere: another set of photographs, a painted reference); where it is
  /// <= 0 the uniform estimate that `albedo` = 0 describes.
  ImageF albedo_map;
  /// Lamps near the subject in place of distant lights: each pixel is read under its own directions
  /// toward them and their strengths there.
  NearLamps lamps;
  int threads = 0;  ///< threads of the per-pixel fits; 0 = all cores
};

/// The share of two-photograph pixels whose two cones an estimated uniform albedo makes meet.
constexpr double kTwoLightAlbedoQuantile = 0.99;

struct PhotometricStereoResult {
  /// H x W unit normals where three or more photographs are usable (the least-squares fit over them);
  /// (0, 0, 0) elsewhere.
  NormalMap normals;
  /// H x W: the fitted albedo (three or more photographs), the albedo the two candidates assume (two),
  /// 0 elsewhere. Same units as the images' intensity.
  ImageF albedo;
  /// H x W: RMS over the usable photographs of (intensity - albedo n . S), intensity units; 0 where
  /// fewer than three are usable, rounding error where three are (the fit is exact).
  ImageF residual;
  /// H x W: the photographs used at each pixel, after shadows, clipped pixels and outliers were left
  /// out; 0 outside the mask.
  CountImage usable;
  /// H x W: at pixels with exactly two usable photographs, the two unit normals n with
  /// albedo n . S_i = I_i for both (the two cones' intersections, mirror images across the plane of
  /// the two lights; `first` on the side of that plane toward the viewer, so it faces the viewer more
  /// than `second` does, and the naming is the same at every pixel of the same pair). Where the
  /// cones do not meet (the albedo is too low for the two intensities) both hold the nearest normal,
  /// in the lights' plane. (0, 0, 0) elsewhere.
  NormalMap first_candidate, second_candidate;
  /// H x W, at the same pixels: how much light each candidate would catch where the photographs are
  /// dark, sum over the other photographs (not clipped) of max(0, n . S_k - I_k / albedo). Near 0 for
  /// the true normal where the darkness is its own shadow (it faces away from those lights); a cast
  /// shadow darkens a photograph whatever the normal, so this is evidence, not a rule. 0 elsewhere.
  ImageF first_shadow_conflict, second_shadow_conflict;
  /// The pixels whose fit chose which of four photographs to leave out, by pixel index (few: kept
  /// sparse); `normals` holds the cheapest of each one's four fits.
  std::vector<FourFits> four_fits;
  std::int64_t dark_pixels = 0;    ///< masked pixels with no usable photograph (dark in every one)
  std::int64_t single_pixels = 0;  ///< masked pixels with exactly one usable photograph
  std::int64_t pair_pixels = 0;    ///< masked pixels with exactly two
};

/// Per-pixel photometric stereo under distant lights, I_k = albedo max(0, n . S_k), or near lamps
/// (PhotometricStereoParams::lamps), I_k = albedo max(0, n . L_k) (distance / |lamp - point|)^2 with
/// L_k the unit direction from the pixel's point toward lamp k.
///
/// At every masked pixel, the photographs that are usable there (not clipped, not in shadow:
/// PhotometricStereoParams::shadow_fraction, judged against the albedo of a first fit and refitted)
/// give, if three or more, n and the albedo by least squares; with four or more the fit drops
/// outliers (PhotometricStereoParams::outlier_tolerance; where it chose among four, the four fits are
/// kept: four_fits). Two give two candidate normals, one or none nothing (usable says which).
///
/// @param[in] images  K >= 2 photographs, each H x W linear intensity on one common scale (divide
///                    each by its light's intensity first), finite.
/// @param[in] lights  K x 3, row k toward the light of images[k], camera frame (normalized here);
///                    every light above the horizon (S_z > 0), no two the same (kSameLightDegrees).
/// @param[in] mask    H x W, the pixels of the surface (at least one).
/// @param[in] clipped empty, or K masks H x W: true where images[k] is clipped (saturated) or known
///                    to be specular, never used there.
/// @param[in] params  thresholds.
/// @param[in] progress told the fraction of rows done, as stage "photometric stereo"; may throw
///                    Cancelled.
/// @throws InvalidArgument for fewer than two images, images of different sizes, a number of lights
///         other than the number of images, a light at or below the horizon, two identical lights,
///         a mask or clipped mask of another shape, non-finite pixels, or params out of range.
PhotometricStereoResult photometric_stereo(const std::vector<ImageF>& images, const LightDirections& lights,
                                           const Mask& mask, const std::vector<Mask>& clipped = {},
                                           const PhotometricStereoParams& params = {},
                                           const Progress& progress = {});

}  // namespace shadecut
