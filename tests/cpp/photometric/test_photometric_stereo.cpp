// Calibrated photometric stereo against exact synthetic truth.
#include "photometric/photometric_scenes.hpp"

#include <shadecut/photometric/photometric_stereo.hpp>
#include <shadecut/support/errors.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace shadecut {
namespace {

using testing::degrees_between;
using testing::lights_around;
using testing::painted_albedo;
using testing::photographs;

struct Errors {
  double mean = 0.0, worst = 0.0;
  int pixels = 0;
};

// Angular errors of the fitted normals over the pixels where `usable` satisfies `keep`.
template <class Keep>
Errors fitted_errors(const PhotometricStereoResult& result, const NormalMap& truth, Keep keep) {
  Errors errors;
  for (Eigen::Index p = 0; p < truth.size(); ++p) {
    if (!keep(result.usable.data()[p])) continue;
    const double e = degrees_between(result.normals.xyz.row(p), truth.xyz.row(p));
    errors.mean += e;
    errors.worst = std::max(errors.worst, e);
    ++errors.pixels;
  }
  if (errors.pixels > 0) errors.mean /= errors.pixels;
  return errors;
}

TEST(PhotometricStereo, FourLightsGiveExactNormalsAndPaintWhereThreeOrMoreAreLit) {
  const auto scene = testing::sphere_scene(96, 0.45, {0, 0, 1});
  const LightDirections lights = lights_around(4, 40.0, 90.0, 90.0);
  const ImageF albedo = painted_albedo(96, 96);
  const auto result = photometric_stereo(photographs(scene, lights, albedo), lights, scene.mask);
  const Errors three_or_more = fitted_errors(result, scene.normals, [](int n) { return n >= 3; });
  const Errors exactly_three = fitted_errors(result, scene.normals, [](int n) { return n == 3; });
  EXPECT_GT(three_or_more.pixels, int(0.8 * scene.mask.count()));
  EXPECT_GT(exactly_three.pixels, 100);  // the sphere's rim is shadowed from the opposite light
  EXPECT_LT(three_or_more.worst, 0.05);  // float32 photographs
  double worst_albedo = 0.0, worst_residual = 0.0;
  for (Eigen::Index p = 0; p < scene.normals.size(); ++p)
    if (result.usable.data()[p] >= 3) {
      worst_albedo = std::max(worst_albedo, double(std::abs(result.albedo.data()[p] - albedo.data()[p])));
      worst_residual = std::max(worst_residual, double(result.residual.data()[p]));
    }
  EXPECT_LT(worst_albedo, 1e-4);
  EXPECT_LT(worst_residual, 1e-4);
  EXPECT_EQ(result.dark_pixels, 0);
  EXPECT_EQ((result.usable > 0).count(), scene.mask.count());
}

// A Blinn-Phong highlight of shininess 200 on top of the Lambertian shading of each photograph: sharp
// enough that no two of the four photographs shine at one pixel (one outlier at most).
std::vector<ImageF> with_highlights(std::vector<ImageF> images, const testing::Scene& scene,
                                    const LightDirections& lights, double strength) {
  for (std::size_t k = 0; k < images.size(); ++k) {
    const Eigen::Vector3d half = (lights.row(Eigen::Index(k)).transpose().normalized() + Eigen::Vector3d::UnitZ()).normalized();
    for (Eigen::Index p = 0; p < scene.normals.size(); ++p)
      if (scene.mask.data()[p])
        images[k].data()[p] += float(strength * std::pow(std::max(0.0, scene.normals.xyz.row(p).cast<double>().dot(half)), 200.0));
  }
  return images;
}

TEST(PhotometricStereo, HighlightsAmongFourPhotographsAreLeftOut) {
  const auto scene = testing::sphere_scene(96, 0.45, {0, 0, 1});
  const LightDirections lights = lights_around(4, 40.0, 90.0, 90.0);
  const auto images = with_highlights(photographs(scene, lights, painted_albedo(96, 96)), scene, lights, 0.5);
  PhotometricStereoParams plain;
  plain.outlier_tolerance = std::numeric_limits<double>::max();
  const Errors robust = fitted_errors(photometric_stereo(images, lights, scene.mask), scene.normals, [](int n) { return n >= 3; });
  const Errors least_squares = fitted_errors(photometric_stereo(images, lights, scene.mask, {}, plain), scene.normals,
                                             [](int n) { return n >= 3; });
  EXPECT_GT(least_squares.mean, 0.5);
  EXPECT_LT(robust.mean, 0.15 * least_squares.mean);
}

TEST(PhotometricStereo, WhereOneOfFourIsLeftOutItsFourFitsAreKept) {
  const auto scene = testing::sphere_scene(96, 0.45, {0, 0, 1});
  const LightDirections lights = lights_around(4, 40.0, 90.0, 90.0);
  const auto clean = photometric_stereo(photographs(scene, lights, painted_albedo(96, 96)), lights, scene.mask);
  EXPECT_TRUE(clean.four_fits.empty());  // nothing to choose
  const auto images = with_highlights(photographs(scene, lights, painted_albedo(96, 96)), scene, lights, 0.5);
  const auto result = photometric_stereo(images, lights, scene.mask);
  int kept = 0, previous = -1;
  for (const FourFits& fits : result.four_fits) {
    const int p = fits.pixel;
    EXPECT_GT(p, previous);  // in pixel order, each once
    previous = p;
    ++kept;
    const std::size_t cheapest = std::size_t(std::min_element(fits.cost.begin(), fits.cost.end()) - fits.cost.begin());
    double nearest = 180.0;
    for (std::size_t i = 0; i < 4; ++i) nearest = std::min(nearest, degrees_between(fits.normals[i], scene.normals.xyz.row(p)));
    EXPECT_EQ(result.usable.data()[p], 3);
    EXPECT_LT(degrees_between(result.normals.xyz.row(p), fits.normals[cheapest]), 1e-3);
    EXPECT_LT(nearest, 0.05);  // the three without the highlight
  }
  EXPECT_GT(kept, 50);
}

TEST(PhotometricStereo, ACastShadowAmongFivePhotographsIsLeftOut) {
  const auto scene = testing::sphere_scene(96, 0.45, {0, 0, 1});
  const LightDirections lights = lights_around(5, 35.0, 90.0, 72.0);
  auto images = photographs(scene, lights, painted_albedo(96, 96));
  // Another object's shadow over a disc of photograph 2: a third of its light.
  for (int r = 30; r < 60; ++r)
    for (int c = 30; c < 60; ++c)
      if ((r - 45) * (r - 45) + (c - 45) * (c - 45) < 225) images[2](r, c) *= 0.35f;
  const auto result = photometric_stereo(images, lights, scene.mask);
  const Errors errors = fitted_errors(result, scene.normals, [](int n) { return n >= 3; });
  EXPECT_LT(errors.worst, 0.05);
  EXPECT_EQ(result.usable(45, 45), 4);
}

// Over the pixels with two usable photographs, the largest angle between the truth and the nearer
// of the two candidates.
double worst_nearer_candidate(const PhotometricStereoResult& result, const NormalMap& truth) {
  double worst = 0.0;
  for (Eigen::Index p = 0; p < truth.size(); ++p)
    if (result.usable.data()[p] == 2)
      worst = std::max(worst, std::min(degrees_between(result.first_candidate.xyz.row(p), truth.xyz.row(p)),
                                       degrees_between(result.second_candidate.xyz.row(p), truth.xyz.row(p))));
  return worst;
}

TEST(PhotometricStereo, TwoPhotographsGiveTwoCandidatesOneOfThemTrue) {
  const auto scene = testing::sphere_scene(96, 0.45, {0, 0, 1});
  const LightDirections lights = lights_around(2, 45.0, 0.0, 100.0);
  PhotometricStereoParams params;
  params.albedo = 0.8;
  const ImageF albedo = ImageF::Constant(96, 96, 0.8f);
  const auto result = photometric_stereo(photographs(scene, lights, albedo), lights, scene.mask, {}, params);
  ASSERT_GT(result.pair_pixels, 1000);
  int first_faces_viewer = 0;
  for (Eigen::Index p = 0; p < scene.normals.size(); ++p)
    first_faces_viewer += result.usable.data()[p] == 2 &&
                          result.first_candidate.xyz(p, 2) >= result.second_candidate.xyz(p, 2) - 1e-6f;
  EXPECT_LT(worst_nearer_candidate(result, scene.normals), 0.05);
  EXPECT_EQ(first_faces_viewer, result.pair_pixels);
  EXPECT_EQ(result.pair_pixels + result.single_pixels + result.dark_pixels, scene.mask.count());
}

// Where the other photographs are dark because the surface faces away from their lights, the true
// candidate would catch none of their light; its mirror image across the pair's plane often would.
TEST(PhotometricStereo, TheTrueCandidateCatchesNoLightWhereTheOtherPhotographsAreDark) {
  const auto scene = testing::sphere_scene(96, 0.45, {0, 0, 1});
  const LightDirections lights = lights_around(4, 60.0, 90.0, 90.0);
  PhotometricStereoParams params;
  params.albedo = 0.8;
  const auto result =
      photometric_stereo(photographs(scene, lights, ImageF::Constant(96, 96, 0.8f)), lights, scene.mask, {}, params);
  ASSERT_GT(result.pair_pixels, 500);
  int mirror_catches_light = 0;
  for (Eigen::Index p = 0; p < scene.normals.size(); ++p) {
    if (result.usable.data()[p] != 2) continue;
    const bool first_is_true = degrees_between(result.first_candidate.xyz.row(p), scene.normals.xyz.row(p)) <
                               degrees_between(result.second_candidate.xyz.row(p), scene.normals.xyz.row(p));
    const float truth = first_is_true ? result.first_shadow_conflict.data()[p] : result.second_shadow_conflict.data()[p];
    const float mirror = first_is_true ? result.second_shadow_conflict.data()[p] : result.first_shadow_conflict.data()[p];
    EXPECT_LT(truth, 1e-4f) << "pixel " << p;
    mirror_catches_light += mirror > 0.05f;
  }
  EXPECT_GT(mirror_catches_light, result.pair_pixels / 2);
}

TEST(PhotometricStereo, TwoPhotographPixelsTakeTheAlbedoOfTheirThreeLightNeighbours) {
  const auto scene = testing::sphere_scene(96, 0.45, {0, 0, 1});
  const LightDirections lights = lights_around(3, 50.0, 90.0, 120.0);
  const auto result = photometric_stereo(photographs(scene, lights, ImageF::Constant(96, 96, 0.6f)), lights, scene.mask);
  ASSERT_GT(result.pair_pixels, 200);
  const double worst = worst_nearer_candidate(result, scene.normals);
  EXPECT_LT(worst, 0.1);
}

TEST(PhotometricStereo, TwoPhotographsOfPaintWithItsAlbedoGiven) {
  const auto scene = testing::sphere_scene(96, 0.45, {0, 0, 1});
  const LightDirections lights = lights_around(2, 45.0, 0.0, 100.0);
  PhotometricStereoParams params;
  params.albedo_map = painted_albedo(96, 96);
  const auto result = photometric_stereo(photographs(scene, lights, params.albedo_map), lights, scene.mask, {}, params);
  ASSERT_GT(result.pair_pixels, 1000);
  const double worst = worst_nearer_candidate(result, scene.normals);
  EXPECT_LT(worst, 0.05);
  params.albedo_map = ImageF::Ones(96, 95);
  EXPECT_THROW(photometric_stereo(photographs(scene, lights, ImageF::Ones(96, 96)), lights, scene.mask, {}, params),
               InvalidArgument);
}

TEST(PhotometricStereo, APixelDarkInEveryPhotographIsReportedNotFitted) {
  const auto scene = testing::sphere_scene(64, 0.45, {0, 0, 1});
  const LightDirections lights = lights_around(4, 40.0, 90.0, 90.0);
  auto images = photographs(scene, lights, ImageF::Constant(64, 64, 1.0f));
  for (auto& image : images) image(32, 32) = 0.0f;
  const auto result = photometric_stereo(images, lights, scene.mask);
  EXPECT_EQ(result.dark_pixels, 1);
  EXPECT_EQ(result.usable(32, 32), 0);
  EXPECT_EQ(result.normals.xyz.row(32 * 64 + 32).norm(), 0.0f);
  EXPECT_EQ(result.usable(32, 33), 4);
}

TEST(PhotometricStereo, ClippedPixelsAreNeverUsed) {
  const auto scene = testing::sphere_scene(64, 0.45, {0, 0, 1});
  const LightDirections lights = lights_around(4, 40.0, 90.0, 90.0);
  auto images = photographs(scene, lights, ImageF::Constant(64, 64, 1.0f));
  std::vector<Mask> clipped(4, Mask::Constant(64, 64, false));
  clipped[1](32, 32) = true;
  images[1](32, 32) = 5.0f;  // nonsense where clipped: must not matter
  const auto result = photometric_stereo(images, lights, scene.mask, clipped);
  EXPECT_EQ(result.usable(32, 32), 3);
  EXPECT_LT(degrees_between(result.normals.xyz.row(32 * 64 + 32), scene.normals.xyz.row(32 * 64 + 32)), 0.02);
}

TEST(PhotometricStereo, ReportsProgressAndStopsWhenTheCallerCancels) {
  const auto scene = testing::sphere_scene(160, 0.45, {0, 0, 1});
  const LightDirections lights = lights_around(4, 40.0, 90.0, 90.0);
  const auto images = photographs(scene, lights, ImageF::Constant(160, 160, 1.0f));
  std::vector<double> fractions;
  photometric_stereo(images, lights, scene.mask, {}, {}, Progress([&](double fraction, const std::string& stage) {
                       EXPECT_EQ(stage, "photometric stereo");
                       fractions.push_back(fraction);
                       return true;
                     }));
  ASSERT_GE(fractions.size(), 2u);
  EXPECT_TRUE(std::is_sorted(fractions.begin(), fractions.end()));
  EXPECT_DOUBLE_EQ(fractions.back(), 1.0);
  EXPECT_THROW(photometric_stereo(images, lights, scene.mask, {}, {}, Progress([](double, const std::string&) { return false; })),
               Cancelled);
}

TEST(PhotometricStereo, RefusesBadInput) {
  const auto scene = testing::sphere_scene(32, 0.45, {0, 0, 1});
  const LightDirections lights = lights_around(3, 40.0, 90.0, 120.0);
  const auto images = photographs(scene, lights, ImageF::Constant(32, 32, 1.0f));
  auto other_size = images;
  other_size[2] = ImageF::Zero(32, 31);
  try {
    photometric_stereo(other_size, lights, scene.mask);
    ADD_FAILURE() << "photographs of two sizes accepted";
  } catch (const InvalidArgument& error) {  // counted from 1, width x height, as the user gave them
    EXPECT_NE(std::string(error.what()).find("photograph 3 is 31 x 32 pixels but the first is 32 x 32"),
              std::string::npos) << error.what();
  }
  EXPECT_THROW(photometric_stereo({images[0], images[1]}, lights, scene.mask), InvalidArgument);
  EXPECT_THROW(photometric_stereo({images[0]}, lights.topRows(1), scene.mask), InvalidArgument);
  LightDirections same = lights;
  same.row(2) = 2.0 * lights.row(0);
  try {
    photometric_stereo(images, same, scene.mask);
    ADD_FAILURE() << "two identical lights accepted";
  } catch (const InvalidArgument& error) {
    EXPECT_NE(std::string(error.what()).find("adds nothing"), std::string::npos) << error.what();
  }
  LightDirections below = lights;
  below.row(1) << 1.0, 0.0, -0.2;
  EXPECT_THROW(photometric_stereo(images, below, scene.mask), InvalidArgument);
  auto with_nan = images;
  with_nan[0](3, 3) = std::numeric_limits<float>::quiet_NaN();
  EXPECT_THROW(photometric_stereo(with_nan, lights, scene.mask), InvalidArgument);
  EXPECT_THROW(photometric_stereo(images, lights, Mask::Constant(31, 32, true)), InvalidArgument);
  EXPECT_THROW(photometric_stereo(images, lights, scene.mask, {Mask::Constant(32, 32, false)}), InvalidArgument);
  PhotometricStereoParams negative;
  negative.albedo = -1.0;
  EXPECT_THROW(photometric_stereo(images, lights, scene.mask, {}, negative), InvalidArgument);
}

// Lambertian photographs of `scene` under lamps `distance` pixels from `centre` along `lights`, with
// the inverse-square falloff NearLamps describes: the physics written out here, apart from the library's.
std::vector<ImageF> near_lamp_photographs(const testing::Scene& scene, const LightDirections& lights, const ImageF& albedo,
                                          double distance, const Eigen::Vector3d& centre) {
  std::vector<ImageF> images;
  const int rows = int(scene.mask.rows()), cols = int(scene.mask.cols());
  for (Eigen::Index k = 0; k < lights.rows(); ++k) {
    const Eigen::Vector3d lamp = centre + distance * lights.row(k).transpose().normalized();
    ImageF image = ImageF::Zero(rows, cols);
    for (int r = 0; r < rows; ++r)
      for (int c = 0; c < cols; ++c) {
        if (!scene.mask(r, c)) continue;
        const Eigen::Vector3d toward = lamp - Eigen::Vector3d(c, -r, scene.depth(r, c));
        const Eigen::Vector3d n = scene.normals.xyz.row(r * cols + c).transpose().cast<double>();
        const double cosine = std::max(0.0, n.dot(toward.normalized()));
        image(r, c) = float(albedo(r, c) * cosine * std::pow(distance / toward.norm(), 2));
      }
    images.push_back(image);
  }
  return images;
}

TEST(PhotometricStereo, NearLampsGiveExactNormalsAcrossTheFrame) {
  const auto scene = testing::sphere_scene(96, 0.45, {0, 0, 1});
  const LightDirections lights = lights_around(4, 40.0, 90.0, 90.0);
  const ImageF albedo = painted_albedo(96, 96);
  NearLamps lamps;
  lamps.distance = 192.0;  // two frame widths: the directions differ by up to 20 degrees across the frame
  lamps.centre = Eigen::Vector3d(47.5, -47.5, 0.0);
  lamps.depth = scene.depth;
  const auto images = near_lamp_photographs(scene, lights, albedo, lamps.distance, lamps.centre);
  PhotometricStereoParams params;
  params.lamps = lamps;
  const auto near = photometric_stereo(images, lights, scene.mask, {}, params);
  const auto read_as_distant = photometric_stereo(images, lights, scene.mask);
  const Errors exact = fitted_errors(near, scene.normals, [](int n) { return n >= 3; });
  // Every pixel that faces three lamps by more than the shadow test's grazing angle is fitted.
  int facing_three = 0;
  for (int r = 0; r < 96; ++r)
    for (int c = 0; c < 96; ++c) {
      int facing = 0;
      for (Eigen::Index k = 0; k < lights.rows(); ++k) {
        const Eigen::Vector3d lamp = lamps.centre + lamps.distance * lights.row(k).transpose().normalized();
        const Eigen::Vector3d toward = (lamp - Eigen::Vector3d(c, -r, scene.depth(r, c))).normalized();
        facing += scene.normals.xyz.row(r * 96 + c).cast<double>().dot(toward) > PhotometricStereoParams{}.shadow_fraction;
      }
      facing_three += scene.mask(r, c) && facing >= 3;
    }
  EXPECT_NEAR(exact.pixels, facing_three, 0.01 * facing_three);
  EXPECT_LT(exact.worst, 0.05);  // float32 photographs
  EXPECT_GT(fitted_errors(read_as_distant, scene.normals, [](int n) { return n >= 3; }).mean, 5.0);
  double worst_albedo = 0.0;
  for (Eigen::Index p = 0; p < scene.normals.size(); ++p)
    if (near.usable.data()[p] >= 3)
      worst_albedo = std::max(worst_albedo, double(std::abs(near.albedo.data()[p] - albedo.data()[p])));
  EXPECT_LT(worst_albedo, 1e-4);
}

TEST(PhotometricStereo, RefusesBadLamps) {
  const auto scene = testing::sphere_scene(32, 0.45, {0, 0, 1});
  const LightDirections lights = lights_around(3, 40.0, 90.0, 120.0);
  const auto images = photographs(scene, lights, ImageF::Constant(32, 32, 1.0f));
  PhotometricStereoParams params;
  params.lamps.distance = -1.0;
  EXPECT_THROW(photometric_stereo(images, lights, scene.mask, {}, params), InvalidArgument);
  params.lamps.distance = 32.0;
  params.lamps.depth = ImageF::Zero(31, 32);
  try {
    photometric_stereo(images, lights, scene.mask, {}, params);
    ADD_FAILURE() << "a depth of another size accepted";
  } catch (const InvalidArgument& error) {
    EXPECT_NE(std::string(error.what()).find("depth does not have the photographs' size"), std::string::npos)
        << error.what();
  }
  params.lamps.depth = ImageF::Zero(32, 32);
  params.lamps.centre.x() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(photometric_stereo(images, lights, scene.mask, {}, params), InvalidArgument);
}

}  // namespace
}  // namespace shadecut
