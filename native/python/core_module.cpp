// pybind11 bindings: the private extension shadecut._core. The public, documented API is the Python
// package in addon/shadecut/, which calls these functions.
#include <shadecut/angular_error.hpp>
#include <shadecut/errors.hpp>
#include <shadecut/estimate_light.hpp>
#include <shadecut/image_io.hpp>
#include <shadecut/integrate.hpp>
#include <shadecut/reconstruct.hpp>
#include <shadecut/render.hpp>

#include <pybind11/functional.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cstring>
#include <optional>
#include <string>

namespace py = pybind11;
using shadecut::ImageF;
using shadecut::Mask;
using shadecut::NormalMap;

namespace {

using FloatArray = py::array_t<float, py::array::c_style | py::array::forcecast>;
using BoolArray = py::array_t<bool, py::array::c_style | py::array::forcecast>;

std::string shape_of(const py::array& a) {
  std::string s = "(";
  for (py::ssize_t i = 0; i < a.ndim(); ++i) s += (i ? ", " : "") + std::to_string(a.shape(i));
  return s + (a.ndim() == 1 ? ",)" : ")");
}

ImageF to_image(const FloatArray& a, const char* what) {
  if (a.ndim() != 2)
    throw shadecut::InvalidArgument(std::string("shadecut: the ") + what + " must be a 2-D array (H, W); got shape " + shape_of(a));
  ImageF image(a.shape(0), a.shape(1));
  std::memcpy(image.data(), a.data(), sizeof(float) * std::size_t(image.size()));
  return image;
}

std::optional<Mask> to_mask(const std::optional<BoolArray>& a) {
  if (!a) return std::nullopt;
  if (a->ndim() != 2) throw shadecut::InvalidArgument("shadecut: the mask must be a 2-D array (H, W); got shape " + shape_of(*a));
  Mask mask(a->shape(0), a->shape(1));
  std::memcpy(mask.data(), a->data(), std::size_t(mask.size()));
  return mask;
}

NormalMap to_normals(const FloatArray& a) {
  if (a.ndim() != 3 || a.shape(2) != 3)
    throw shadecut::InvalidArgument("shadecut: normals must be an (H, W, 3) array; got shape " + shape_of(a));
  NormalMap normals(int(a.shape(0)), int(a.shape(1)));
  std::memcpy(normals.xyz.data(), a.data(), sizeof(float) * std::size_t(normals.xyz.size()));
  return normals;
}

Eigen::Vector3d to_vector3(const std::vector<double>& v, const char* what) {
  if (v.size() != 3) throw shadecut::InvalidArgument(std::string("shadecut: the ") + what + " must have 3 components");
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

Mask mask_or_all(const std::optional<Mask>& mask, Eigen::Index rows, Eigen::Index cols) {
  return mask ? *mask : Mask::Constant(rows, cols, true);
}

py::dict reconstruct(const FloatArray& image_array, const std::optional<std::vector<double>>& light,
                     const std::optional<BoolArray>& mask_array, std::optional<double> albedo, const std::string& method,
                     int labels, double data_weight, std::optional<double> undefined_weight, const std::string& integrator, const std::string& maxflow,
                     int max_cycles, int coarse_to_fine_band, std::optional<double> tolerance, std::optional<int> iterations, std::optional<double> smoothness,
                     const std::string& light_method, std::optional<double> min_curvature, bool refine, double max_slope, bool fill_shadows,
                     bool occluding_contour, int threads, const std::optional<py::function>& progress) {
  const ImageF image = to_image(image_array, "image");
  const std::optional<Mask> mask = to_mask(mask_array);
  shadecut::ReconstructOptions options;
  options.method = shadecut::parse_method(method);
  options.labels = labels;
  options.data_weight = data_weight;
  options.undefined_weight = undefined_weight;
  options.integrator = shadecut::parse_integrator(integrator);
  options.maxflow = shadecut::parse_maxflow_kind(maxflow);
  options.max_cycles = max_cycles;
  options.coarse_to_fine_band = coarse_to_fine_band;
  options.tolerance = tolerance;
  options.iterations = iterations;
  options.smoothness = smoothness;
  options.light_estimator = shadecut::parse_light_estimator(light_method);
  options.min_curvature = min_curvature;
  options.refine = refine;
  options.max_slope = max_slope;
  options.fill_shadows = fill_shadows;
  options.occluding_contour = occluding_contour;
  options.threads = threads;
  if (progress) {
    options.progress = [callback = *progress](double fraction, const std::string& stage) {
      py::gil_scoped_acquire gil;
      const py::object answer = callback(fraction, stage);
      return answer.is_none() || answer.cast<bool>();
    };
  }
  std::optional<Eigen::Vector3d> light_vector;
  if (light) light_vector = to_vector3(*light, "light");
  shadecut::Reconstruction result;
  {
    py::gil_scoped_release release;
    result = shadecut::reconstruct(image, light_vector, mask ? &*mask : nullptr, albedo, options);
  }
  py::dict stats;
  stats["seconds"] = result.stats.seconds;
  stats["energy"] = result.stats.energy_per_cycle;
  stats["cycles"] = result.stats.cycles;
  stats["iterations"] = result.stats.iterations;
  stats["light_estimated"] = result.stats.light_estimated;
  if (result.stats.light_estimated) stats["light_method"] = shadecut::to_string(options.light_estimator);
  stats["moves"] = result.stats.moves;
  stats["levels"] = result.stats.levels;
  stats["accepted_moves"] = result.stats.accepted_moves;
  stats["maxflow_seconds"] = result.stats.maxflow_seconds;
  stats["allowed_label_fraction"] = result.stats.allowed_label_fraction;
  stats["shadow_pixels"] = result.stats.shadow_pixels;
  py::dict out;
  out["normals"] = from_normals(result.normals);
  out["depth"] = from_image(result.depth);
  out["mask"] = from_mask(result.mask);
  out["albedo"] = result.albedo;
  out["light"] = std::vector<double>{result.light.x(), result.light.y(), result.light.z()};
  out["stats"] = stats;
  return out;
}

}  // namespace

PYBIND11_MODULE(_core, m) {
  m.doc() = "ShadeCut's compiled core; use the shadecut package, not this module.";

  static py::exception<shadecut::Cancelled> cancelled(m, "Cancelled");
  py::register_exception_translator([](std::exception_ptr error) {
    try {
      if (error) std::rethrow_exception(error);
    } catch (const shadecut::Cancelled& e) {
      cancelled(e.what());
    } catch (const shadecut::InvalidArgument& e) {
      PyErr_SetString(PyExc_ValueError, e.what());
    } catch (const shadecut::IoError& e) {
      PyErr_SetString(PyExc_OSError, e.what());
    }
  });

  m.def("reconstruct", &reconstruct, py::arg("image"), py::arg("light"), py::arg("mask"), py::arg("albedo"),
        py::arg("method"), py::arg("labels"), py::arg("data_weight"), py::arg("undefined_weight"),
        py::arg("integrator"), py::arg("maxflow"),
        py::arg("max_cycles"), py::arg("coarse_to_fine_band"), py::arg("tolerance"), py::arg("iterations"), py::arg("smoothness"), py::arg("light_method"), py::arg("min_curvature"), py::arg("refine"), py::arg("max_slope"), py::arg("fill_shadows"), py::arg("occluding_contour"), py::arg("threads"),
        py::arg("progress"));

  m.attr("METHODS") = py::tuple(py::cast(shadecut::method_names()));
  m.attr("LIGHT_METHODS") = py::make_tuple(shadecut::to_string(shadecut::LightEstimator::LeeRosenfeld),
                                           shadecut::to_string(shadecut::LightEstimator::ZhengChellappa));

  m.def("estimate_light", [](const FloatArray& image, const std::optional<BoolArray>& mask, const std::string& method) {
    const ImageF img = to_image(image, "image");
    const shadecut::LightEstimator estimator = shadecut::parse_light_estimator(method);
    const shadecut::LightEstimate estimate =
        shadecut::estimate_light(img, mask_or_all(to_mask(mask), img.rows(), img.cols()), estimator);
    return py::make_tuple(std::vector<double>{estimate.light.x(), estimate.light.y(), estimate.light.z()}, estimate.albedo);
  });

  m.def("estimate_albedo", [](const FloatArray& image, const std::optional<BoolArray>& mask) {
    const ImageF img = to_image(image, "image");
    return shadecut::estimate_albedo(img, mask_or_all(to_mask(mask), img.rows(), img.cols()));
  });

  m.def("normals_from_depth", [](const FloatArray& depth, const std::optional<BoolArray>& mask) {
    const ImageF z = to_image(depth, "depth map");
    return from_normals(shadecut::normals_from_depth(z, mask_or_all(to_mask(mask), z.rows(), z.cols())));
  });

  m.def("render_normals", [](const FloatArray& normals, const std::vector<double>& light, double albedo,
                             const std::optional<BoolArray>& mask) {
    const NormalMap n = to_normals(normals);
    return from_image(shadecut::render_lambertian(n, to_vector3(light, "light"), albedo, mask_or_all(to_mask(mask), n.rows, n.cols)));
  });

  m.def("integrate", [](const FloatArray& normals, const std::optional<BoolArray>& mask, const std::string& method,
                        double max_slope) {
    const NormalMap n = to_normals(normals);
    const Mask m_ = mask_or_all(to_mask(mask), n.rows, n.cols);
    const shadecut::Integrator integrator = shadecut::parse_integrator(method);
    ImageF depth;
    {
      py::gil_scoped_release release;
      depth = shadecut::integrate_normals(n, m_, integrator, max_slope);
    }
    return from_image(depth);
  });

  m.def("angular_error_map", [](const FloatArray& a, const FloatArray& b, const std::optional<BoolArray>& mask) {
    const NormalMap na = to_normals(a), nb = to_normals(b);
    return from_image(shadecut::angular_error_map(na, nb, mask_or_all(to_mask(mask), na.rows, na.cols)));
  });

  m.def("erode_mask", [](const BoolArray& mask, int pixels) { return from_mask(shadecut::erode_mask(*to_mask(mask), pixels)); });

  m.def("load_image", [](const std::string& path, const std::string& color_space) {
    const shadecut::LoadedImage loaded = shadecut::load_image(path, shadecut::parse_color_space(color_space));
    return py::make_tuple(from_image(loaded.intensity), from_mask(loaded.mask), loaded.has_alpha, loaded.color_space);
  });

  m.def("save_image", [](const std::string& path, const FloatArray& image, const std::optional<BoolArray>& alpha) {
    const std::optional<Mask> mask = to_mask(alpha);
    shadecut::save_image(path, to_image(image, "image"), mask ? &*mask : nullptr);
  });

  m.def("save_depth", [](const std::string& path, const FloatArray& depth, const std::optional<BoolArray>& mask) {
    const ImageF z = to_image(depth, "depth map");
    shadecut::save_depth(path, z, mask_or_all(to_mask(mask), z.rows(), z.cols()));
  });

  m.def("save_normals", [](const std::string& path, const FloatArray& normals, const std::optional<BoolArray>& mask) {
    const NormalMap n = to_normals(normals);
    shadecut::save_normals(path, n, mask_or_all(to_mask(mask), n.rows, n.cols));
  });

  m.def("save_mesh", [](const std::string& path, const FloatArray& depth, const std::optional<BoolArray>& mask) {
    const ImageF z = to_image(depth, "depth map");
    shadecut::save_mesh(path, z, mask_or_all(to_mask(mask), z.rows(), z.cols()));
  });
}
