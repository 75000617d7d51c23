// Binds reconstruct() with its option, result and stats types and their enums. The defaults live in
// ReconstructOptions alone: Python, the command-line tool and the add-on read them from here.
#include "bind_reconstruct.hpp"

#include "arrays.hpp"

#include <shadecut/support/errors.hpp>
#include <shadecut/pipeline/reconstruct.hpp>

#include <pybind11/functional.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <string>
#include <vector>

namespace py = pybind11;

namespace shadecut::python {

namespace {

// Binds an enum whose Python names are the library's own names (to_string), so that Method.graphcut
// and "graphcut" mean the same everywhere.
// Every value of an enum, named by its one table of names (value i is names[i]).
template <class Enum>
void bind_enum(py::module_& m, const char* name, const char* doc, const std::vector<std::string>& names) {
  py::enum_<Enum> bound(m, name, doc);
  for (std::size_t i = 0; i < names.size(); ++i) bound.value(names[i].c_str(), static_cast<Enum>(i));
}

// value cast to the option's type; pybind11's own message for a wrong type names neither the option
// nor the value.
template <class T>
T cast_option(const char* name, const py::object& value, const T& current) {
  try {
    return value.cast<T>();
  } catch (const py::cast_error&) {
  } catch (const py::reference_cast_error&) {
    // None for an enum: escaping the setter, pybind11 would take it for a call of the wrong overload
    // and say only "incompatible function arguments".
  }
  throw py::type_error("shadecut: option '" + std::string(name) + "' cannot be " + py::repr(value).cast<std::string>() +
                       " (" + py::type::of(value).attr("__name__").cast<std::string>() + "); it is now " +
                       py::repr(py::cast(current)).template cast<std::string>());
}

// An enum option, or an optional one (unset = None), that also takes its name as a string; the
// parser's error names the choices.
template <class Field, class Enum>
void enum_option(py::class_<ReconstructOptions>& options, std::vector<std::string>& names, const char* name,
                 Field ReconstructOptions::*field, Enum (*parse)(const std::string&)) {
  options.def_property(
      name, [field](const ReconstructOptions& o) { return o.*field; },
      [field, parse, name](ReconstructOptions& o, const py::object& value) {
        o.*field = py::isinstance<py::str>(value) ? Field(parse(value.cast<std::string>())) : cast_option(name, value, o.*field);
      });
  names.emplace_back(name);
}

template <class T>
void option(py::class_<ReconstructOptions>& options, std::vector<std::string>& names, const char* name,
            T ReconstructOptions::*field) {
  options.def_property(
      name, [field](const ReconstructOptions& o) { return o.*field; },
      [field, name](ReconstructOptions& o, const py::object& value) { o.*field = cast_option(name, value, o.*field); });
  names.emplace_back(name);
}

// A copy of `options` with the named fields set; an unknown name is a TypeError, as for a function.
ReconstructOptions replaced(const std::vector<std::string>& names, ReconstructOptions options,
                            const py::kwargs& overrides) {
  // Cast by move: casting the caller's own object would find and change it.
  py::object copy = py::cast(std::move(options));
  for (const auto& [key, value] : overrides) {
    const std::string name = key.cast<std::string>();
    if (std::find(names.begin(), names.end(), name) == names.end())
      throw py::type_error("shadecut: unknown option '" + name + "'; the options are " +
                           py::str(", ").attr("join")(names).cast<std::string>());
    copy.attr(key) = value;
  }
  return copy.cast<ReconstructOptions>();
}

py::array view(const py::object& owner, std::vector<py::ssize_t> shape, const float* data) {
  return py::array_t<float>(std::move(shape), data, owner);
}

}  // namespace

void bind_reconstruct(py::module_& m) {
  bind_enum<Method>(m, "Method", "Reconstruction methods (docs/method.md)", method_names());
  bind_enum<Integrator>(m, "Integrator", "Normal integrators", integrator_names());
  bind_enum<LightMethod>(m, "LightMethod", "Light estimators", light_method_names());
  bind_enum<SceneKind>(m, "SceneKind", "What the image shows", scene_kind_names());
  bind_enum<AlbedoMethod>(m, "AlbedoMethod", "Albedo estimators (one value, or per pixel: retinex)", albedo_method_names());
  bind_enum<CutOutOutcome>(m, "CutOutOutcome", "How a cut-out ended (pipeline/cut_out.hpp)", cut_out_outcome_names());

  py::class_<ReconstructOptions> options(m, "ReconstructOptions",
                                         "Every setting of reconstruct() with its default (native/include/shadecut/reconstruct.hpp).");
  std::vector<std::string> names;
  enum_option(options, names, "scene", &ReconstructOptions::scene, &parse_scene_kind);
  option(options, names, "cut_out", &ReconstructOptions::cut_out);
  enum_option(options, names, "method", &ReconstructOptions::method, &parse_method);
  option(options, names, "labels", &ReconstructOptions::labels);
  option(options, names, "data_weight", &ReconstructOptions::data_weight);
  option(options, names, "undefined_weight", &ReconstructOptions::undefined_weight);
  enum_option(options, names, "integrator", &ReconstructOptions::integrator, &parse_integrator);
  option(options, names, "max_cycles", &ReconstructOptions::max_cycles);
  option(options, names, "coarse_to_fine_band", &ReconstructOptions::coarse_to_fine_band);
  option(options, names, "coarse_to_fine_radius", &ReconstructOptions::coarse_to_fine_radius);
  option(options, names, "tolerance", &ReconstructOptions::tolerance);
  option(options, names, "iterations", &ReconstructOptions::iterations);
  option(options, names, "smoothness", &ReconstructOptions::smoothness);
  enum_option(options, names, "light_method", &ReconstructOptions::light_method, &parse_light_method);
  enum_option(options, names, "albedo_method", &ReconstructOptions::albedo_method, &parse_albedo_method);
  option(options, names, "retinex_chroma_edge", &ReconstructOptions::retinex_chroma_edge);
  option(options, names, "retinex_intensity_edge", &ReconstructOptions::retinex_intensity_edge);
  option(options, names, "retinex_rim", &ReconstructOptions::retinex_rim);
  option(options, names, "retinex_shadow", &ReconstructOptions::retinex_shadow);
  option(options, names, "retinex_passes", &ReconstructOptions::retinex_passes);
  option(options, names, "retinex_highlight", &ReconstructOptions::retinex_highlight);
  option(options, names, "highlight_threshold", &ReconstructOptions::highlight_threshold);
  option(options, names, "min_curvature", &ReconstructOptions::min_curvature);
  option(options, names, "refine", &ReconstructOptions::refine);
  option(options, names, "max_slope", &ReconstructOptions::max_slope);
  option(options, names, "fill_shadows", &ReconstructOptions::fill_shadows);
  option(options, names, "shadow_threshold", &ReconstructOptions::shadow_threshold);
  option(options, names, "occluding_contour", &ReconstructOptions::occluding_contour);
  option(options, names, "contour_weight", &ReconstructOptions::contour_weight);
  option(options, names, "viscosity_weight", &ReconstructOptions::viscosity_weight);
  option(options, names, "fit_shading", &ReconstructOptions::fit_shading);
  option(options, names, "fit_smoothness", &ReconstructOptions::fit_smoothness);
  option(options, names, "seamless", &ReconstructOptions::seamless);
  option(options, names, "detail_size", &ReconstructOptions::detail_size);
  option(options, names, "detail_scale_factor", &ReconstructOptions::detail_scale_factor);
  option(options, names, "paint_line_width", &ReconstructOptions::paint_line_width);
  option(options, names, "paint_line_contrast", &ReconstructOptions::paint_line_contrast);
  option(options, names, "threads", &ReconstructOptions::threads);
  m.attr("OPTION_NAMES") = py::tuple(py::cast(names));
  m.attr("MIN_LABELS") = kMinLabels;
  m.attr("MAX_THREADS") = kMaxThreads;
  options.def(py::init([names](const py::kwargs& overrides) { return replaced(names, ReconstructOptions{}, overrides); }),
              "The defaults, with the given fields set (unknown names raise TypeError).");
  options.def(
      "replace",
      [names](const ReconstructOptions& self, const py::kwargs& overrides) { return replaced(names, self, overrides); },
      "A copy with the given fields set.");
  options.def("light_method_used", &light_method_used,
              "The light estimator reconstruct() uses when given no light: light_method, or by scene when None.");
  options.def("highlight_threshold_used", &highlight_threshold_used,
              "The highlight threshold reconstruct() uses: highlight_threshold, or by albedo_method when None.");
  py::class_<MethodDefaults>(m, "MethodDefaults",
                             "The values a method uses for the options left None (tuned: docs/parameters.md); 0 = unused.")
      .def_readonly("min_curvature", &MethodDefaults::min_curvature)
      .def_readonly("undefined_weight", &MethodDefaults::undefined_weight)
      .def_readonly("tolerance", &MethodDefaults::tolerance)
      .def_readonly("iterations", &MethodDefaults::iterations)
      .def_readonly("smoothness", &MethodDefaults::smoothness)
      .def("__repr__", [](const MethodDefaults& d) {
        return "MethodDefaults(min_curvature=" + py::repr(py::float_(d.min_curvature)).cast<std::string>() +
               ", undefined_weight=" + py::repr(py::float_(d.undefined_weight)).cast<std::string>() +
               ", tolerance=" + py::repr(py::float_(d.tolerance)).cast<std::string>() +
               ", iterations=" + std::to_string(d.iterations) +
               ", smoothness=" + py::repr(py::float_(d.smoothness)).cast<std::string>() + ")";
      });
  m.def("method_defaults", [](const std::string& method) { return method_defaults(parse_method(method)); }, py::arg("method"),
        "The values `method` uses for the options left None (min_curvature, undefined_weight, tolerance, "
        "iterations, smoothness).");
  // An option left None shows the value its method uses: `undefined_weight=None (graphcut: 0.5)`.
  options.def("__repr__", [names](const py::object& self) {
    const py::object per_method = py::cast(method_defaults(self.cast<const ReconstructOptions&>().method));
    const std::string method = self.attr("method").attr("name").cast<std::string>();
    std::string text = "ReconstructOptions(";
    for (std::size_t i = 0; i < names.size(); ++i) {
      const py::object value = self.attr(names[i].c_str());
      const bool is_enum = py::hasattr(value, "name") && py::hasattr(value, "value");
      text += std::string(i ? ", " : "") + names[i] + "=" +
              (is_enum ? "'" + value.attr("name").cast<std::string>() + "'" : py::repr(value).cast<std::string>());
      if (value.is_none() && py::hasattr(per_method, names[i].c_str()))
        text += " (" + method + ": " + py::repr(per_method.attr(names[i].c_str())).cast<std::string>() + ")";
    }
    return text + ")";
  });

  py::class_<ReconstructStats>(m, "ReconstructStats", "What a reconstruct() call did and how long it took.")
      .def_readonly("seconds", &ReconstructStats::seconds, "seconds per stage run, and 'total'")
      .def_readonly("energy_per_cycle", &ReconstructStats::energy_per_cycle, "initial energy, then after every cycle")
      .def_readonly("cycles", &ReconstructStats::cycles)
      .def_readonly("iterations", &ReconstructStats::iterations, "cycles, brooks_horn / tsai_shah sweeps, or upwind rounds")
      .def_readonly("light_estimated", &ReconstructStats::light_estimated)
      .def_readonly("light_uncertainty", &ReconstructStats::light_uncertainty,
                    "degrees: how far the estimated light may be off (light_method contour: its fit's misfit); NaN when "
                    "the light was given or its estimator does not know it")
      .def_readonly("moves", &ReconstructStats::moves)
      .def_readonly("accepted_moves", &ReconstructStats::accepted_moves)
      .def_readonly("levels", &ReconstructStats::levels, "resolutions solved (coarse to fine)")
      .def_readonly("maxflow_seconds", &ReconstructStats::maxflow_seconds)
      .def_readonly("allowed_label_fraction", &ReconstructStats::allowed_label_fraction)
      .def_readonly("shadow_pixels", &ReconstructStats::shadow_pixels)
      .def_readonly("detail_size", &ReconstructStats::detail_size)
      .def_readonly("shading_residual_before", &ReconstructStats::shading_residual_before,
                    "fit_shading: sum of squared brightness residuals of the integrated depth")
      .def_readonly("shading_residual_after", &ReconstructStats::shading_residual_after,
                    "fit_shading: the same after the fit (never larger)")
      .def_readonly("fit_steps", &ReconstructStats::fit_steps)
      .def_readonly("paper_residual", &ReconstructStats::paper_residual,
                    "viscosity_weight: mean squared brightness residual of the paper's labelling's depth")
      .def_readonly("pulled_residual", &ReconstructStats::pulled_residual, "the same for the labelling pulled toward upwind's")
      .def_readonly("pulled_kept", &ReconstructStats::pulled_kept, "whether the pulled labelling was kept")
      .def_readonly("orientation_energy", &ReconstructStats::orientation_energy,
                    "graphcut, graphcut_two: the energy of the coarsest level's labelling (0 for the other methods)")
      .def_readonly("inverted_energy", &ReconstructStats::inverted_energy,
                    "the same for its inversion (every label turned by pi)")
      .def_readonly("orientation_residual", &ReconstructStats::orientation_residual,
                    "mean squared brightness residual of the returned depth")
      .def_readonly("inverted_residual", &ReconstructStats::inverted_residual,
                    "the same for its inversion (every normal turned by pi about the light, integrated)")
      .def_readonly("orientation_ambiguous", &ReconstructStats::orientation_ambiguous,
                    "whether the image explains the inversion nearly as well (inverted_residual < "
                    "AMBIGUOUS_RESIDUAL_RATIO x orientation_residual): the priors chose the orientation")
      .def_readonly("cut_out", &ReconstructStats::cut_out,
                    "cut_out: how the object's cut-out ended (not_tried, found, busy_border, no_object, low_contrast); "
                    "the mask is the cut-out's only when found")
      .def_readonly("cut_out_contrast", &ReconstructStats::cut_out_contrast,
                    "the share of the cut-out's outline that differs from the background")
      .def_readonly("cut_out_message", &ReconstructStats::cut_out_message, "the cut-out's sentence for the user");

  // The arrays are views of the result's own buffers, kept alive by it: no copy.
  py::class_<Reconstruction>(m, "Reconstruction", "The result of reconstruct().")
      .def_property_readonly("normals", [](const py::object& self) {
        const NormalMap& n = self.cast<const Reconstruction&>().normals;
        return view(self, {n.rows, n.cols, 3}, n.xyz.data());
      }, "(H, W, 3) float32 camera-frame unit normals, 0 outside the mask")
      .def_property_readonly("depth", [](const py::object& self) {
        const ImageF& z = self.cast<const Reconstruction&>().depth;
        return view(self, {z.rows(), z.cols()}, z.data());
      }, "(H, W) float32, pixel units, larger = closer; each mask component's minimum is 0")
      .def_property_readonly("mask", [](const py::object& self) {
        const Mask& mask = self.cast<const Reconstruction&>().mask;
        return py::array_t<bool>({mask.rows(), mask.cols()}, mask.data(), self);
      }, "(H, W) bool, the pixels reconstructed")
      .def_readonly("albedo", &Reconstruction::albedo, "the albedo used (given or estimated; of the brightest paint with retinex)")
      .def_property_readonly("albedo_map", [](const py::object& self) {
        const ImageF& a = self.cast<const Reconstruction&>().albedo_map;
        return view(self, {a.rows(), a.cols()}, a.data());
      }, "(H, W) float32 albedo per pixel (the albedo everywhere unless retinex), 0 outside the mask")
      .def_property_readonly("albedo_colour", [](const Reconstruction& r) { return from_colour(r.albedo_colour); },
                             "(H, W, 3) float32 de-lit colour of a colour image (albedo_map times its chromaticity); None for grey")
      .def_property_readonly("light", [](const Reconstruction& r) {
        return py::array_t<double>(3, r.light.data());
      }, "(3,) unit vector toward the light used, camera frame")
      .def_readonly("stats", &Reconstruction::stats);

  m.attr("AMBIGUOUS_RESIDUAL_RATIO") = kAmbiguousResidualRatio;

  m.def(
      "reconstruct",
      [](const FloatArray& image_array, const std::optional<std::vector<double>>& light,
         const std::optional<BoolArray>& mask_array, std::optional<double> albedo, ReconstructOptions options,
         const std::optional<py::function>& progress) {
        const std::optional<Mask> mask = to_mask(mask_array);
        if (progress) {
          options.progress = [callback = *progress](double fraction, const std::string& stage) {
            py::gil_scoped_acquire gil;
            const py::object answer = callback(fraction, stage);
            return answer.is_none() || PyObject_IsTrue(answer.ptr()) == 1;
          };
        } else {
          // Python runs its Ctrl+C handler only between bytecodes, never during this call: without a
          // callback of the caller's, whose Python code would run it, the reports ask for it here.
          options.progress = [](double, const std::string&) {
            py::gil_scoped_acquire gil;
            if (PyErr_CheckSignals() != 0) throw py::error_already_set();
            return true;
          };
        }
        std::optional<Eigen::Vector3d> light_vector;
        if (light) light_vector = to_vector3(*light, "light");
        require_grey_or_colour(image_array);
        if (image_array.ndim() == 3) {
          const ColourImage colour = to_colour(image_array, "image");
          py::gil_scoped_release release;
          return reconstruct(colour, light_vector, mask ? &*mask : nullptr, albedo, options);
        }
        const ImageF image = to_image(image_array, "image");
        py::gil_scoped_release release;
        return reconstruct(image, light_vector, mask ? &*mask : nullptr, albedo, options);
      },
      py::arg("image"), py::arg("light"), py::arg("mask"), py::arg("albedo"), py::arg("options"), py::arg("progress"));
}

}  // namespace shadecut::python
