// pybind11 bindings: the private extension shadecut._core, the algorithms and nothing but the C runtime
// (it ships in the Blender add-on). The public, documented API is the Python package in addon/shadecut/,
// which calls these functions; image files are the separate _imageio module's.
#include "arrays.hpp"
#include "bind_reconstruct.hpp"
#include "python_errors.hpp"
#include "estimate/estimate_contour_light.hpp"

#include <shadecut/support/angular_error.hpp>
#include <shadecut/support/downsample.hpp>
#include <shadecut/support/errors.hpp>
#include <shadecut/estimate/estimate_light.hpp>
#include <shadecut/estimate/estimate_reflectance.hpp>
#include <shadecut/integrate/height_field_mesh.hpp>
#include <shadecut/integrate/integrate.hpp>
#include <shadecut/support/light.hpp>
#include <shadecut/support/intensity.hpp>
#include <shadecut/support/mask_components.hpp>
#include <shadecut/pipeline/cut_out.hpp>
#include <shadecut/pipeline/flip_surface.hpp>
#include <shadecut/pipeline/reconstruct.hpp>
#include <shadecut/support/render.hpp>

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

namespace {

// The light, the albedo and the paint, estimated from an image.
void bind_light_and_albedo(py::module_& m) {
  m.def("estimate_light", [](const FloatArray& image, const std::optional<BoolArray>& mask, const std::string& method,
                             std::optional<double> albedo) {
    const ImageF img = to_image(image, "image");
    const shadecut::LightMethod estimator = shadecut::parse_light_method(method);
    const shadecut::LightEstimate estimate =
        shadecut::estimate_light(img, mask_or_all(mask, img.rows(), img.cols()), estimator, albedo);
    return py::make_tuple(std::vector<double>{estimate.light.x(), estimate.light.y(), estimate.light.z()}, estimate.albedo);
  });

  // Private: scripts/tune_parameters.py --light-method chooses the contour estimator's ring with it.
  m.def("estimate_contour_light", [](const FloatArray& image, const std::optional<BoolArray>& mask, double albedo,
                                     double ring) {
    const ImageF img = to_image(image, "image");
    const shadecut::LightEstimate estimate =
        shadecut::detail::estimate_contour_light(img, mask_or_all(mask, img.rows(), img.cols()), albedo, ring);
    return py::make_tuple(std::vector<double>{estimate.light.x(), estimate.light.y(), estimate.light.z()}, estimate.albedo,
                          estimate.uncertainty);
  });

  m.def("estimate_albedo", [](const FloatArray& image, const std::optional<BoolArray>& mask, const std::string& method,
                              std::optional<std::tuple<double, double, double>> window) {
    const ImageF img = to_image(image, "image");
    shadecut::TopFitWindow top_fit;
    if (window) top_fit = {std::get<0>(*window), std::get<1>(*window), std::get<2>(*window)};
    return shadecut::estimate_albedo(img, mask_or_all(mask, img.rows(), img.cols()), shadecut::parse_albedo_method(method), top_fit);
  });

  m.def("light_direction", [](const std::vector<double>& light) {
    const Eigen::Vector3d direction = shadecut::LightFrame::from_direction(to_vector3(light, "light")).direction;
    return py::array_t<double>(3, direction.data());
  });

  m.def("light_from_side", [](const std::string& side, double slant_degrees) {
    const Eigen::Vector3d direction = shadecut::light_from_side(side, slant_degrees);
    return py::array_t<double>(3, direction.data());
  });
  m.attr("LIGHT_SIDES") = shadecut::light_side_names();
  m.attr("SIDE_LIGHT_SLANT_DEGREES") = shadecut::kSideLightSlantDegrees;
  m.attr("FEWEST_PHOTOGRAPHS_TO_ESTIMATE_LIGHTS") = shadecut::kFewestPhotographsToEstimateLights;

  m.def("estimate_reflectance", [](const FloatArray& image, const std::optional<BoolArray>& mask,
                                   const shadecut::ReconstructOptions& options, const std::optional<FloatArray>& shading) {
    require_grey_or_colour(image);
    std::optional<shadecut::ColourImage> colour;
    if (image.ndim() == 3) colour = to_colour(image, "image");
    const ImageF intensity = colour ? shadecut::luminance(*colour) : to_image(image, "image");
    std::optional<ImageF> shading_image;
    if (shading) shading_image = to_image(*shading, "shading");
    const Mask pixels = mask_or_all(mask, intensity.rows(), intensity.cols());
    ImageF relative;
    {
      py::gil_scoped_release release;
      relative = shadecut::estimate_reflectance(intensity, colour ? &*colour : nullptr, pixels,
                                                shadecut::reflectance_params(options), {},
                                                shading_image ? &*shading_image : nullptr)
                     .relative;
    }
    return from_image(relative);
  });
}

// Normals, depth and meshes.
void bind_geometry(py::module_& m) {
  m.def("normals_from_depth", [](const FloatArray& depth, const std::optional<BoolArray>& mask) {
    const ImageF z = to_image(depth, "depth map");
    return from_normals(shadecut::normals_from_depth(z, mask_or_all(mask, z.rows(), z.cols())));
  });

  m.def("render_normals", [](const FloatArray& normals, const std::vector<double>& light, double albedo,
                             const std::optional<BoolArray>& mask) {
    const NormalMap n = to_normals(normals);
    return from_image(shadecut::render_lambertian(n, to_vector3(light, "light"), albedo, mask_or_all(mask, n.rows, n.cols)));
  });

  m.def("integrate", [](const FloatArray& normals, const std::optional<BoolArray>& mask, const std::string& method,
                        double max_slope) {
    const NormalMap n = to_normals(normals);
    const Mask m_ = mask_or_all(mask, n.rows, n.cols);
    const shadecut::Integrator integrator = shadecut::parse_integrator(method);
    ImageF depth;
    {
      py::gil_scoped_release release;
      depth = shadecut::integrate_normals(n, m_, integrator, max_slope);
    }
    return from_image(depth);
  });

  m.def("fold_back_facing", [](const FloatArray& normals, const std::optional<BoolArray>& mask) {
    NormalMap n = to_normals(normals);
    const int folded = shadecut::fold_back_facing(n, mask_or_all(mask, n.rows, n.cols));
    return py::make_tuple(from_normals(n), folded);
  });

  m.def("flip_surface", [](const FloatArray& depth, const FloatArray& normals, const std::optional<BoolArray>& mask) {
    ImageF z = to_image(depth, "depth map");
    NormalMap n = to_normals(normals);
    shadecut::flip_surface(z, n, mask_or_all(mask, z.rows(), z.cols()));
    return py::make_tuple(from_image(z), from_normals(n));
  });

  m.def("height_field_mesh", [](const FloatArray& depth, const std::optional<BoolArray>& mask, int step) {
    const ImageF z = to_image(depth, "depth map");
    const shadecut::HeightFieldMesh mesh = shadecut::height_field_mesh(z, mask_or_all(mask, z.rows(), z.cols()), step);
    return py::make_tuple(py::array_t<float>({mesh.vertices.rows(), Eigen::Index(3)}, mesh.vertices.data()),
                          py::array_t<std::int32_t>({mesh.quads.rows(), Eigen::Index(4)}, mesh.quads.data()),
                          py::array_t<float>({mesh.uvs.rows(), Eigen::Index(2)}, mesh.uvs.data()));
  });
}

// Images, masks and their comparison.
void bind_images(py::module_& m) {
  m.attr("LUMINANCE_WEIGHTS") = py::tuple(py::cast(shadecut::kLuminanceWeights));
  m.def("angular_error_map", [](const FloatArray& a, const FloatArray& b, const std::optional<BoolArray>& mask) {
    const NormalMap na = to_normals(a), nb = to_normals(b);
    return from_image(shadecut::angular_error_map(na, nb, mask_or_all(mask, na.rows, na.cols)));
  });

  m.def("mean_angular_error", [](const FloatArray& a, const FloatArray& b, const std::optional<BoolArray>& mask) {
    const NormalMap na = to_normals(a), nb = to_normals(b);
    return shadecut::mean_angular_error(na, nb, mask_or_all(mask, na.rows, na.cols));
  });

  m.def("mask_components", [](const BoolArray& mask) {
    const shadecut::MaskComponents components = shadecut::mask_components(*to_mask(mask));
    py::array_t<std::int32_t> labels({components.labels.rows(), components.labels.cols()});
    std::copy_n(components.labels.data(), components.labels.size(), labels.mutable_data());
    return py::make_tuple(labels, components.count);
  });

  m.def("downsample", [](const FloatArray& image, const BoolArray& mask, int factor, double min_coverage) {
    const shadecut::Downsampled small = shadecut::downsample(to_image(image, "image"), *to_mask(mask), factor, min_coverage);
    return py::make_tuple(from_image(small.image), from_mask(small.mask));
  });

  m.def("intensity_from_pixels", [](const FloatArray& pixels, bool srgb, std::optional<int> alpha) {
    if (pixels.ndim() != 3) throw shadecut::InvalidArgument("shadecut: pixels must be an (H, W, channels) array");
    const int channels = int(pixels.shape(2));
    const shadecut::Intensity decoded = shadecut::intensity_from_pixels(
        pixels.data(), int(pixels.shape(0)), int(pixels.shape(1)), channels, alpha.value_or(shadecut::default_alpha_channel(channels)), srgb);
    return py::make_tuple(from_image(decoded.intensity), from_mask(decoded.mask), from_colour(decoded.colour));
  });

  m.def("srgb_to_linear", py::vectorize([](double encoded) { return shadecut::srgb_to_linear(encoded); }));

  m.def("erode_mask", [](const BoolArray& mask, int pixels) { return from_mask(shadecut::erode_mask(*to_mask(mask), pixels)); });
}

// An object cut out of its background.
void bind_cut_out(py::module_& m) {
  py::class_<shadecut::CutOutOptions>(m, "CutOutOptions", "The settings of cut_out() with their defaults (pipeline/cut_out.hpp).")
      .def(py::init<>())
      .def_readwrite("working_size", &shadecut::CutOutOptions::working_size)
      .def_readwrite("border", &shadecut::CutOutOptions::border)
      .def_readwrite("max_noise", &shadecut::CutOutOptions::max_noise)
      .def_readwrite("min_border_share", &shadecut::CutOutOptions::min_border_share)
      .def_readwrite("smoothness", &shadecut::CutOutOptions::smoothness)
      .def_readwrite("iterations", &shadecut::CutOutOptions::iterations)
      .def_readwrite("min_area", &shadecut::CutOutOptions::min_area)
      .def_readwrite("min_outline_contrast", &shadecut::CutOutOptions::min_outline_contrast);

  m.def(
      "cut_out",
      [](const FloatArray& image, const shadecut::CutOutOptions& options, const std::optional<py::function>& progress) {
        require_grey_or_colour(image);
        const shadecut::Progress reporter(python_progress(progress));
        const shadecut::Observation photograph = image.ndim() == 3
                                                     ? shadecut::colour_observation(to_colour(image, "image"), std::nullopt)
                                                     : shadecut::grey_observation(to_image(image, "image"), std::nullopt);
        shadecut::CutOut cut;
        {
          py::gil_scoped_release release;
          cut = shadecut::cut_out(photograph.image, photograph.has_colour() ? &photograph.colour : nullptr, options, reporter);
        }
        return py::make_tuple(from_mask(cut.mask), cut.outcome, cut.outline_contrast, cut.background_noise, cut.border_share,
                              cut.message);
      },
      py::arg("image"), py::arg("options"), py::arg("progress") = py::none());
}

}  // namespace

PYBIND11_MODULE(_core, m) {
  m.doc() = "ShadeCut's compiled core; use the shadecut package, not this module.";

  static py::exception<shadecut::Cancelled> cancelled(m, "Cancelled");
  py::register_local_exception_translator(translate_core_error);
  py::register_local_exception_translator([](std::exception_ptr error) {
    try {
      if (error) std::rethrow_exception(error);
    } catch (const shadecut::Cancelled& e) {
      cancelled(e.what());
    }
  });

  bind_reconstruct(m);
  // The add-on, which has no _imageio, refuses a file's header above the library's own limit.
  m.attr("DEFAULT_MAX_PIXELS") = shadecut::kDefaultMaxPixels;
  m.attr("METHODS") = py::tuple(py::cast(shadecut::method_names()));
  m.attr("LIGHT_METHODS") = py::tuple(py::cast(shadecut::light_method_names()));
  bind_light_and_albedo(m);
  bind_geometry(m);
  bind_images(m);
  bind_cut_out(m);
}
