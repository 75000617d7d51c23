#pragma once

#include <pybind11/pybind11.h>

namespace shadecut::python {

/// Adds ReconstructOptions (a property per field of the option table, its setters as strict as the
/// field's type), OPTION_NAMES, option_fields(), MethodDefaults and method_defaults() to the module.
void bind_options(pybind11::module_& m);

}  // namespace shadecut::python
