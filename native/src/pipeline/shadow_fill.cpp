#include <shadecut/pipeline/shadow_fill.hpp>

#include <shadecut/support/mask_components.hpp>

#include "support/contour.hpp"

#include "integrate/grid_poisson.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

namespace shadecut {

namespace {

// Weight of the pull toward the current normal; it only keeps shadow regions that touch no known
// normal well posed and is too small to matter elsewhere.
constexpr double kAnchor = 1e-6;
// The solve's relative residual: the filled normals then differ from the exact harmonic ones by
// about 1e-5 (ShadowFill.*: 1e-4 gave 0.09 on a region held by the faint pull alone).
constexpr double kFillTolerance = 1e-6;

}  // namespace

Mask unreliable_pixels(const ImageF& image, const Mask& mask, double albedo, double shadow_threshold,
                       double highlight_threshold) {
  const double dark = shadow_threshold * albedo;
  const double bright = highlight_threshold > 0.0 ? highlight_threshold * albedo : std::numeric_limits<double>::infinity();
  const auto intensity = image.cast<double>();
  return mask && (intensity <= dark || intensity > bright);
}

int fill_normals(NormalMap& normals, const Mask& fill, const Mask& mask, bool occluding_contour) {
  const int rows = int(mask.rows()), cols = int(mask.cols()), n = rows * cols;
  auto inside = [&](int r, int c) { return r >= 0 && r < rows && c >= 0 && c < cols && mask(r, c); };
  auto shadowed = [&](int p) { return bool(fill.data()[p]); };
  auto outward = [&](int r, int c) -> Eigen::Vector2d {
    return occluding_contour ? detail::contour_outward(mask, r, c) : Eigen::Vector2d::Zero();
  };

  if (!(fill && mask).any()) return 0;
  // Whether an edge turns away from the viewer (a silhouette: normals point outward) or toward it
  // (a rim: inward) is read from the lit pixels of the same connected component.
  MaskComponents components;
  std::vector<double> outward_vote;
  if (occluding_contour) {
    components = mask_components(mask);
    outward_vote.assign(std::size_t(components.count), 0.0);
    for (int p = 0; p < n; ++p) {
      if (!mask.data()[p] || shadowed(p)) continue;
      outward_vote[std::size_t(components.labels.data()[p])] +=
          outward(p / cols, p % cols).dot(normals.xyz.row(p).head<2>().cast<double>());
    }
  }

  Mask unknown = Mask::Constant(rows, cols, false);
  std::vector<int> unknowns;
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) {
      const int p = r * cols + c;
      if (!mask(r, c) || !shadowed(p)) continue;
      const Eigen::Vector2d edge = outward(r, c);
      const double vote = occluding_contour ? outward_vote[std::size_t(components.labels.data()[p])] : 0.0;
      if (edge.norm() > 0.0 && vote != 0.0) {
        const Eigen::Vector2d horizontal = vote > 0.0 ? edge : Eigen::Vector2d(-edge);
        normals.xyz.row(p) << float(horizontal.x()), float(horizontal.y()), 0.0f;
        continue;
      }
      unknown.data()[p] = true;
      unknowns.push_back(p);
    }
  }
  if (unknowns.empty()) return 0;

  // The unknowns' harmonic x and y: a graph Laplacian on them, each known masked neighbour an anchor
  // of weight 1 at its value, and the faint pull toward the current normal (kAnchor).
  detail::Anchors anchors{std::vector<double>(std::size_t(n), 0.0), {}};
  std::array<std::vector<double>, 2> targets{std::vector<double>(std::size_t(n), 0.0), std::vector<double>(std::size_t(n), 0.0)};
  for (int p : unknowns) {
    const int r = p / cols, c = p % cols;
    double weight = kAnchor;
    Eigen::Vector2d pulled = kAnchor * normals.xyz.row(p).head<2>().transpose().cast<double>();
    const int neighbours[4][2] = {{r, c - 1}, {r, c + 1}, {r - 1, c}, {r + 1, c}};
    for (const auto& rc : neighbours) {
      if (!inside(rc[0], rc[1])) continue;
      const int q = rc[0] * cols + rc[1];
      if (unknown.data()[q]) continue;
      weight += 1.0;
      pulled += normals.xyz.row(q).head<2>().transpose().cast<double>();
    }
    anchors.weight[std::size_t(p)] = weight;
    for (int k = 0; k < 2; ++k) targets[std::size_t(k)][std::size_t(p)] = pulled[k] / weight;
  }
  std::array<std::vector<double>, 2> solved;
  for (int k = 0; k < 2; ++k) {
    anchors.target = std::move(targets[std::size_t(k)]);
    solved[std::size_t(k)] = detail::solve_grid_poisson(unknown, {}, kFillTolerance, {}, &anchors);
  }
  for (int p : unknowns) {
    Eigen::Vector2d planar(solved[0][std::size_t(p)], solved[1][std::size_t(p)]);
    // The harmonic x, y are right for a sphere; z follows from unit length, facing the viewer.
    if (planar.norm() > 1.0) planar.normalize();
    normals.xyz.row(p) << float(planar.x()), float(planar.y()), float(std::sqrt(std::max(0.0, 1.0 - planar.squaredNorm())));
  }
  return int(unknowns.size());
}

}  // namespace shadecut
