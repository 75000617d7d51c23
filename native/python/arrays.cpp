#include "arrays.hpp"

#include <shadecut/support/errors.hpp>

#include <climits>
#include <cstring>
#include <string>

namespace py = pybind11;

namespace shadecut::python {

namespace {

std::string shape_of(const py::array& a) {
  std::string s = "(";
  for (py::ssize_t i = 0; i < a.ndim(); ++i) s += (i ? ", " : "") + std::to_string(a.shape(i));
  return s + (a.ndim() == 1 ? ",)" : ")");
}

// The core counts rows and columns in int: a side beyond it (possible in an array of zero size,
// 2^31 x 0) would wrap to a negative count.
void require_int_sides(const py::array& a, const std::string& what) {
  if (a.shape(0) > INT_MAX || a.shape(1) > INT_MAX)
    throw InvalidArgument("shadecut: the " + what + " is " + std::to_string(a.shape(0)) + " x " + std::to_string(a.shape(1)) +
                          " pixels; a side may have at most " + std::to_string(INT_MAX));
}

}  // namespace

ImageF to_image(const FloatArray& a, const char* what) {
  if (a.ndim() != 2)
    throw InvalidArgument(std::string("shadecut: the ") + what + " must be a 2-D array (H, W); got shape " + shape_of(a));
  require_int_sides(a, what);
  ImageF image(a.shape(0), a.shape(1));
  std::memcpy(image.data(), a.data(), sizeof(float) * std::size_t(image.size()));
  return image;
}

ColourImage to_colour(const FloatArray& a, const char* what) {
  if (a.ndim() != 3 || a.shape(2) != 3)
    throw InvalidArgument(std::string("shadecut: the ") + what + " must be (H, W) or (H, W, 3); got shape " + shape_of(a));
  require_int_sides(a, what);
  ColourImage colour;
  const float* data = a.data();
  for (int k = 0; k < 3; ++k) {
    ImageF& channel = colour.channel[std::size_t(k)];
    channel.resize(a.shape(0), a.shape(1));
    for (Eigen::Index i = 0; i < channel.size(); ++i) channel.data()[i] = data[3 * i + k];
  }
  return colour;
}

void require_grey_or_colour(const FloatArray& a) {
  if (a.ndim() != 2 && a.ndim() != 3)
    throw InvalidArgument("shadecut: the image must be (H, W) intensity or (H, W, 3) RGB; got " + std::to_string(a.ndim()) +
                          " dimension(s)");
}

pybind11::object from_colour(const ColourImage& colour) {
  if (colour.channel[0].size() == 0) return pybind11::none();
  pybind11::array_t<float> out({colour.rows(), colour.cols(), Eigen::Index(3)});
  float* data = out.mutable_data();
  for (int k = 0; k < 3; ++k)
    for (Eigen::Index i = 0; i < colour.channel[std::size_t(k)].size(); ++i) data[3 * i + k] = colour.channel[std::size_t(k)].data()[i];
  return std::move(out);
}

std::optional<Mask> to_mask(const std::optional<BoolArray>& a) {
  if (!a) return std::nullopt;
  if (a->ndim() != 2) throw InvalidArgument("shadecut: the mask must be a 2-D array (H, W); got shape " + shape_of(*a));
  require_int_sides(*a, "mask");
  Mask mask(a->shape(0), a->shape(1));
  std::memcpy(mask.data(), a->data(), std::size_t(mask.size()));
  return mask;
}

Mask mask_or_all(const std::optional<BoolArray>& array, Eigen::Index rows, Eigen::Index cols) {
  const std::optional<Mask> mask = to_mask(array);
  return mask ? *mask : Mask::Constant(rows, cols, true);
}

NormalMap to_normals(const FloatArray& a) {
  if (a.ndim() != 3 || a.shape(2) != 3)
    throw InvalidArgument("shadecut: normals must be an (H, W, 3) array; got shape " + shape_of(a));
  require_int_sides(a, "normal map");
  NormalMap normals(int(a.shape(0)), int(a.shape(1)));
  std::memcpy(normals.xyz.data(), a.data(), sizeof(float) * std::size_t(normals.xyz.size()));
  return normals;
}

Eigen::Vector3d to_vector3(const std::vector<double>& v, const char* what) {
  if (v.size() != 3) throw InvalidArgument(std::string("shadecut: the ") + what + " must have 3 components");
  return {v[0], v[1], v[2]};
}

py::array_t<float> from_image(const ImageF& image) {
  py::array_t<float> out({image.rows(), image.cols()});
  std::memcpy(out.mutable_data(), image.data(), sizeof(float) * std::size_t(image.size()));
  return out;
}

py::array_t<bool> from_mask(const Mask& mask) {
  py::array_t<bool> out({mask.rows(), mask.cols()});
  std::memcpy(out.mutable_data(), mask.data(), std::size_t(mask.size()));
  return out;
}

py::array_t<float> from_normals(const NormalMap& normals) {
  py::array_t<float> out({py::ssize_t(normals.rows), py::ssize_t(normals.cols), py::ssize_t(3)});
  std::memcpy(out.mutable_data(), normals.xyz.data(), sizeof(float) * std::size_t(normals.xyz.size()));
  return out;
}

}  // namespace shadecut::python
