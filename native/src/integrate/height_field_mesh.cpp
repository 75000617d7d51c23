#include <shadecut/integrate/height_field_mesh.hpp>

#include <shadecut/support/errors.hpp>

#include <cmath>
#include <string>
#include <vector>

namespace shadecut {

HeightFieldMesh height_field_mesh(const ImageF& depth, const Mask& mask, int step) {
  if (depth.size() == 0) throw InvalidArgument("shadecut: the depth map is empty");
  if (mask.rows() != depth.rows() || mask.cols() != depth.cols())
    throw InvalidArgument("shadecut: the mask is " + std::to_string(mask.rows()) + " x " + std::to_string(mask.cols()) +
                          " but the depth map is " + std::to_string(depth.rows()) + " x " + std::to_string(depth.cols()));
  if (step < 1) throw InvalidArgument("shadecut: the mesh step must be >= 1, got " + std::to_string(step));
  const Eigen::Index rows = depth.rows(), cols = depth.cols();
  const Eigen::Index sampled_rows = (rows + step - 1) / step, sampled_cols = (cols + step - 1) / step;

  constexpr std::int32_t kNoVertex = -1;
  std::vector<std::int32_t> vertex_of(std::size_t(sampled_rows * sampled_cols), kNoVertex);
  std::int32_t count = 0;
  for (Eigen::Index i = 0; i < sampled_rows; ++i) {
    for (Eigen::Index j = 0; j < sampled_cols; ++j) {
      if (!mask(i * step, j * step)) continue;
      if (!std::isfinite(depth(i * step, j * step)))
        throw InvalidArgument("shadecut: the depth at pixel (" + std::to_string(i * step) + ", " +
                              std::to_string(j * step) + ") is NaN or infinite");
      vertex_of[std::size_t(i * sampled_cols + j)] = count++;
    }
  }

  HeightFieldMesh mesh;
  mesh.vertices.resize(count, 3);
  mesh.uvs.resize(count, 2);
  for (Eigen::Index i = 0; i < sampled_rows; ++i) {
    for (Eigen::Index j = 0; j < sampled_cols; ++j) {
      const std::int32_t v = vertex_of[std::size_t(i * sampled_cols + j)];
      if (v == kNoVertex) continue;
      const Eigen::Index r = i * step, c = j * step;
      mesh.vertices.row(v) << float(c), float(-r), depth(r, c);
      mesh.uvs.row(v) << float((double(c) + 0.5) / double(cols)), float(1.0 - (double(r) + 0.5) / double(rows));
    }
  }

  std::vector<std::int32_t> corners;
  for (Eigen::Index i = 0; i + 1 < sampled_rows; ++i) {
    for (Eigen::Index j = 0; j + 1 < sampled_cols; ++j) {
      const std::size_t top_left = std::size_t(i * sampled_cols + j);
      const std::int32_t quad[4] = {vertex_of[top_left], vertex_of[top_left + std::size_t(sampled_cols)],
                                    vertex_of[top_left + std::size_t(sampled_cols) + 1], vertex_of[top_left + 1]};
      if (quad[0] == kNoVertex || quad[1] == kNoVertex || quad[2] == kNoVertex || quad[3] == kNoVertex) continue;
      corners.insert(corners.end(), quad, quad + 4);
    }
  }
  mesh.quads = Eigen::Map<const Eigen::Matrix<std::int32_t, Eigen::Dynamic, 4, Eigen::RowMajor>>(
      corners.data(), Eigen::Index(corners.size() / 4), 4);
  return mesh;
}

}  // namespace shadecut
