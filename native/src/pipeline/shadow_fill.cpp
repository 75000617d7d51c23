#include <shadecut/pipeline/shadow_fill.hpp>

#include <shadecut/support/mask_components.hpp>

#include "support/contour.hpp"

#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>

#include <cmath>
#include <limits>
#include <vector>

namespace shadecut {

namespace {

// Weight of the pull toward the current normal; it only keeps shadow regions that touch no known
// normal well posed and is too small to matter elsewhere.
constexpr double kAnchor = 1e-6;

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

  std::vector<int> unknown_index(std::size_t(n), -1);
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
      unknown_index[std::size_t(p)] = int(unknowns.size());
      unknowns.push_back(p);
    }
  }
  if (unknowns.empty()) return 0;

  const int m = int(unknowns.size());
  std::vector<Eigen::Triplet<double>> triplets;
  Eigen::MatrixX3d rhs = Eigen::MatrixX3d::Zero(m, 3);
  for (int i = 0; i < m; ++i) {
    const int p = unknowns[std::size_t(i)], r = p / cols, c = p % cols;
    double diagonal = kAnchor;
    rhs.row(i) = kAnchor * normals.xyz.row(p).cast<double>();
    const int neighbours[4][2] = {{r, c - 1}, {r, c + 1}, {r - 1, c}, {r + 1, c}};
    for (const auto& rc : neighbours) {
      if (!inside(rc[0], rc[1])) continue;
      const int q = rc[0] * cols + rc[1];
      diagonal += 1.0;
      if (unknown_index[std::size_t(q)] >= 0)
        triplets.emplace_back(i, unknown_index[std::size_t(q)], -1.0);
      else
        rhs.row(i) += normals.xyz.row(q).cast<double>();
    }
    triplets.emplace_back(i, i, diagonal);
  }
  Eigen::SparseMatrix<double> laplacian(m, m);
  laplacian.setFromTriplets(triplets.begin(), triplets.end());
  const Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(laplacian);
  const Eigen::MatrixX3d solution = solver.solve(rhs);
  for (int i = 0; i < m; ++i) {
    Eigen::Vector3d v = solution.row(i).transpose();
    // The harmonic x, y are right for a sphere; z follows from unit length, facing the viewer.
    const double planar = std::hypot(v.x(), v.y());
    if (planar > 1.0) v.head<2>() /= planar;
    v.z() = std::sqrt(std::max(0.0, 1.0 - v.head<2>().squaredNorm()));
    normals.xyz.row(unknowns[std::size_t(i)]) = v.normalized().cast<float>();
  }
  return m;
}

}  // namespace shadecut
