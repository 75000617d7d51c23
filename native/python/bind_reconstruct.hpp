#pragma once

#include <pybind11/pybind11.h>

namespace shadecut::python {

/// Adds reconstruct(), ReconstructOptions, Reconstruction, ReconstructStats and the enums Method,
/// Integrator and LightMethod to the module.
void bind_reconstruct(pybind11::module_& m);

}  // namespace shadecut::python
