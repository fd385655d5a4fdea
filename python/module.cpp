// The compiled part of the Python module `aggkit` (python/aggkit/ is the API users call). Bad input
// raises ValueError with the message the command line prints; solver failures raise RuntimeError.
#include <pybind11/pybind11.h>

#include "analysis/input_error.hpp"

namespace py = pybind11;

void bind_runs(py::module_& m);      // run_binding.cpp
void bind_analysis(py::module_& m);  // analysis_binding.cpp

PYBIND11_MODULE(_aggkit, m) {
  m.doc() = "aggkit's compiled core; use the aggkit package";
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const aggkit::InputError& e) {
      PyErr_SetString(PyExc_ValueError, e.what());
    }
  });
  bind_runs(m);
  bind_analysis(m);
}
