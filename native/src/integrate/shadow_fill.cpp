#include <shadecut/integrate/shadow_fill.hpp>

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

// Whether (r, c) lies in the frame and in `mask`.
bool masked(const Mask& mask, int r, int c) {
  return r >= 0 && r < mask.rows() && c >= 0 && c < mask.cols() && mask(r, c);
}

// The harmonic x and y of one 4-connected region of unknown normals (pixel indices `region`): a graph
// Laplacian on them, each known masked neighbour an anchor of weight 1 at its value, and the faint pull
// toward the current normal (kAnchor); solved in the region's bounding box. The normals are rebuilt
// from them: right for a sphere, z from unit length, facing the viewer.
void fill_region(NormalMap& normals, const std::vector<int>& region, const Mask& unknown, const Mask& mask) {
  const int rows = int(mask.rows()), cols = int(mask.cols());
  int top = rows, bottom = 0, left = cols, right = 0;
  for (int p : region) {
    top = std::min(top, p / cols), bottom = std::max(bottom, p / cols + 1);
    left = std::min(left, p % cols), right = std::max(right, p % cols + 1);
  }
  const int box_cols = right - left;
  const std::size_t box_size = std::size_t(bottom - top) * std::size_t(box_cols);
  auto in_box = [&](int p) { return std::size_t(p / cols - top) * std::size_t(box_cols) + std::size_t(p % cols - left); };
  Mask box = Mask::Constant(bottom - top, box_cols, false);
  detail::Anchors anchors{std::vector<double>(box_size, 0.0), {}};
  std::array<std::vector<double>, 2> targets{std::vector<double>(box_size, 0.0), std::vector<double>(box_size, 0.0)};
  for (int p : region) {
    const int r = p / cols, c = p % cols;
    double weight = kAnchor;
    Eigen::Vector2d pulled = kAnchor * normals.xyz.row(p).head<2>().transpose().cast<double>();
    const int neighbours[4][2] = {{r, c - 1}, {r, c + 1}, {r - 1, c}, {r + 1, c}};
    for (const auto& rc : neighbours) {
      if (!masked(mask, rc[0], rc[1])) continue;
      const int q = rc[0] * cols + rc[1];
      if (unknown.data()[q]) continue;
      weight += 1.0;
      pulled += normals.xyz.row(q).head<2>().transpose().cast<double>();
    }
    const std::size_t i = in_box(p);
    box.data()[i] = true;
    anchors.weight[i] = weight;
    for (int k = 0; k < 2; ++k) targets[std::size_t(k)][i] = pulled[k] / weight;
  }
  std::array<std::vector<double>, 2> solved;
  for (int k = 0; k < 2; ++k) {
    anchors.target = std::move(targets[std::size_t(k)]);
    solved[std::size_t(k)] = detail::solve_grid_poisson(box, {}, kFillTolerance, {}, &anchors);
  }
  for (int p : region) {
    const std::size_t i = in_box(p);
    Eigen::Vector2d planar(solved[0][i], solved[1][i]);
    if (planar.norm() > 1.0) planar.normalize();
    normals.xyz.row(p) << float(planar.x()), float(planar.y()), float(std::sqrt(std::max(0.0, 1.0 - planar.squaredNorm())));
  }
}

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

  // Each 4-connected region of unknowns is a system of its own (its known neighbours are fixed values),
  // solved in its own bounding box: scattered shadows cost what they hold, not a multigrid over the
  // whole frame, which a few thousand scattered pixels of a large relief made the fill's whole cost.
  Mask visited = Mask::Constant(rows, cols, false);
  std::vector<int> region;
  for (int seed : unknowns) {
    if (visited.data()[seed]) continue;
    visited.data()[seed] = true;
    region.assign(1, seed);
    for (std::size_t k = 0; k < region.size(); ++k) {
      const int r = region[k] / cols, c = region[k] % cols;
      const int neighbours[4][2] = {{r, c - 1}, {r, c + 1}, {r - 1, c}, {r + 1, c}};
      for (const auto& rc : neighbours) {
        if (!masked(mask, rc[0], rc[1])) continue;
        const int q = rc[0] * cols + rc[1];
        if (unknown.data()[q] && !visited.data()[q]) {
          visited.data()[q] = true;
          region.push_back(q);
        }
      }
    }
    fill_region(normals, region, unknown, mask);
  }
  return int(unknowns.size());
}

}  // namespace shadecut
