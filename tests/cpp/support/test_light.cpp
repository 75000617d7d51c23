#include <shadecut/support/errors.hpp>
#include <shadecut/support/light.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <string>

namespace shadecut {
namespace {

TEST(LightFromSide, PointsTowardTheNamedSideAtTheSlant) {
  const double s = std::sin(M_PI / 4), c = std::cos(M_PI / 4);
  EXPECT_TRUE(light_from_side("top").isApprox(Eigen::Vector3d(0, s, c), 1e-12));
  EXPECT_TRUE(light_from_side("left").isApprox(Eigen::Vector3d(-s, 0, c), 1e-12));
  EXPECT_TRUE(light_from_side("bottom-right", 60.0).isApprox(
      Eigen::Vector3d(std::sin(M_PI / 3) * std::sqrt(0.5), -std::sin(M_PI / 3) * std::sqrt(0.5), 0.5), 1e-12));
  EXPECT_TRUE(light_from_side("above").isApprox(light_from_side("top"), 0.0));
  EXPECT_TRUE(light_from_side("below").isApprox(light_from_side("bottom"), 0.0));
  for (const std::string& side : light_side_names()) {
    EXPECT_NEAR(light_from_side(side).norm(), 1.0, 1e-12) << side;
    EXPECT_NEAR(std::acos(light_from_side(side).z()) * 180.0 / M_PI, kSideLightSlantDegrees, 1e-9) << side;
  }
}

TEST(LightFromSide, RefusesAnotherWordOrSlantNamingWhatIsKnown) {
  try {
    light_from_side("sideways");
    FAIL() << "no exception";
  } catch (const InvalidArgument& error) {
    EXPECT_NE(std::string(error.what()).find("'sideways' names no side"), std::string::npos) << error.what();
    EXPECT_NE(std::string(error.what()).find("top, bottom, left, right"), std::string::npos) << error.what();
  }
  for (const double slant : {0.0, 90.0, -10.0, std::nan("")}) EXPECT_THROW(light_from_side("top", slant), InvalidArgument);
}

}  // namespace
}  // namespace shadecut
