// The benchmarks' scene: a full frame of Gaussian bumps and dents of random sign.
#pragma once

#include <shadecut/support/types.hpp>

#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

namespace shadecut::bench {

// Uniform in [0, 1) from mt19937's raw output, which the standard fixes, unlike its distributions:
// the picture is then the same with every standard library.
inline double unit_uniform(std::mt19937& generator) { return generator() / 4294967296.0; }

/// Depth (size x size, pixel units) of 48 bumps and dents placed in the unit square and drawn at
/// `size` pixels, so every size shows the same picture.
inline ImageF bump_field_depth(int size) {
  constexpr std::uint32_t kSceneSeed = 2024;
  constexpr int kBumps = 48;
  struct Bump {
    double x, y, sigma, height;
  };
  std::mt19937 generator(kSceneSeed);
  std::vector<Bump> bumps(kBumps);
  for (Bump& bump : bumps) {
    bump.x = unit_uniform(generator);
    bump.y = unit_uniform(generator);
    bump.sigma = 0.03 + 0.04 * unit_uniform(generator);
    // A height in proportion to the width gives a lone bump the same steepest slope, 30 to 40
    // degrees, at every size: strong shading, with attached shadow only where bumps overlap.
    const double sign = unit_uniform(generator) < 0.5 ? -1.0 : 1.0;
    bump.height = sign * (1.0 + 0.5 * unit_uniform(generator)) * bump.sigma;
  }
  ImageF depth(size, size);
  for (int r = 0; r < size; ++r) {
    for (int c = 0; c < size; ++c) {
      const double x = (c + 0.5) / size, y = (r + 0.5) / size;
      double z = 0.0;
      for (const Bump& bump : bumps) {
        const double d2 = (x - bump.x) * (x - bump.x) + (y - bump.y) * (y - bump.y);
        z += bump.height * std::exp(-d2 / (2.0 * bump.sigma * bump.sigma));
      }
      depth(r, c) = float(size * z);
    }
  }
  return depth;
}

}  // namespace shadecut::bench
