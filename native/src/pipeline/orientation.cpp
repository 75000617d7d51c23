#include "pipeline/orientation.hpp"

#include <shadecut/integrate/surface_from_normals.hpp>
#include <shadecut/local/local_shape.hpp>
#include <shadecut/support/downsample.hpp>
#include <shadecut/support/render.hpp>

#include "pipeline/surface_rules.hpp"

#include <algorithm>
#include <array>

namespace shadecut::detail {

namespace {

// The orientation is judged at an object size of at most this many pixels: a surface and its
// inversion differ in how their large forms render, which survives block means, and at full size the
// judgement cost as much as the call's integration (docs/benchmarks.md).
constexpr double kOrientationObjectSize = 256.0;

// Normals averaged over factor x factor blocks (where the whole block is in `mask`), renormalized.
NormalMap block_mean_normals(const NormalMap& normals, const Mask& mask, int factor) {
  std::array<ImageF, 3> small;
  Mask small_mask;
  for (int axis = 0; axis < 3; ++axis) {
    ImageF plane(normals.rows, normals.cols);
    for (Eigen::Index i = 0; i < normals.size(); ++i) plane.data()[i] = normals.xyz(i, axis);
    Downsampled shrunk = downsample(plane, mask, factor, 1.0);
    small[std::size_t(axis)] = std::move(shrunk.image);
    small_mask = std::move(shrunk.mask);
  }
  NormalMap out(int(small_mask.rows()), int(small_mask.cols()));
  for (Eigen::Index i = 0; i < out.size(); ++i) {
    const Eigen::Vector3f n(small[0].data()[i], small[1].data()[i], small[2].data()[i]);
    out.xyz.row(i) = small_mask.data()[i] && n.norm() > 0.0f ? n.normalized().transpose() : Eigen::RowVector3f(0, 0, 1);
  }
  return out;
}

}  // namespace

void judge_orientation(const ImageF& full_image, const Mask& full_unreliable, const LightFrame& frame,
                       const ReconstructOptions& options, const ImageF& full_depth, const NormalMap& full_normals,
                       Reconstruction& result) {
  const int factor = std::max(1, int(object_size(result.mask) / kOrientationObjectSize));
  // The block means, when there are blocks; the call's own images are only read.
  Downsampled small;
  ImageF small_depth;
  Mask small_unreliable;
  double detail_size = result.stats.detail_size;
  if (factor > 1) {
    // A block is unreliable when any of its pixels is; depth in pixel units shrinks with the pixels.
    small = downsample(full_image, result.mask, factor, 1.0);
    small_depth = downsample(full_depth, result.mask, factor, 1.0).image / float(factor);
    small_unreliable = downsample(full_unreliable.cast<float>(), result.mask, factor, 1.0).image > 0.0f && small.mask;
    detail_size /= factor;
  }
  NormalMap turned = factor > 1 ? block_mean_normals(full_normals, result.mask, factor) : full_normals;
  const ImageF& image = factor > 1 ? small.image : full_image;
  const ImageF& depth = factor > 1 ? small_depth : full_depth;
  const Mask& mask = factor > 1 ? small.mask : result.mask;
  const Mask& unreliable = factor > 1 ? small_unreliable : full_unreliable;
  const Eigen::Vector3f light = frame.direction.cast<float>();
  for (Eigen::Index i = 0; i < turned.size(); ++i) {
    if (!mask.data()[i]) continue;
    const Eigen::Vector3f n = turned.xyz.row(i).transpose();
    turned.xyz.row(i) = (2.0f * n.dot(light) * light - n).transpose();
  }
  Surface inverted = surface_from_normals(std::move(turned), mask, unreliable, edge_is_outline(options), options.integrator,
                                          options.seamless, options.max_slope);
  finish_relief(inverted.depth, mask, options, detail_size);
  const Mask counted = mask && !unreliable;
  auto residual = [&](const ImageF& rendered_depth) {
    return mean_brightness_residual(rendered_depth, image, mask, counted, frame.direction, result.albedo);
  };
  ReconstructStats& stats = result.stats;
  stats.orientation_residual = residual(depth);
  stats.inverted_residual = residual(inverted.depth);
  stats.orientation_ambiguous = stats.inverted_residual < kAmbiguousResidualRatio * stats.orientation_residual;
}


}  // namespace shadecut::detail
