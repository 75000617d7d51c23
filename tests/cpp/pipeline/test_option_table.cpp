#include "test_support.hpp"

#include <shadecut/pipeline/option_table.hpp>
#include <shadecut/pipeline/reconstruct.hpp>
#include <shadecut/support/angular_error.hpp>
#include <shadecut/support/errors.hpp>
#include <shadecut/support/render.hpp>

#include <gtest/gtest.h>

#include <set>
#include <string>

namespace shadecut {
namespace {

// Every field of ReconstructOptions is one row: the table's text of each default reads back as it.
TEST(OptionTable, EveryRowRoundTripsItsDefaultAsText) {
  std::set<std::string> names;
  const ReconstructOptions defaults;
  for (const OptionField& field : option_fields()) {
    EXPECT_TRUE(names.insert(field.name).second) << field.name;
    EXPECT_FALSE(field.help.empty()) << field.name;
    EXPECT_EQ(find_option(field.name), &field);
    ReconstructOptions parsed;
    set_option_from_text(field, parsed, option_value_text(field, defaults));
    EXPECT_EQ(option_value_text(field, parsed), option_value_text(field, defaults)) << field.name;
  }
  EXPECT_EQ(find_option("no_such_option"), nullptr);
  EXPECT_NO_THROW(check_option_ranges(defaults));
}

TEST(OptionTable, TextAndRangesAreRefusedWithTheFieldsWords) {
  ReconstructOptions options;
  EXPECT_THROW(set_option_from_text(*find_option("labels"), options, "36x"), InvalidArgument);
  EXPECT_THROW(set_option_from_text(*find_option("data_weight"), options, "nan"), InvalidArgument);
  EXPECT_THROW(set_option_from_text(*find_option("method"), options, "magic"), InvalidArgument);
  set_option_from_text(*find_option("light_method"), options, "contour");
  ASSERT_TRUE(options.light_method);
  EXPECT_EQ(*options.light_method, LightMethod::Contour);
  set_option_from_text(*find_option("light_method"), options, "none");
  EXPECT_FALSE(options.light_method);
  options.labels = 3;
  try {
    check_option_ranges(options);
    FAIL() << "labels 3 was taken";
  } catch (const InvalidArgument& error) {
    EXPECT_NE(std::string(error.what()).find("labels must be in 4 .. 360; got 3"), std::string::npos) << error.what();
  }
  EXPECT_EQ(OptionRange({0.0, 1.0, false, true}).text(false), "in [0, 1)");
  EXPECT_FALSE(OptionRange({0.0, 1.0, false, true}).contains(1.0));
}

// One photograph as an observation list is the image overload, bit for bit.
TEST(Observations, OnePhotographInAListIsTheImageCall) {
  const Eigen::Vector3d light(1, 0, 1);
  const testing::Scene scene = testing::sphere_scene(64, 0.45, light);
  const Reconstruction alone = reconstruct(scene.image, light, &scene.mask, std::nullopt, ReconstructOptions{});
  const Reconstruction listed = reconstruct({grey_observation(scene.image, light)}, &scene.mask, std::nullopt, ReconstructOptions{});
  EXPECT_TRUE((alone.depth == listed.depth).all());
  EXPECT_TRUE(alone.normals.xyz == listed.normals.xyz);
  EXPECT_THROW(reconstruct(std::vector<Observation>{}, nullptr, std::nullopt, ReconstructOptions{}), InvalidArgument);
}

// Four photographs of a sphere under lights around it give its normals.
TEST(Observations, FourPhotographsGiveTheNormals) {
  const testing::Scene scene = testing::sphere_scene(96, 0.45, Eigen::Vector3d(0, 0, 1));
  std::vector<Observation> photographs;
  for (const Eigen::Vector3d& light : {Eigen::Vector3d(0, 0.64, 0.77), Eigen::Vector3d(-0.64, 0, 0.77),
                                      Eigen::Vector3d(0, -0.64, 0.77), Eigen::Vector3d(0.64, 0, 0.77)})
    photographs.push_back(grey_observation(render_lambertian(scene.normals, light, 0.8, scene.mask), light));
  const Reconstruction result = reconstruct(photographs, &scene.mask, std::nullopt, ReconstructOptions{});
  EXPECT_LT(mean_angular_error(result.normals, scene.normals, erode_mask(scene.mask, 2)), 1.0);
  EXPECT_EQ(result.stats.photographs, 4);
  EXPECT_EQ(result.lights.size(), 4u);
  photographs[2].light.reset();  // one light missing while the others are given: refused, not guessed
  EXPECT_THROW(reconstruct(photographs, &scene.mask, std::nullopt, ReconstructOptions{}), InvalidArgument);
}

// The sphere's photographs under `lights` (each 0.64 from the viewer's axis, 0.77 along it), none given.
std::vector<Observation> photographs_without_lights(const testing::Scene& scene, const std::vector<Eigen::Vector3d>& lights) {
  std::vector<Observation> photographs;
  for (const Eigen::Vector3d& light : lights)
    photographs.push_back(grey_observation(render_lambertian(scene.normals, light, 0.8, scene.mask), std::nullopt));
  return photographs;
}

// Options whose hint has those lights' slant.
ReconstructOptions hint_at_their_slant() {
  ReconstructOptions options;
  options.light_slant = std::acos(0.77 / Eigen::Vector2d(0.64, 0.77).norm()) * 180.0 / M_PI;
  return options;
}

// Without any light, four photographs lit from around give their lights at the hint's slant.
TEST(Observations, FourPhotographsWithoutLightsGiveTheirLights) {
  const testing::Scene scene = testing::sphere_scene(96, 0.45, Eigen::Vector3d(0, 0, 1));
  const std::vector<Eigen::Vector3d> lights{Eigen::Vector3d(0, 0.64, 0.77), Eigen::Vector3d(-0.64, 0, 0.77),
                                            Eigen::Vector3d(0, -0.64, 0.77), Eigen::Vector3d(0.64, 0, 0.77)};
  const std::vector<Observation> photographs = photographs_without_lights(scene, lights);
  const ReconstructOptions options = hint_at_their_slant();
  const Reconstruction result = reconstruct(photographs, &scene.mask, std::nullopt, options);
  EXPECT_TRUE(result.stats.light_estimated);
  for (std::size_t k = 0; k < lights.size(); ++k)
    EXPECT_GT(result.lights[k].dot(lights[k].normalized()), std::cos(0.5 * M_PI / 180.0)) << "light " << k;
  EXPECT_LT(mean_angular_error(result.normals, scene.normals, erode_mask(scene.mask, 2)), 1.0);
}

// The first photograph lit from the bottom, the hint's first tilt at the top: the hint gives the
// sphere's inversion, and its outline, whose normals would then point inward, turns the lights back.
TEST(Observations, AnObjectsOutlineTurnsLightsTheHintPutOnTheWrongSide) {
  const testing::Scene scene = testing::sphere_scene(96, 0.45, Eigen::Vector3d(0, 0, 1));
  const std::vector<Eigen::Vector3d> lights{Eigen::Vector3d(0, -0.64, 0.77), Eigen::Vector3d(0.64, 0, 0.77),
                                            Eigen::Vector3d(0, 0.64, 0.77), Eigen::Vector3d(-0.64, 0, 0.77)};
  const std::vector<Observation> photographs = photographs_without_lights(scene, lights);
  const ReconstructOptions options = hint_at_their_slant();
  const Reconstruction result = reconstruct(photographs, &scene.mask, std::nullopt, options);
  EXPECT_TRUE(result.stats.lights_turned_by_outline);
  EXPECT_LT(result.lights.front().y(), 0.0);
  EXPECT_EQ(result.light, result.lights.front());
  for (std::size_t k = 0; k < lights.size(); ++k)
    EXPECT_GT(result.lights[k].dot(lights[k].normalized()), std::cos(0.5 * M_PI / 180.0)) << "light " << k;
  EXPECT_LT(mean_angular_error(result.normals, scene.normals, erode_mask(scene.mask, 2)), 1.0);
  // A frame without an outline (a relief) keeps the hint's choice: the inversion.
  const Mask frame = Mask::Constant(96, 96, true);
  const Reconstruction relief = reconstruct(photographs, &frame, std::nullopt, options);
  EXPECT_FALSE(relief.stats.lights_turned_by_outline);
  EXPECT_GT(relief.lights.front().y(), 0.0);
}

}  // namespace
}  // namespace shadecut
