// A depth map as a mesh: the one construction behind mesh files and the Blender add-on's objects.
#pragma once

#include <shadecut/support/types.hpp>

#include <Eigen/Core>

#include <cstdint>

namespace shadecut {

struct HeightFieldMesh {
  /// V x 3 vertices (x, y, z) = (c, -r, depth(r, c)) in pixel units, camera frame: one per sampled
  /// masked pixel, in raster order.
  Eigen::Matrix<float, Eigen::Dynamic, 3, Eigen::RowMajor> vertices;
  /// F x 4 vertex indices of the quads joining four sampled masked neighbours, corners top-left,
  /// bottom-left, bottom-right, top-right: counter-clockwise seen from +z (image rows run downward),
  /// in raster order of their top-left corner.
  Eigen::Matrix<std::int32_t, Eigen::Dynamic, 4, Eigen::RowMajor> quads;
  /// V x 2 texture coordinates of each vertex's pixel centre in the image, (u, v) =
  /// ((c + 0.5) / W, 1 - (r + 0.5) / H): v up, as in Blender and OBJ.
  Eigen::Matrix<float, Eigen::Dynamic, 2, Eigen::RowMajor> uvs;
};

/// Builds the mesh of a height field sampled every `step` pixels (rows and columns 0, step, 2 step...).
///
/// @param[in] depth H x W, pixel units, larger = closer; must be finite inside the mask.
/// @param[in] mask  H x W; every sampled masked pixel becomes a vertex.
/// @param[in] step  >= 1 (1 = a vertex per masked pixel).
/// @throws InvalidArgument for an empty depth map, a mask of another shape, step < 1 or a non-finite
///         masked depth.
HeightFieldMesh height_field_mesh(const ImageF& depth, const Mask& mask, int step = 1);

}  // namespace shadecut
