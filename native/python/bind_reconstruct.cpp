// Binds reconstruct() with its option, result and stats types and their enums. The defaults live in
// ReconstructOptions alone: Python, the command-line tool and the add-on read them from here.
#include "bind_reconstruct.hpp"

#include "arrays.hpp"
#include "bind_options.hpp"

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

py::array view(const py::object& owner, std::vector<py::ssize_t> shape, const float* data) {
  return py::array_t<float>(std::move(shape), data, owner);
}

void bind_stats(py::module_& m);
void bind_result(py::module_& m);
void bind_reconstruct_function(py::module_& m);

}  // namespace

// A call's progress: the caller's callback, or one that lets Ctrl+C through.
ProgressCallback python_progress(const std::optional<py::function>& progress) {
  if (progress) {
    return [callback = *progress](double fraction, const std::string& stage) {
      py::gil_scoped_acquire gil;
      const py::object answer = callback(fraction, stage);
      if (answer.is_none()) return true;
      const int truth = PyObject_IsTrue(answer.ptr());
      if (truth < 0) {  // an answer with no truth value (an array) is a mistake, not a cancel
        PyErr_Clear();
        throw py::type_error("shadecut: the progress callback returned " + py::repr(answer).cast<std::string>() +
                             "; return None or True to go on, False to cancel");
      }
      return truth == 1;
    };
  }
  // Python runs its Ctrl+C handler only between bytecodes, never during this call: without a
  // callback of the caller's, whose Python code would run it, the reports ask for it here.
  return [](double, const std::string&) {
    py::gil_scoped_acquire gil;
    if (PyErr_CheckSignals() != 0) throw py::error_already_set();
    return true;
  };
}

void bind_reconstruct(py::module_& m) {
  bind_enum<Method>(m, "Method", "Reconstruction methods (docs/method.md)", method_names());
  bind_enum<Integrator>(m, "Integrator", "Normal integrators", integrator_names());
  bind_enum<LightMethod>(m, "LightMethod", "Light estimators", light_method_names());
  bind_enum<SceneKind>(m, "SceneKind", "What the image shows", scene_kind_names());
  bind_enum<AlbedoMethod>(m, "AlbedoMethod", "Albedo estimators (one value, or per pixel: retinex)", albedo_method_names());
  bind_enum<CutOutOutcome>(m, "CutOutOutcome", "How a cut-out ended (pipeline/cut_out.hpp)", cut_out_outcome_names());

  bind_options(m);
  bind_stats(m);
  bind_result(m);
  bind_reconstruct_function(m);
}

namespace {

void bind_stats(py::module_& m) {
  py::class_<ReconstructStats>(m, "ReconstructStats", "What a reconstruct() call did and how long it took.")
      .def_readonly("seconds", &ReconstructStats::seconds, "seconds per stage run, and 'total'")
      .def_readonly("energy_per_cycle", &ReconstructStats::energy_per_cycle, "initial energy, then after every cycle")
      .def_readonly("cycles", &ReconstructStats::cycles)
      .def_readonly("iterations", &ReconstructStats::iterations, "cycles, brooks_horn / tsai_shah sweeps, upwind rounds or pentland solves")
      .def_readonly("light_estimated", &ReconstructStats::light_estimated)
      .def_readonly("light_uncertainty", &ReconstructStats::light_uncertainty,
                    "degrees: how far the estimated light may be off (light_method contour: its fit's misfit); NaN when "
                    "the light was given or its estimator does not know it")
      .def_readonly("lights_turned_by_outline", &ReconstructStats::lights_turned_by_outline,
                    "several photographs, lights estimated: the object's outline turned the hint's lights by half a circle")
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
      .def_readonly("cut_out_message", &ReconstructStats::cut_out_message, "the cut-out's sentence for the user")
      .def_readonly("brighter_than_albedo", &ReconstructStats::brighter_than_albedo,
                    "share of the mask brighter than the albedo used (read as facing the light)")
      .def_readonly("albedo_message", &ReconstructStats::albedo_message,
                    "a sentence for the user when a given albedo lies below much of the image; empty otherwise")
      .def_readonly("photographs", &ReconstructStats::photographs, "how many photographs the call read")
      .def_readonly("pair_pixels", &ReconstructStats::pair_pixels,
                    "several photographs: masked pixels where two were usable (the graph cut chose between two normals)")
      .def_readonly("four_fit_pixels", &ReconstructStats::four_fit_pixels,
                    "several photographs: masked pixels fitted from three of four, the graph cut choosing which to leave out")
      .def_readonly("single_pixels", &ReconstructStats::single_pixels,
                    "several photographs: masked pixels where one was usable (filled from their neighbours)")
      .def_readonly("dark_pixels", &ReconstructStats::dark_pixels,
                    "several photographs: masked pixels where none was usable (filled from their neighbours)");
}

void bind_result(py::module_& m) {
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
      .def_property_readonly("lights", [](const Reconstruction& r) {
        py::array_t<double> lights({py::ssize_t(r.lights.size()), py::ssize_t(3)});
        for (std::size_t k = 0; k < r.lights.size(); ++k)
          for (int axis = 0; axis < 3; ++axis) lights.mutable_at(py::ssize_t(k), axis) = r.lights[k][axis];
        return lights;
      }, "(K, 3) the unit light of each photograph, as used")
      .def_property_readonly("residual", [](const py::object& self) -> py::object {
        const ImageF& residual = self.cast<const Reconstruction&>().residual;
        if (residual.size() == 0) return py::none();
        return view(self, {residual.rows(), residual.cols()}, residual.data());
      }, "several photographs: (H, W) float32 RMS misfit of the photographs to the result; None for one")
      .def_readonly("stats", &Reconstruction::stats);

  m.attr("AMBIGUOUS_RESIDUAL_RATIO") = kAmbiguousResidualRatio;
}

// One photograph of a Python call: grey (H, W) or colour (H, W, 3), with its light or none.
Observation to_observation(const FloatArray& image, const std::optional<std::vector<double>>& light, const char* name) {
  std::optional<Eigen::Vector3d> light_vector;
  if (light) light_vector = to_vector3(*light, "light");
  require_grey_or_colour(image);
  return image.ndim() == 3 ? colour_observation(to_colour(image, name), light_vector)
                           : grey_observation(to_image(image, name), light_vector);
}

void bind_reconstruct_function(py::module_& m) {
  m.def(
      "reconstruct",
      [](const std::vector<FloatArray>& images, const std::optional<std::vector<std::vector<double>>>& lights,
         const std::optional<BoolArray>& mask_array, std::optional<double> albedo, ReconstructOptions options,
         const std::optional<py::function>& progress) {
        if (lights && lights->size() != images.size())
          throw InvalidArgument("shadecut: " + std::to_string(images.size()) + " photographs but " +
                                std::to_string(lights->size()) + " lights; give one light per photograph");
        const std::optional<Mask> mask = to_mask(mask_array);
        options.progress = python_progress(progress);
        std::vector<Observation> photographs;
        for (std::size_t k = 0; k < images.size(); ++k)
          photographs.push_back(to_observation(images[k], lights ? std::optional((*lights)[k]) : std::nullopt,
                                               images.size() > 1 ? "photograph" : "image"));
        py::gil_scoped_release release;
        return reconstruct(photographs, mask ? &*mask : nullptr, albedo, options);
      },
      py::arg("images"), py::arg("lights"), py::arg("mask"), py::arg("albedo"), py::arg("options"), py::arg("progress"));
}

}  // namespace

}  // namespace shadecut::python
