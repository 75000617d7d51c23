#include <shadecut/support/light.hpp>

#include <shadecut/support/errors.hpp>
#include <shadecut/support/validate.hpp>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

namespace shadecut {

LightFrame LightFrame::from_direction(const Eigen::Vector3d& light) {
  if (!light.allFinite()) throw InvalidArgument("shadecut: the light direction has a NaN or infinite component");
  // Scaled by its largest component first, so that a very long vector's norm does not overflow.
  const double largest = light.cwiseAbs().maxCoeff();
  if (!(largest > 1e-300)) throw InvalidArgument("shadecut: the light direction is the zero vector");
  LightFrame frame;
  frame.direction = (light / largest).normalized();
  // A light at or below the horizon leaves part of every visible hemisphere unlit and the slant
  // formula undefined; the paper's model needs S_z > 0.
  if (frame.direction.z() <= 1e-6) {
    // In hundredths of a degree: what a user reads, and 0 rather than 6e-11 for a light on the horizon.
    const double elevation = std::round(std::asin(std::clamp(frame.direction.z(), -1.0, 1.0)) * 18000.0 / M_PI) / 100.0 + 0.0;
    throw InvalidArgument("shadecut: the light is at or below the horizon (" + number_text(elevation) +
                          " degrees above it); it must come from the viewer's side, z > 0 (1,0,1 is 45 degrees up from the right)");
  }
  frame.slant = std::acos(std::min(1.0, frame.direction.z()));
  frame.tilt = std::atan2(frame.direction.y(), frame.direction.x());
  frame.to_camera = (Eigen::AngleAxisd(frame.tilt, Eigen::Vector3d::UnitZ()) *
                     Eigen::AngleAxisd(frame.slant, Eigen::Vector3d::UnitY()))
                        .toRotationMatrix();
  return frame;
}

Eigen::Vector3d LightFrame::normal(double s, double t) const {
  const Eigen::Vector3d in_light_frame(std::sin(s) * std::cos(t), std::sin(s) * std::sin(t), std::cos(s));
  return to_camera * in_light_frame;
}

namespace {

struct Side {
  const char* name;
  double azimuth_degrees;  // counter-clockwise from the image's right (+x), toward its top (+y)
};

constexpr Side kSides[] = {{"top", 90.0},         {"bottom", 270.0},    {"left", 180.0},
                           {"right", 0.0},        {"top-left", 135.0},  {"top-right", 45.0},
                           {"bottom-left", 225.0}, {"bottom-right", 315.0}, {"above", 90.0},
                           {"below", 270.0}};

}  // namespace

const std::vector<std::string>& light_side_names() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> all;
    for (const Side& side : kSides) all.emplace_back(side.name);
    return all;
  }();
  return names;
}

Eigen::Vector3d light_from_side(const std::string& side, double slant_degrees) {
  if (!(slant_degrees > 0.0 && slant_degrees < 90.0))
    throw InvalidArgument("shadecut: a light's slant from the viewer must lie in (0, 90) degrees; got " +
                          number_text(slant_degrees));
  for (const Side& known : kSides) {
    if (side != known.name) continue;
    const double slant = slant_degrees * M_PI / 180.0, azimuth = known.azimuth_degrees * M_PI / 180.0;
    return {std::sin(slant) * std::cos(azimuth), std::sin(slant) * std::sin(azimuth), std::cos(slant)};
  }
  std::string words;
  for (const std::string& name : light_side_names()) words += (words.empty() ? "" : ", ") + name;
  throw InvalidArgument("shadecut: '" + side + "' names no side of the image a light can come from; the sides are " +
                        words);
}

}  // namespace shadecut
