// The Python exception for each of the core's, shared by the compiled modules.
#pragma once

#include <exception>

namespace shadecut::python {

/// A pybind11 exception translator: InvalidArgument becomes ValueError and IoError OSError; any other
/// exception is rethrown for the next translator.
void translate_core_error(std::exception_ptr error);

}  // namespace shadecut::python
