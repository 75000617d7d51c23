// The de-lit colour against the paint the photographs were rendered with.
#include "photometric/photometric_scenes.hpp"

#include <shadecut/photometric/colour_albedo.hpp>
#include <shadecut/support/angular_error.hpp>
#include <shadecut/support/errors.hpp>
#include <shadecut/pipeline/observation.hpp>

#include <gtest/gtest.h>

#include <limits>

namespace shadecut {
namespace {

using testing::lights_around;

// Four colour photographs of a sphere painted (0.8, 0.5, 0.2) times painted_albedo, with a sharp
// white highlight in each: its luminance is what photometric_stereo reads.
struct ColourSet {
  testing::Scene scene;
  LightDirections lights;
  std::vector<ColourImage> photographs;
  ColourImage paint;
};

ColourSet painted_sphere() {
  ColourSet set{testing::sphere_scene(96, 0.45, {0, 0, 1}), lights_around(4, 40.0, 90.0, 90.0), {}, {}};
  const ImageF pattern = testing::painted_albedo(96, 96);
  const float tint[3] = {0.8f, 0.5f, 0.2f};
  for (int ch = 0; ch < 3; ++ch) set.paint.channel[std::size_t(ch)] = tint[ch] * pattern;
  for (Eigen::Index k = 0; k < set.lights.rows(); ++k) {
    const ImageF shade = render_lambertian(set.scene.normals, set.lights.row(k).transpose(), 1.0, set.scene.mask);
    const Eigen::Vector3d half = (set.lights.row(k).transpose().normalized() + Eigen::Vector3d::UnitZ()).normalized();
    ImageF highlight = ImageF::Zero(96, 96);
    for (Eigen::Index p = 0; p < set.scene.normals.size(); ++p)
      if (set.scene.mask.data()[p])
        highlight.data()[p] = float(0.5 * std::pow(std::max(0.0, set.scene.normals.xyz.row(p).cast<double>().dot(half)), 200.0));
    ColourImage photo;
    for (int ch = 0; ch < 3; ++ch) photo.channel[std::size_t(ch)] = set.paint.channel[std::size_t(ch)] * shade + highlight;
    set.photographs.push_back(photo);
  }
  return set;
}

// The largest difference, over the sphere without its outline and the channels, from the paint.
double worst_paint_error(const ColourImage& albedo, const ColourSet& set) {
  double worst = 0.0;
  const Mask inner = erode_mask(set.scene.mask, 3);
  for (int ch = 0; ch < 3; ++ch)
    for (Eigen::Index p = 0; p < inner.size(); ++p)
      if (inner.data()[p])
        worst = std::max(worst, double(std::abs(albedo.channel[std::size_t(ch)].data()[p] -
                                                set.paint.channel[std::size_t(ch)].data()[p])));
  return worst;
}

TEST(ColourAlbedo, ThePaintUnderTheTrueNormalsHighlightsLeftOut) {
  const ColourSet set = painted_sphere();
  const PhotometricStereoParams params;
  PhotometricStereoParams keep_all;
  keep_all.outlier_tolerance = std::numeric_limits<double>::max();
  const ColourImage albedo = photometric_colour_albedo(set.photographs, set.lights, set.scene.normals, set.scene.mask);
  const ColourImage with_highlights = photometric_colour_albedo(set.photographs, set.lights, set.scene.normals,
                                                                set.scene.mask, {}, keep_all);
  // What a highlight below the tolerance leaves in, at most.
  EXPECT_LT(worst_paint_error(albedo, set), params.outlier_tolerance);
  EXPECT_GT(worst_paint_error(with_highlights, set), 2.0 * params.outlier_tolerance);
  EXPECT_EQ(albedo.channel[0](0, 0), 0.0f);  // outside the mask
}

// Grey photographs follow the same rules in one channel: the luminance of the colour fit, highlights
// left out the same way.
TEST(ColourAlbedo, GreyPhotographsGiveTheLuminanceOfTheColourFit) {
  const ColourSet set = painted_sphere();
  std::vector<ImageF> grey;
  for (const ColourImage& photo : set.photographs) grey.push_back(luminance(photo));
  const ImageF albedo = photometric_albedo(grey, set.lights, set.scene.normals, set.scene.mask);
  const ImageF expected = luminance(photometric_colour_albedo(set.photographs, set.lights, set.scene.normals, set.scene.mask));
  EXPECT_LT((albedo - expected).abs().maxCoeff(), 1e-5f);
  EXPECT_THROW(photometric_albedo(grey, set.lights.topRows(3), set.scene.normals, set.scene.mask), InvalidArgument);
}

TEST(ColourAlbedo, RefusesBadInput) {
  const ColourSet set = painted_sphere();
  EXPECT_THROW(photometric_colour_albedo(set.photographs, set.lights, NormalMap(96, 95), set.scene.mask), InvalidArgument);
  EXPECT_THROW(photometric_colour_albedo(set.photographs, set.lights.topRows(3), set.scene.normals, set.scene.mask),
               InvalidArgument);
  auto uneven = set.photographs;
  uneven[1].channel[2] = ImageF::Zero(96, 90);
  EXPECT_THROW(photometric_colour_albedo(uneven, set.lights, set.scene.normals, set.scene.mask), InvalidArgument);
}

}  // namespace
}  // namespace shadecut
