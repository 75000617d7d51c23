#pragma once

#include <shadecut/support/progress.hpp>

#include <pybind11/functional.h>
#include <pybind11/pybind11.h>

#include <optional>

namespace shadecut::python {

/// Adds reconstruct(), ReconstructOptions, Reconstruction, ReconstructStats and the enums Method,
/// Integrator and LightMethod to the module.
void bind_reconstruct(pybind11::module_& m);

/// A long call's progress: the caller's callback (its answer False cancels; None or True goes on), or
/// without one a callback that lets Ctrl+C through. Called with the GIL released.
ProgressCallback python_progress(const std::optional<pybind11::function>& progress);

}  // namespace shadecut::python
