#include "python_errors.hpp"

#include <shadecut/support/errors.hpp>

#include <pybind11/pybind11.h>

namespace shadecut::python {

void translate_core_error(std::exception_ptr error) {
  try {
    if (error) std::rethrow_exception(error);
  } catch (const InvalidArgument& e) {
    PyErr_SetString(PyExc_ValueError, e.what());
  } catch (const IoError& e) {
    PyErr_SetString(PyExc_OSError, e.what());
  }
}

}  // namespace shadecut::python
