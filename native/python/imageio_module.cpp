// pybind11 bindings: the private extension shadecut._imageio, image and mesh files through
// OpenImageIO. Separate from _core so that the Blender add-on, which gets its images from Blender,
// ships without OpenImageIO and the libraries it pulls in; shadecut.load_image and the save_*
// functions import it when first called.
#include "arrays.hpp"
#include "python_errors.hpp"

#include <shadecut/io/image_io.hpp>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <optional>
#include <string>

namespace py = pybind11;
using namespace shadecut::python;
using shadecut::ImageF;
using shadecut::Mask;
using shadecut::NormalMap;

PYBIND11_MODULE(_imageio, m) {
  m.doc() = "ShadeCut's image and mesh files; use the shadecut package, not this module.";
  py::register_local_exception_translator(translate_core_error);

  m.attr("DEFAULT_MAX_PIXELS") = shadecut::kDefaultMaxPixels;
  m.def("load_image", [](const std::string& path, const std::string& color_space, std::int64_t max_pixels) {
    const shadecut::LoadedImage loaded = shadecut::load_image(path, shadecut::parse_color_space(color_space), max_pixels);
    return py::make_tuple(from_image(loaded.intensity), from_mask(loaded.mask), loaded.has_alpha, loaded.color_space,
                          from_colour(loaded.colour));
  });

  m.def("save_image", [](const std::string& path, const FloatArray& image, const std::optional<BoolArray>& alpha) {
    const std::optional<Mask> mask = to_mask(alpha);
    if (image.ndim() == 3) shadecut::save_image(path, to_colour(image, "image"), mask ? &*mask : nullptr);
    else shadecut::save_image(path, to_image(image, "image"), mask ? &*mask : nullptr);
  });

  m.def("save_depth", [](const std::string& path, const FloatArray& depth, const std::optional<BoolArray>& mask) {
    const ImageF z = to_image(depth, "depth map");
    shadecut::save_depth(path, z, mask_or_all(mask, z.rows(), z.cols()));
  });

  m.def("save_normals", [](const std::string& path, const FloatArray& normals, const std::optional<BoolArray>& mask) {
    const NormalMap n = to_normals(normals);
    shadecut::save_normals(path, n, mask_or_all(mask, n.rows, n.cols));
  });

  m.def("save_mesh", [](const std::string& path, const FloatArray& depth, const std::optional<BoolArray>& mask,
                        int step) {
    const ImageF z = to_image(depth, "depth map");
    shadecut::save_mesh(path, z, mask_or_all(mask, z.rows(), z.cols()), step);
  });
}
